"""The JSON Schema of a catalogue family's file (``schema.json`` beside the files;
:mod:`rotorlib.beyond.catalogue` reads them): every field a researcher reads without
rotorlib, with its type. The tests validate every stored file against it."""

from __future__ import annotations

from typing import Any

__all__ = ["SCHEMA"]

_num = {"type": "number"}
_str = {"type": "string"}
_member = {
    "type": "object",
    "required": [
        "kind",
        "E",
        "E_str",
        "period",
        "period_str",
        "state0",
        "state0_str",
        "trace",
        "trace_str",
        "multipliers",
        "stability",
        "action",
        "maslov",
        "maslov_reason",
        "u",
        "pieces",
        "closure",
        "digits",
    ],
    "properties": {
        "kind": {"enum": ["path", "IS", "PD", "fold", "touch", "seed"]},
        "E": _num,
        "E_str": _str,
        "period": {"type": "number", "exclusiveMinimum": 0},
        "period_str": _str,
        "state0": {"type": "array", "items": _num, "minItems": 4, "maxItems": 4},
        "state0_str": {"type": "array", "items": _str, "minItems": 4, "maxItems": 4},
        "trace": _num,
        "trace_str": _str,
        "multipliers": {
            "type": "array",
            "minItems": 4,
            "maxItems": 4,
            "items": {"type": "array", "items": _num, "minItems": 2, "maxItems": 2},
        },
        "stability": {"enum": ["stable", "unstable"]},
        "action": _num,
        "maslov": {"type": ["integer", "null"]},
        "maslov_reason": {"type": ["string", "null"]},
        "u": _num,
        "pieces": {"type": "array", "items": {"type": "integer", "minimum": 0}},
        "closure": {"type": "number", "minimum": 0},
        "digits": {"type": "integer", "minimum": 16},
    },
}
_link = {
    "type": "object",
    "required": ["id", "kind", "E"],
    "properties": {"id": _str, "kind": {"enum": ["IS", "PD"]}, "E": _num},
}
_pair = {"type": "array", "items": _num, "minItems": 2, "maxItems": 2}

#: The JSON Schema (draft 2020-12) of a family file ``F<nnn>.json``.
SCHEMA: dict[str, Any] = {
    "$schema": "https://json-schema.org/draft/2020-12/schema",
    "title": "rotorlib catalogue: one family of symmetric periodic orbits of the 3-rotor",
    "type": "object",
    "required": [
        "id",
        "name",
        "names",
        "t_max",
        "window",
        "symmetry",
        "E_range",
        "period_range",
        "ends",
        "special_points",
        "stable_windows",
        "parents",
        "daughters",
        "fold_twins",
        "census_orbits",
        "members",
        "interpolation",
        "branch",
    ],
    "properties": {
        "id": {"type": "string", "pattern": "^F[0-9]{3}$"},
        "name": {"type": ["string", "null"]},
        "names": {"type": "array", "items": _str},
        "t_max": _num,
        "window": _pair,
        "symmetry": {
            "type": "object",
            "required": ["fixed_sets", "choreography", "rotating", "winding"],
            "properties": {
                "fixed_sets": {
                    "type": "array",
                    "items": {"type": "array", "items": _str},
                },
                "choreography": {"type": "boolean"},
                "rotating": {"type": "boolean"},
                "winding": {"type": "array", "items": _num},
            },
        },
        "E_range": _pair,
        "period_range": _pair,
        "ends": {
            "type": "array",
            "minItems": 2,
            "maxItems": 2,
            "items": {
                "type": "object",
                "required": ["side", "E", "period", "kind", "stop", "reason"],
                "properties": {"side": {"enum": ["backward", "forward"]}},
            },
        },
        "special_points": {
            "type": "array",
            "items": {
                "type": "object",
                "required": ["kind", "E", "period", "trace", "index"],
                "properties": {
                    "kind": {"enum": ["IS", "PD", "fold", "touch", "marginal"]}
                },
            },
        },
        "stable_windows": {"type": "array", "items": _pair},
        "parents": {"type": "array", "items": _link},
        # the records of the same family's other branches, across a fold they share
        "fold_twins": {
            "type": "array",
            "items": {
                "type": "object",
                "required": ["id", "E"],
                "properties": {"id": _str, "E": _num},
            },
        },
        "daughters": {"type": "array", "items": _link},
        # empty for a record found off the censuses (past a zigzag end, or by branch
        # switching) whose orbits no census met
        "census_orbits": {"type": "array"},
        "members": {"type": "array", "items": _member, "minItems": 1},
        "interpolation": {
            "type": "object",
            "required": ["pieces", "degree", "tolerance", "max_error", "path_accuracy"],
            "properties": {
                "pieces": {
                    "type": "array",
                    "minItems": 1,
                    "items": {
                        "type": "object",
                        "required": ["param", "path", "members"],
                        "properties": {
                            "param": {"enum": ["E", "u"]},
                            "path": {"type": "array", "items": {"type": "integer"}},
                            "members": {
                                "type": "array",
                                "minItems": 1,
                                "items": {"type": "integer", "minimum": 0},
                            },
                        },
                    },
                },
                "degree": {"type": "integer", "minimum": 1},
                "tolerance": _num,
                "max_error": _num,
                "left_out_error": _num,
                "densified": {"type": "integer", "minimum": 0},
                "path_accuracy": {
                    "type": "object",
                    "required": ["period", "trace", "above_tolerance"],
                    "properties": {
                        "period": _num,
                        "trace": _num,
                        "above_tolerance": {
                            "type": "array",
                            "items": {"type": "array", "items": _num, "minItems": 3},
                        },
                    },
                },
            },
        },
        "branch": {
            "type": "object",
            "required": ["factor", "problem", "path"],
            "properties": {
                "path": {
                    "type": "array",
                    "minItems": 2,
                    "items": {"type": "array", "items": _num, "minItems": 8},
                }
            },
        },
    },
}
