#!/usr/bin/env bash
# Build the Jupyter Book into _build/html from the notebooks as stored.
# Sphinx warnings are errors (-W --keep-going) and references are nitpicky.
#
# Nothing is executed (`execute_notebooks: "off"` in _config.yml): the pages show
# the stored outputs, which the test command's nbval runs re-execute and compare
# (README, "Building and testing in detail"). A notebook stored without outputs
# fails tests/test_toc.py.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup_env.sh

export PYTHONHASHSEED=0 TQDM_DISABLE=1
PY=.venv/bin/python

# --- generated pages ----------------------------------------------------------
"$PY" scripts/make_api.py
"$PY" scripts/make_gallery.py
"$PY" scripts/make_ledger.py

# --- build --------------------------------------------------------------------
# --all: re-read every page (a few seconds; no notebook executes).
rm -rf _build/html   # no stale pages of chapters that left the toc
.venv/bin/jupyter-book build . --all --builder html \
    --warningiserror --keep-going --nitpick

echo "build_book: HTML written to $PWD/_build/html/index.html"
