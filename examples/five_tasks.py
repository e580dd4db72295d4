"""Five everyday tasks through rotorlib's front door, each checked independently.

Part 1 uses only ``rotorlib.orbit``, ``family``, ``transition`` and ``census`` and prints
each result's ``to_dict()`` (the JSON of the command line), abridged. Part 2 checks the
numbers against computations that share no code with rotorlib: Hamilton's equations and
their variational equations are derived here by heyoka's symbolic differentiation from

    H = p1^2/4 + 3 p2^2/4 + 3 - cos(2 a1) - cos(a2 - a1) - cos(a1 + a2),

integrated by heyoka in real128 or at 256 bits, the pendulum's period comes from
mpmath's K(m), and the transition energy is a root of tr M(E) = 4 found by mpmath.

    python examples/five_tasks.py          # ~1 min; exit status 1 if a check fails
"""

from __future__ import annotations

import json
import sys

import heyoka as hy
import mpmath as mp

import rotorlib

# ------------------------------------------------------------------ part 1: the front door
o39 = rotorlib.orbit("pendulum", 3.9)  # 1. tr M of the librational pendulum
o39_30 = rotorlib.orbit("pendulum", "3.9", digits=30)
o39_40 = rotorlib.orbit("pendulum", "3.9", digits=40)
newborn = rotorlib.orbit(
    "IS^l_2", "3.999", digits=30
)  # 2. a newborn orbit, multipliers
branch = rotorlib.family("IS^l_1", (4.0, 4.2))  # 3. period against E over a range
atlas = rotorlib.census(4.3, 8.0)  # 4. the stable orbits of a census
tr = rotorlib.transition("IS^l_2", digits=25)  # 5. a transition energy to 25 digits

KEYS = (
    "label",
    "E",
    "period",
    "period_str",
    "trace",
    "trace_str",
    "stability",
    "digits",
)
for name, res in [("1", o39), ("1 (40 digits)", o39_40), ("2", newborn), ("5", tr)]:
    d = res.to_dict()
    print(f"task {name}:", json.dumps({k: d[k] for k in KEYS if k in d}))
print(
    "task 2 multipliers:",
    [complex(round(z.real, 9), round(z.imag, 9)) for z in newborn.multipliers],
)
print(
    f"task 3: {len(branch.members)} members of IS^l_1 with 4.0 <= E <= 4.2; stop: {branch.reason}"
)
for m in branch.members[:: max(1, len(branch.members) // 4)]:
    print(
        f"    E = {float(m.E):.6f}  T = {float(m.period):.9f}  tr M = {float(m.trace):.6f}"
    )
stable = [o for o in atlas.orbits if o.stability == "stable"]
print(
    f"task 4: {len(atlas.orbits)} orbits with T <= 8 at E = 4.3, {len(stable)} stable:",
    ", ".join(f"{o.label} (T = {o.period:.6f})" for o in stable),
)

# ------------------------------------------------------------------ part 2: independent checks
a1, a2, p1, p2 = hy.make_vars("a1", "a2", "p1", "p2")
H = p1**2 / 4 + 3 * p2**2 / 4 + 3 - hy.cos(2 * a1) - hy.cos(a2 - a1) - hy.cos(a1 + a2)
SYS = [
    (a1, hy.diff(H, p1)),
    (a2, hy.diff(H, p2)),
    (p1, -hy.diff(H, a1)),
    (p2, -hy.diff(H, a2)),
]
VSYS = hy.var_ode_sys(SYS, hy.var_args.vars, order=1)
_TA: dict = {}


def flow(state, period, bits):
    """x(T) and tr M by heyoka at ``bits`` (113: real128), from decimal strings."""
    if bits not in _TA:
        kw = (
            {"fp_type": hy.real128}
            if bits == 113
            else {"fp_type": hy.real, "prec": bits}
        )
        zero = hy.real128("0") if bits == 113 else hy.real("0", bits)
        _TA[bits] = hy.taylor_adaptive(VSYS, [zero] * 4, compact_mode=True, **kw)
    ta = _TA[bits]
    num = (
        (lambda s: hy.real128(str(s)))
        if bits == 113
        else (lambda s: hy.real(str(s), bits))
    )
    ta.time = num(0)
    ta.state[:] = [num(s) for s in state] + [
        num(1 if i % 5 == 0 else 0) for i in range(16)
    ]
    ta.propagate_until(num(period))
    with mp.workdps(int(bits / 3.3) + 5):
        xs = [mp.mpf(str(v)) for v in ta.state]
        return xs[:4], sum(xs[4 + 5 * i] for i in range(4))


def pendulum_reference(E, bits=256):
    with mp.workprec(bits + 20):
        E = mp.mpf(E)
        T = 4 * mp.ellipk(E / 4) / mp.sqrt(3)
        return T, flow(
            [0, 0, 0, mp.nstr(mp.sqrt(4 * E / 3), 80)], mp.nstr(T, 80), bits
        )[1]


failures = []


def check(what, err, tol):
    err = mp.mpf(err)
    ok = err < tol
    if not ok:
        failures.append(what)
    rel = "<" if ok else ">="
    print(f"  {'PASS' if ok else 'FAIL'}  {what}: {mp.nstr(err, 2)} {rel} {tol:g}")


print("\nindependent checks")
with mp.workdps(60):
    T_ref, tr_ref = pendulum_reference("3.9")
    check(
        "1. tr M at 30 digits vs heyoka 256 bits",
        abs(mp.mpf(o39_30.trace_str) - tr_ref),
        1e-24,
    )
    check(
        "1. tr M at 40 digits vs heyoka 256 bits",
        abs(mp.mpf(o39_40.trace_str) - tr_ref),
        1e-34,
    )
    check("1. float64 tr M", abs(o39.trace - tr_ref), 1e-12)
    check(
        "1. period at 40 digits vs 4K(E/4)/sqrt3",
        abs(mp.mpf(o39_40.period_str) - T_ref),
        1e-38,
    )
    x_T, _ = flow(newborn.state0_str, newborn.period_str, 113)
    closure = max(abs(x_T[i] - mp.mpf(newborn.state0_str[i])) for i in range(4))
    _, tr_nb = flow(newborn.state0_str, newborn.period_str, 256)
    check("2. newborn state closes under real128", closure, 1e-25)
    # the reference starts from the 30-digit state, which closes only to ~1e-26: near the
    # separatrix tr M moves by |M| times that, so ~1e-20 relative is all it can confirm
    check(
        "2. newborn tr M vs heyoka 256 bits from its 30-digit state (relative)",
        abs(tr_nb - mp.mpf(newborn.trace_str)) / abs(tr_nb),
        1e-20,
    )
    mu = newborn.multipliers
    check(
        "2. multipliers: mu + 1/mu = tr M - 2",
        abs(mu[2] + mu[3] - (newborn.trace - 2)),
        1e-9,
    )
    Es = [float(m.E) for m in branch.members]
    check("3. members outside (4.0, 4.2)", sum(not 4.0 <= E <= 4.2 for E in Es), 1)
    for m in branch.members[:: max(1, len(branch.members) // 3)]:
        x_T, _ = flow([repr(float(v)) for v in m.state0], repr(float(m.period)), 113)
        gap = max(abs(float(x_T[i]) - float(m.state0[i])) for i in range(4))
        check(f"3. member E = {float(m.E):.4f} closes under real128", gap, 1e-7)
    n_stable = 0
    for o in atlas.orbits:
        _, tr_o = flow([repr(float(v)) for v in o.state0], repr(float(o.period)), 113)
        n_stable += bool(0 < tr_o < 4)
    check("4. stable count: census vs real128 traces", abs(n_stable - len(stable)), 1)
    wider = [o for o in rotorlib.census(4.3, 10.0).orbits if o.period <= 8.0]
    missing = sum(
        not any(
            abs(w.period - o.period) < 1e-7 and w.label == o.label for o in atlas.orbits
        )
        for w in wider
    )  # another sampling of the start sets (a longer window) finds nothing more
    check(
        "4. census complete: orbits with T <= 8 found only by a T <= 10 census",
        missing,
        1,
    )

with mp.workprec(276):
    E_tr = mp.findroot(
        lambda E: pendulum_reference(mp.nstr(E, 80))[1] - 4,
        (mp.mpf(repr(tr.E)) - mp.mpf("1e-14"), mp.mpf(repr(tr.E)) + mp.mpf("1e-14")),
        solver="secant",
        tol=mp.mpf(10) ** -60,
    )
    check(
        "5. transition energy vs root of tr M(E) = 4",
        abs(mp.mpf(tr.E_str) - E_tr),
        1e-22,
    )

print("all checks passed" if not failures else f"{len(failures)} checks failed")
sys.exit(1 if failures else 0)
