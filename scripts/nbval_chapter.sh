#!/usr/bin/env bash
# Check chapters against their stored outputs, as the test command does, without
# overwriting anything: nbval re-executes each notebook given (default: all of
# book/) and compares, once as the machine is and once in the perturbed
# floating-point environment (scripts/perturbed_env.sh).
#   bash scripts/nbval_chapter.sh book/03_transitions.ipynb [more notebooks]
# A failure names the cell and shows the stored and the fresh output; see the book's
# page "Reproducing this book" for how to read it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup_env.sh >/dev/null
export PYTHONHASHSEED=0 TQDM_DISABLE=1
unset MPLBACKEND
PY=.venv/bin/python
[ "$#" -gt 0 ] || set -- book/
NBVAL=(-p no:cacheprovider --nbval --nbval-current-env --nbval-cell-timeout=600
       --nbval-sanitize-with book/nbval_sanitize.cfg "$@")
source scripts/perturbed_env.sh
rc=0
"$PY" scripts/fp_environment.py
"$PY" -m pytest "${NBVAL[@]}" || rc=1
perturbed "$PY" -m pytest "${NBVAL[@]}" || rc=1
[ "$rc" -eq 0 ] && echo "nbval_chapter: both runs passed" || echo "nbval_chapter: FAILED"
exit "$rc"
