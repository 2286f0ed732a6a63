#!/usr/bin/env bash
# Python 3.13 with an empty numba cache, as a student with a newer Python meets the workbook the first time: a fresh
# venv on pyenv's 3.13 (requirements.txt, this checkout editable), NUMBA_CACHE_DIR a new empty folder (the engine
# compiles everything it runs, cold), then
# `python -m rbcourse demo` timed as a whole process, and the full-length French exercise notebook
# (notebooks/fr/01_exercice_euler.ipynb) run as .ci/notebooks_full.py runs notebooks, each cell timed; each of the
# two on an empty cache of its own (the notebook compiles what it needs, as for a student who opens it first).
# Prints "python 3.13, empty cache: demo N s; fr/01 N s, slowest cell #K N s".  Exits 0 with one line when pyenv
# or its 3.13 is missing; non-zero when the demo or the notebook fails.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"

if ! command -v pyenv >/dev/null 2>&1; then
  echo "python 3.13: skipped (pyenv is not installed on this machine)"; exit 0
fi
python=""
for candidate in "$(pyenv root)"/versions/3.13.*/bin/python3; do     # the newest 3.13 (the glob sorts 3.13.10 early)
  [ -x "$candidate" ] || continue
  if [ -z "$python" ] || [ "$("$candidate" -c 'import sys; print(sys.version_info[2])')" -gt \
                           "$("$python" -c 'import sys; print(sys.version_info[2])')" ]; then
    python="$candidate"
  fi
done
if [ -z "$python" ]; then
  echo "python 3.13: skipped (pyenv has no 3.13: $(pyenv versions --bare 2>/dev/null | tr '\n' ' '))"; exit 0
fi

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$python" -m venv "$work/venv"
(cd "$root" && "$work/venv/bin/pip" install -q -r requirements.txt)
py="$work/venv/bin/python"
echo "python 3.13: $("$py" -c 'import sys; print(sys.version.split()[0])') at $python, venv in $work"

mkdir "$work/cache-demo" "$work/cache-notebook" "$work/demo"
export MPLBACKEND=Agg
unset RBCOURSE_QUICK
# the notebook's kernel is this venv's Python for certain (JUPYTER_PATH is searched before the user's kernels)
mkdir -p "$work/kernels/kernels/python3"
printf '{"argv": ["%s", "-m", "ipykernel_launcher", "-f", "{connection_file}"], "display_name": "Python 3.13", "language": "python"}\n' \
  "$py" > "$work/kernels/kernels/python3/kernel.json"
export JUPYTER_PATH="$work/kernels"

now() { date +%s.%N; }
t0=$(now)
(cd "$work/demo" && NUMBA_CACHE_DIR="$work/cache-demo" "$py" -m rbcourse demo --out "$work/demo/out") > "$work/demo.log" 2>&1 \
  || { cat "$work/demo.log"; echo "python 3.13: python -m rbcourse demo failed (empty cache)"; exit 1; }
demo=$(awk -v a="$t0" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }')
cat "$work/demo.log"
echo "python 3.13, empty cache: demo $demo s"

NUMBA_CACHE_DIR="$work/cache-notebook" "$py" "$root/.ci/notebooks_full.py" --cell-times "$root/notebooks/fr/01_exercice_euler.ipynb" | tee "$work/nb.log" \
  || { echo "python 3.13: notebooks/fr/01_exercice_euler.ipynb failed (empty cache)"; exit 1; }
notebook=$(awk '$1 == "ok" { print $2; exit }' "$work/nb.log")
slowest=$(sed -n 's/^ *slowest cell \(#[0-9]*\): \([0-9.]*\) s$/\1 \2 s/p' "$work/nb.log" | head -1)
echo "python 3.13, empty cache: demo $demo s; fr/01 $notebook s, slowest cell $slowest"
