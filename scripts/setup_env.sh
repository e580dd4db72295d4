#!/usr/bin/env bash
# Create/refresh the project virtualenv in .venv (idempotent).
# Reinstalls only when environment.txt, pyproject.toml or the presence of the
# rotorlib package changed since the last successful run (.venv/.stamp).
set -euo pipefail
cd "$(dirname "$0")/.."

export PIP_DISABLE_PIP_VERSION_CHECK=1
PY=.venv/bin/python
STAMP=.venv/.stamp

if [ ! -x "$PY" ]; then
    echo "setup_env: creating .venv"
    python3 -m venv .venv
fi

# rotorlib may not exist yet in a fresh repository: the editable install
# is done (and accounted in the stamp) only once the package is there.
have_pkg=no
[ -f rotorlib/__init__.py ] && have_pkg=yes

want=$( { cat environment.txt pyproject.toml; echo "rotorlib=$have_pkg"; } | sha256sum | cut -d' ' -f1)
if [ -f "$STAMP" ] && [ "$(cat "$STAMP")" = "$want" ]; then
    echo "setup_env: .venv up to date"
    exit 0
fi

rm -f "$STAMP"
echo "setup_env: installing requirements into .venv"
"$PY" -m pip install -q --upgrade pip
"$PY" -m pip install -q -r environment.txt
if [ "$have_pkg" = yes ]; then
    "$PY" -m pip install -q -e .
else
    echo "setup_env: rotorlib/__init__.py not found; skipping 'pip install -e .'"
fi
echo "$want" > "$STAMP"
echo "setup_env: done"
