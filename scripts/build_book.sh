#!/usr/bin/env bash
# Build the Jupyter Book (executing every notebook) into _build/html.
# Sphinx warnings are errors (-W --keep-going) and references are nitpicky.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup_env.sh

export PYTHONHASHSEED=0 TQDM_DISABLE=1
unset MPLBACKEND   # let the notebook kernels use the inline backend (figures)
.venv/bin/jupyter-book build . --all --builder html \
    --warningiserror --keep-going --nitpick

echo "build_book: HTML written to $PWD/_build/html/index.html"
