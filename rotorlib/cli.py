"""Command line: ``python -m rotorlib <command> ...``.

Each command lives in :mod:`rotorlib.commands` as a module with
``register(subparsers)``, which adds its parser and sets ``func``. Errors in
the input (``ValueError``) and in the arguments print one line on stderr and
exit with status 2; there is never a traceback for bad input. A command that needs
heyoka where it is not installed is refused the same way, naming the extra
``rotorlib[fast]`` (:class:`rotorlib.core.precision.HeyokaMissing`).
"""

from __future__ import annotations

import argparse
import importlib
import json
import re
import sys
from collections.abc import Sequence
from typing import Any

from .core.precision import DIGITS_RANGE, HeyokaMissing, check_digits

#: Command modules, in help order. A module missing from the package is skipped.
COMMANDS = (
    "trace",
    "bifurcations",
    "orbit",
    "family",
    "atlas",
    "spectrum",
    "catalogue",
)


#: A negative number in any notation (-5, -1.5, -.5, -1e6, -1E+3, -inf, -nan). argparse's own matcher
#: knows only -123 and -1.5 and takes "-1e6" for an option ("expected at least one argument").
#:
#: :meta hide-value:
NEGATIVE_NUMBER = re.compile(
    r"^-(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$|^-(inf|infinity|nan)$", re.IGNORECASE
)


class _OneLineParser(argparse.ArgumentParser):
    """argparse that reports usage errors on a single line and reads negative numbers in any notation."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        # argparse consults this matcher to decide whether "-..." is a value or an option
        # (no option of ours looks like a number, so every match is a value)
        self._negative_number_matcher = NEGATIVE_NUMBER

    def error(self, message):
        raise ValueError(f"{self.prog}: {message}")


def build_parser(prog: str = "python -m rotorlib") -> argparse.ArgumentParser:
    from . import __version__

    parser = _OneLineParser(
        prog=prog,
        description="The 3-rotor bifurcation cascade (Krishnaswami & Yadav 2023), recomputed.",
    )
    parser.add_argument(
        "--version", action="version", version=f"rotorlib {__version__}"
    )
    sub = parser.add_subparsers(
        dest="command", parser_class=_OneLineParser, metavar="COMMAND", required=True
    )
    for name in COMMANDS:
        importlib.import_module(f"rotorlib.commands.{name}").register(sub)
    return parser


class _Digits(argparse.Action):
    """Stores ``--digits`` once :func:`rotorlib.core.precision.check_digits` accepts it (a
    ``ValueError`` otherwise: the one range and message of every command)."""

    def __call__(self, parser, namespace, values, option_string=None):
        setattr(namespace, self.dest, check_digits(values, "--digits"))


def add_digits_argument(p: argparse.ArgumentParser, detail: str) -> None:
    """``--digits D``, the one precision option of every command: an integer in
    :data:`rotorlib.core.precision.DIGITS_RANGE` (default float64), checked as it is read;
    ``detail`` says what the command does with it.

    Examples
    --------
    >>> import argparse
    >>> from rotorlib.cli import add_digits_argument
    >>> p = argparse.ArgumentParser()
    >>> add_digits_argument(p, "> 15 uses real128")
    >>> p.parse_args(["--digits", "30"]).digits
    30
    >>> p.parse_args(["--digits", "0"])
    Traceback (most recent call last):
    ...
    ValueError: --digits must be an integer from 1 to 1000, got 0
    """
    lo, hi = DIGITS_RANGE
    p.add_argument(
        "--digits",
        type=int,
        default=None,
        action=_Digits,
        help=f"significant digits, {lo} to {hi} (default: float64); {detail}",
    )


def add_executor_arguments(p: argparse.ArgumentParser) -> None:
    """``--workers N`` or ``--scheduler ADDRESS`` (one of them): where a scanning command
    runs, for :func:`rotorlib.core.parallel.executor_for`."""
    g = p.add_mutually_exclusive_group()
    g.add_argument("--workers", type=int, default=None, help="local worker processes")
    g.add_argument(
        "--scheduler",
        default=None,
        metavar="ADDRESS",
        help="tcp:// address of a running Dask scheduler",
    )


def emit(
    records: Sequence[Any], as_json: bool, columns: Sequence[str], one: bool = True
) -> None:
    """Print records as JSON (a list when several, one object when one and ``one``) or
    as a table (a column shows ``<column>_str``, every digit, where a record has it)."""
    if as_json:
        out = records[0] if one and len(records) == 1 else records
        # nan and inf (JSON has no such numbers) become null; the records say why in a *_note
        out = json.loads(json.dumps(out), parse_constant=lambda _: None)
        print(json.dumps(out, indent=2, allow_nan=False))
        return
    rows = [[str(r.get(c + "_str", r.get(c, ""))) for c in columns] for r in records]
    widths = [  # no rows: the header alone
        max([len(c), *(len(row[i]) for row in rows)]) for i, c in enumerate(columns)
    ]
    print("  ".join(c.ljust(w) for c, w in zip(columns, widths)))
    for row in rows:
        print("  ".join(v.ljust(w) for v, w in zip(row, widths)))


def console() -> int:
    """The installed ``rotorlib`` command (same as ``python -m rotorlib``)."""
    return main(prog="rotorlib")


def main(argv: list[str] | None = None, prog: str = "python -m rotorlib") -> int:
    """Entry point; returns the exit status."""
    try:
        args = build_parser(prog).parse_args(argv)
        return args.func(args) or 0
    except ValueError as exc:
        msg = str(exc).splitlines()[0] if str(exc) else exc.__class__.__name__
        print(f"rotorlib: error: {msg}", file=sys.stderr)
        return 2
    except HeyokaMissing as exc:  # an optional dependency: a refusal naming the extra
        print(f"rotorlib: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("rotorlib: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # output piped into head & co: stop quietly
        sys.stderr.close()
        return 141
    except Exception as exc:  # a bug, not bad input: still one line, never a traceback
        msg = str(exc).splitlines()[0] if str(exc) else ""
        print(
            f"rotorlib: internal error: {exc.__class__.__name__}: {msg} (please report)",
            file=sys.stderr,
        )
        return 1
