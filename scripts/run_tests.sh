#!/usr/bin/env bash
# Run every check:
#   1. ruff check and ruff format --check on the Python code and the notebooks
#      (config: [tool.ruff] in pyproject.toml);
#   2. actionlint on the GitHub Actions workflows (.github/workflows/), and mypy on
#      rotorlib (config: [tool.mypy] in pyproject.toml);
#   3. the unit tests (tests/, including the headless-browser test of the built
#      HTML in _build/html) and the doctests of rotorlib;
#   4. nbval: re-execute the book's notebooks, comparing fresh outputs with the
#      stored ones, twice: once as the machine is, once in a floating-point
#      environment changed to imitate another CPU (see perturbed_env below).
# pytest and nbval run on NPROC workers (pytest-xdist, default 2: this machine's cores),
# one file per worker (--dist loadfile: a notebook's cells run in order in one kernel).
#
# The last line is "run_tests: all parts passed" only when every part ran and passed.
# A part that did not run is named in a "run_tests: NOT RUN: ..." line with how to run
# it: the browser test (tests/test_book_html.py) is skipped without the built book or
# without chromium at $CHROMIUM (default /usr/bin/chromium; `apt-get install chromium`
# as .ci/run does), and parts left out of RUN_TESTS_PARTS (default: all of
# "lint types pytest doctests nbval") are not run. RUN_TESTS_PYTEST (default "tests")
# narrows the pytest part, e.g.
#   CHROMIUM=/nonexistent RUN_TESTS_PARTS=pytest RUN_TESTS_PYTEST=tests/test_book_html.py \
#       bash scripts/run_tests.sh
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup_env.sh

export PYTHONHASHSEED=0 TQDM_DISABLE=1
PY=.venv/bin/python
XDIST=(-n "${NPROC:-2}" --dist loadfile)

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

# Every part always runs (so one report shows every failure); the script fails
# if any failed, and lists those that did. Each part's wall-clock time is printed.
failed=()
not_run=()
PARTS=" ${RUN_TESTS_PARTS:-lint types pytest doctests nbval} "
selected() {  # selected GROUP: whether GROUP is in RUN_TESTS_PARTS
    [[ "$PARTS" == *" $1 "* ]]
}
part() {  # part NAME CMD...: run CMD, print its time, record a failure
    local name=$1 t0=$SECONDS rc=0
    shift
    "$@" || rc=$?
    echo "run_tests: $name took $((SECONDS - t0)) s$([ "$rc" -eq 0 ] || echo " (FAILED, exit $rc)")"
    [ "$rc" -eq 0 ] || failed+=("$name")
}

# --- lint ---------------------------------------------------------------------
LINT_PATHS=(rotorlib tests scripts benchmarks book)
if selected lint; then
    part "ruff check" .venv/bin/ruff check --no-cache "${LINT_PATHS[@]}"
    part "ruff format --check" .venv/bin/ruff format --check --no-cache "${LINT_PATHS[@]}"
    # actionlint's optional shellcheck/pyflakes passes are switched off so that the
    # result does not depend on what else happens to be installed on the machine.
    shopt -s nullglob
    workflows=(.github/workflows/*.yml .github/workflows/*.yaml)
    shopt -u nullglob
    if [ "${#workflows[@]}" -eq 0 ]; then
        echo "run_tests: no workflow in .github/workflows/ (expected at least book.yml)"
        failed+=("actionlint")
    else
        part "actionlint" .venv/bin/actionlint -shellcheck= -pyflakes= "${workflows[@]}"
    fi
else
    not_run+=("lint (ruff and actionlint): not in RUN_TESTS_PARTS")
fi

# --- types --------------------------------------------------------------------
if selected types; then
    part "mypy rotorlib" .venv/bin/mypy --no-incremental
else
    not_run+=("types (mypy): not in RUN_TESTS_PARTS")
fi

# --- tests --------------------------------------------------------------------
mkdir -p tests book _build
if selected pytest; then
    read -r -a PYTEST_PATHS <<< "${RUN_TESTS_PYTEST:-tests}"
    [ "${PYTEST_PATHS[*]}" = tests ] ||
        not_run+=("pytest on the rest of tests/: RUN_TESTS_PYTEST=${PYTEST_PATHS[*]}")
    n_tests=$(find "${PYTEST_PATHS[@]}" -name 'test_*.py' -o -name '*_test.py' | wc -l)
    rm -f _build/pytest.xml
    MPLBACKEND=Agg part "pytest ${PYTEST_PATHS[*]}" run_pytest "$n_tests" "${XDIST[@]}" \
        -rs --junitxml=_build/pytest.xml "${PYTEST_PATHS[@]}"
    # The browser test skips itself (with its reason) without chromium or the built
    # book: say so at the end, loudly, rather than count it among the passes.
    browser=$("$PY" scripts/skipped_tests.py _build/pytest.xml tests/test_book_html.py || true)
    if [ -n "$browser" ]; then
        not_run+=("browser test (tests/test_book_html.py): $browser. To run it: build the book (bash scripts/build_book.sh) and install chromium (apt-get install chromium, as .ci/run does) or set CHROMIUM=/path/to/chromium")
    fi
else
    not_run+=("pytest (tests/, the browser test included): not in RUN_TESTS_PARTS")
fi
# The Examples sections of the library's docstrings (run as written).
if selected doctests; then
    MPLBACKEND=Agg part "doctests rotorlib/" "$PY" -m pytest -q -p no:cacheprovider \
        --doctest-modules rotorlib
else
    not_run+=("doctests: not in RUN_TESTS_PARTS")
fi

# --nbval-current-env: execute notebooks with this venv's Python, whatever
# kernel their metadata names. MPLBACKEND must not reach the kernel: with it
# set (e.g. Agg) ipykernel does not use the inline backend and figures vanish.
# The sanitizer file masks only what cannot be rounded (see its comments): every
# number a chapter prints is rounded to its verified digits or printed as a bound.
n_nb=$(find book -name '*.ipynb' -not -path '*/.ipynb_checkpoints/*' | wc -l)
unset MPLBACKEND
if selected nbval; then
    source scripts/perturbed_env.sh   # defines `perturbed` (used below)
    "$PY" scripts/fp_environment.py
    NBVAL=(--nbval --nbval-current-env --nbval-cell-timeout=600
           --nbval-sanitize-with book/nbval_sanitize.cfg book/)
    mkdir -p _build
    part "nbval book/" run_pytest "$n_nb" "${XDIST[@]}" "${NBVAL[@]}" --junitxml=_build/nbval.xml

    # The same notebooks again, in a floating-point environment that imitates another
    # CPU (OpenBLAS kernel, numpy SIMD groups, one thread: scripts/perturbed_env.sh).
    # A number that moves there is printed with more digits than its computation has.
    part "nbval book/ (perturbed)" perturbed run_pytest "$n_nb" "${XDIST[@]}" "${NBVAL[@]}" \
        --junitxml=_build/nbval_perturbed.xml
    # each chapter's execution time in both runs (the sum of its cells' times)
    "$PY" scripts/chapter_times.py _build/nbval.xml _build/nbval_perturbed.xml || true
else
    not_run+=("nbval (both runs): not in RUN_TESTS_PARTS")
fi

for what in "${not_run[@]}"; do
    echo "run_tests: NOT RUN: $what"
done
names=$(printf '%s\n' "${not_run[@]}" | sed 's/:.*//' | paste -sd, - | sed 's/,/, /g')
if [ "${#failed[@]}" -gt 0 ]; then
    echo "run_tests: FAILED: $(IFS=,; echo "${failed[*]}" | sed 's/,/, /g')${names:+; NOT RUN: $names}"
    exit 1
fi
if [ "${#not_run[@]}" -gt 0 ]; then
    echo "run_tests: the parts that ran passed, but NOT all parts ran. NOT RUN: $names (how to run each: above)"
    exit 0
fi
echo "run_tests: all parts passed"
