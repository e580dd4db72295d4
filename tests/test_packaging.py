"""The package installs: a wheel and an sdist built from this tree, installed into a clean
virtual environment with only its required dependencies (numpy, scipy, mpmath and, on
Linux x86_64/aarch64, heyoka: no Dask, no matplotlib), give a working ``import
rotorlib`` and a ``rotorlib`` command that prints what ``.venv`` prints; with heyoka
removed, every command that integrates the flow refuses in one line naming the extra.

The clean environment gets numpy, scipy, mpmath and heyoka at the versions pinned in
``environment.txt`` (pip's constraints), from the package index of this machine's pip
configuration (or its cache). Marked ``slow`` (about 1.5 minutes: the install, then
five commands in each environment). Skipped when pip cannot install the wheel, except
under ``CI=true``, where it must run.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tarfile
import venv
import zipfile
from pathlib import Path

import pytest

import rotorlib

ROOT = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.slow


def _run(*cmd, cwd=None, check=True) -> subprocess.CompletedProcess:
    return subprocess.run(
        [str(c) for c in cmd], cwd=cwd, capture_output=True, text=True, check=check
    )


@pytest.fixture(scope="module")
def dists(tmp_path_factory) -> dict[str, Path]:
    out = tmp_path_factory.mktemp("dist")
    # --no-isolation: build with this environment's setuptools (no download)
    _run(sys.executable, "-m", "build", "--no-isolation", "--outdir", out, ROOT)
    wheel = next(out.glob("rotorlib-*.whl"))
    sdist = next(out.glob("rotorlib-*.tar.gz"))
    return {"wheel": wheel, "sdist": sdist}


def test_distributions_hold_every_subpackage(dists):
    names = zipfile.ZipFile(dists["wheel"]).namelist()
    for module in (
        "rotorlib/cli.py",
        "rotorlib/commands/trace.py",
        "rotorlib/plotting/__init__.py",
    ):
        assert module in names, f"{module} missing from the wheel"
    assert any(n.endswith("entry_points.txt") for n in names)
    with tarfile.open(dists["sdist"]) as tar:
        members = tar.getnames()
    assert any(m.endswith("rotorlib/commands/orbit.py") for m in members)
    version = dists["wheel"].name.split("-")[1]
    assert version == rotorlib.__version__  # the version is set in one place


#: The commands a new user starts with (issue 29): each must print in the clean
#: environment what it prints in .venv, to the last printed digit.
COMMANDS = (
    "orbit CG --E 3 --digits 30",
    "orbit ISl2 --E 4",
    "family IS^l_1 --E-range 3.99 4.1",
    "atlas --E 4.3 --t-max 8",
    "spectrum --hbar 0.5 --sector A1 --E-max 4",
)
#: ... of which these integrate the flow: they refuse without heyoka.
NEED_HEYOKA = COMMANDS[:4]


def _pins(path: Path) -> Path:
    """A pip constraints file: environment.txt's pins of the required dependencies."""
    keep = ("numpy", "scipy", "mpmath", "heyoka")
    lines = [
        line.split("#")[0].strip()
        for line in (ROOT / "environment.txt").read_text().splitlines()
        if line.split("==")[0].strip() in keep
    ]
    assert len(lines) == len(keep), lines
    path.write_text("\n".join(lines) + "\n")
    return path


def test_clean_venv_install_gives_a_working_command(dists, tmp_path):
    # the reference: the same commands in this (development) environment, started
    # now so that they run while pip installs
    refs = {
        cmd: subprocess.Popen(
            [sys.executable, "-m", "rotorlib", *cmd.split()],
            cwd=tmp_path,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for cmd in COMMANDS
    }
    env_dir = tmp_path / "venv"
    venv.EnvBuilder(with_pip=True).create(env_dir)
    py = env_dir / "bin" / "python"
    pip = (py, "-m", "pip")
    install = _run(
        *pip,
        "install",
        "-q",
        "--disable-pip-version-check",
        "-c",
        _pins(tmp_path / "pins.txt"),
        dists["wheel"],
        check=False,
    )
    if install.returncode != 0:
        for p in refs.values():
            p.kill()
        if os.environ.get("CI") == "true":
            pytest.fail(f"pip install of the wheel failed:\n{install.stderr[-2000:]}")
        pytest.skip(f"pip could not install the wheel here: {install.stderr[-300:]}")
    listed = _run(*pip, "list", "--format=json").stdout
    have = {p["name"].lower() for p in json.loads(listed)}
    assert {"numpy", "scipy", "mpmath", "heyoka", "rotorlib"} <= have
    assert not {"dask", "distributed", "matplotlib"} & have  # extras only
    command = env_dir / "bin" / "rotorlib"
    version = _run(command, "--version").stdout.strip()
    assert version == f"rotorlib {rotorlib.__version__}"
    # outside the source tree, so the installed copy is the one imported
    res = _run(command, "trace", "pendulum", "--E", "3.9", "--json", cwd=tmp_path)
    record = json.loads(res.stdout)
    assert record["phase"] == "lib" and 0 < float(record["trace"]) < 4
    bad = _run(command, "trace", "pendulum", "--E", "-1", cwd=tmp_path, check=False)
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1
    assert "Traceback" not in bad.stderr

    installed = {}
    for cmd in COMMANDS:
        out = _run(command, *cmd.split(), cwd=tmp_path, check=False)
        assert out.returncode == 0 and out.stdout.strip(), (cmd, out.stderr)
        installed[cmd] = out.stdout
    for cmd, p in refs.items():
        stdout, stderr = p.communicate(timeout=600)
        assert p.returncode == 0, (cmd, stderr)
        assert installed[cmd] == stdout, (
            f"{cmd}: the installed package prints otherwise"
        )

    # heyoka removed (a platform without its wheels): the flow refuses, in one line
    # naming the extra; the quantum spectrum still prints the same levels
    _run(*pip, "uninstall", "-q", "-y", "heyoka")
    assert "heyoka" not in _run(*pip, "list", "--format=freeze").stdout.lower()
    for cmd in COMMANDS:
        out = _run(command, *cmd.split(), cwd=tmp_path, check=False)
        if cmd in NEED_HEYOKA:
            assert out.returncode == 2 and out.stdout == "", (cmd, out.stderr)
            assert out.stderr.count("\n") == 1 and "Traceback" not in out.stderr
            assert "rotorlib[fast]" in out.stderr and "heyoka" in out.stderr
        else:
            assert out.returncode == 0 and out.stdout == installed[cmd], out.stderr
