"""The package installs: a wheel and an sdist built from this tree, installed into a clean
virtual environment (numpy, scipy and mpmath only: no heyoka, no Dask), give a working
``import rotorlib`` and a ``rotorlib`` command.

Marked ``slow`` (about a minute: the clean environment downloads or reuses numpy, scipy
and mpmath through pip's cache). Skipped when pip cannot reach a package index, except
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
        "rotorlib/beyond/data/choreo_resonance.json",  # seeds of orbit CG1/5a etc.
    ):
        assert module in names, f"{module} missing from the wheel"
    assert any(n.endswith("entry_points.txt") for n in names)
    with tarfile.open(dists["sdist"]) as tar:
        members = tar.getnames()
    assert any(m.endswith("rotorlib/commands/orbit.py") for m in members)
    version = dists["wheel"].name.split("-")[1]
    assert version == rotorlib.__version__  # the version is set in one place


def test_clean_venv_install_gives_a_working_command(dists, tmp_path):
    env_dir = tmp_path / "venv"
    venv.EnvBuilder(with_pip=True).create(env_dir)
    py = env_dir / "bin" / "python"
    install = _run(
        py,
        "-m",
        "pip",
        "install",
        "-q",
        "--disable-pip-version-check",
        dists["wheel"],
        check=False,
    )
    if install.returncode != 0:
        if os.environ.get("CI") == "true":
            pytest.fail(f"pip install of the wheel failed:\n{install.stderr[-2000:]}")
        pytest.skip(f"pip could not install the wheel here: {install.stderr[-300:]}")
    listed = _run(py, "-m", "pip", "list", "--format=json").stdout
    have = {p["name"].lower() for p in json.loads(listed)}
    assert {"numpy", "scipy", "mpmath", "rotorlib"} <= have
    assert not {"heyoka", "dask", "distributed", "matplotlib"} & have  # extras only
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
