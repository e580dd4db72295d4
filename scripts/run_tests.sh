#!/usr/bin/env bash
# Run the unit tests (tests/, including the headless-browser test of the built
# HTML in _build/html) and re-execute the book's notebooks with nbval,
# comparing fresh outputs with the stored ones.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup_env.sh

export PYTHONHASHSEED=0 TQDM_DISABLE=1
PY=.venv/bin/python

# run_pytest N ARGS...: run pytest; its exit code 5 ("no tests collected")
# is accepted only when N (the number of candidate files) is 0.
run_pytest() {
    local n=$1 rc=0
    shift
    "$PY" -m pytest "$@" || rc=$?
    if [ "$rc" -eq 5 ] && [ "$n" -eq 0 ]; then
        echo "run_tests: nothing to collect for 'pytest $*' yet"
        rc=0
    fi
    return "$rc"
}

# Both parts always run (so one report shows every failure); the script fails
# if either failed. Each part's wall-clock time is printed.
status=0
mkdir -p tests book
n_tests=$(find tests -name 'test_*.py' -o -name '*_test.py' | wc -l)
t0=$SECONDS
MPLBACKEND=Agg run_pytest "$n_tests" tests || status=1
echo "run_tests: pytest tests/ took $((SECONDS - t0)) s"

# --nbval-current-env: execute notebooks with this venv's Python, whatever
# kernel their metadata names. MPLBACKEND must not reach the kernel: with it
# set (e.g. Agg) ipykernel does not use the inline backend and figures vanish.
n_nb=$(find book -name '*.ipynb' -not -path '*/.ipynb_checkpoints/*' | wc -l)
unset MPLBACKEND
t0=$SECONDS
run_pytest "$n_nb" --nbval --nbval-current-env --nbval-cell-timeout=600 \
    --nbval-sanitize-with book/nbval_sanitize.cfg book/ || status=1
echo "run_tests: nbval book/ took $((SECONDS - t0)) s"
exit "$status"
