#!/usr/bin/env bash
# Build the Jupyter Book into _build/html, executing the notebooks that need it.
# Sphinx warnings are errors (-W --keep-going) and references are nitpicky.
#
# Re-execution (see README, "Re-execution"): notebooks run through jupyter-cache
# (`execute_notebooks: cache` in _config.yml), which keys a notebook on its code
# cells only (MyST-NB issue #299). To re-execute when the library changes too,
# the cache directory is keyed on a hash of everything the outputs depend on
# besides the notebook itself: rotorlib/**/*.py, pyproject.toml,
# environment.txt and the data products in book/data/. _build/.jupyter_cache is a symlink to
# _build/.jupyter_caches/<hash>; a changed library gives a new, empty cache
# (every notebook re-executes), restoring the library restores the old one.
# Only the most recent KEEP_CACHES caches are kept.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup_env.sh

export PYTHONHASHSEED=0 TQDM_DISABLE=1
unset MPLBACKEND   # let the notebook kernels use the inline backend (figures)
PY=.venv/bin/python
KEEP_CACHES=${KEEP_CACHES:-3}

# --- key the execution cache on the library -----------------------------------
key=$( {
    find rotorlib -name '*.py' -not -path '*/__pycache__/*' | LC_ALL=C sort |
        while read -r f; do echo "== $f"; cat "$f"; done
    echo "== pyproject.toml"; cat pyproject.toml
    echo "== environment.txt"; cat environment.txt
    find book/data -type f 2>/dev/null | LC_ALL=C sort |
        while read -r f; do echo "== $f"; cat "$f"; done
} | sha256sum | cut -c1-16)
if [ -e _build/.jupyter_cache ] && [ ! -L _build/.jupyter_cache ]; then
    rm -rf _build/.jupyter_cache             # a plain cache dir from an older build script
fi
if [ "$(readlink _build/.jupyter_cache 2>/dev/null || true)" = ".jupyter_caches/$key" ]; then
    echo "build_book: rotorlib key $key unchanged: only changed notebooks execute"
elif [ -d "_build/.jupyter_caches/$key" ]; then
    echo "build_book: rotorlib key $key: library changed back; reusing its earlier cache"
else
    echo "build_book: rotorlib key $key: new library state; every notebook executes"
fi
mkdir -p "_build/.jupyter_caches/$key"
touch "_build/.jupyter_caches/$key"          # mtime = last use (for pruning)
ln -sfn ".jupyter_caches/$key" _build/.jupyter_cache
echo "$key" > _build/.rotorlib.key
# prune old caches (keep the KEEP_CACHES most recently used)
ls -1t _build/.jupyter_caches | tail -n +$((KEEP_CACHES + 1)) |
    while read -r old; do rm -rf "_build/.jupyter_caches/$old"; done

# --- generated pages ----------------------------------------------------------
"$PY" scripts/make_api.py
"$PY" scripts/make_gallery.py
"$PY" scripts/make_ledger.py

# --- build --------------------------------------------------------------------
# --all: re-read every page (cheap: unchanged notebooks come from the cache);
# without it Sphinx would not notice a change that lives only in rotorlib.
# Executed outputs are kept in the jupyter-cache, not in _build/html.
rm -rf _build/html   # no stale pages of chapters that left the toc
.venv/bin/jupyter-book build . --all --builder html \
    --warningiserror --keep-going --nitpick

echo "build_book: HTML written to $PWD/_build/html/index.html"
