#!/usr/bin/env bash
# A real install, as `pip install .` gives it: build the wheel, install it (with its dependencies, pinned
# as in requirements.txt) into a fresh venv in a folder outside the checkout, check the public contract
# there (tests/test_public_contract.py run as a script, against the installed package) and run
# `python -m rbcourse demo` on an empty numba cache (the wheel ships no machine code: the demo compiles what it
# runs, as on a student's machine), checking the files it says it wrote, and timing it.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
python="${PYTHON:-python3}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"

"$python" -m venv venv
venv/bin/pip install -q --upgrade pip >/dev/null 2>&1 || true
venv/bin/pip wheel -q --no-deps "$root" -w wheels
grep -v '^-e' "$root/requirements.txt" > constraints.txt       # the same pins, without the editable line
venv/bin/pip install -q -c constraints.txt wheels/rbcourse-*.whl

# nothing of the checkout is importable from here: the package must come from the wheel
where="$(venv/bin/python -c 'import rbcourse, os; print(os.path.dirname(rbcourse.__file__))')"
case "$where" in
  "$root"*) echo "wheel check: rbcourse was imported from the checkout ($where), not from the wheel"; exit 1 ;;
esac
echo "wheel check: rbcourse installed at $where"
# build output stays out of the wheel: no numba machine code in it
if "$python" -c "import sys, zipfile; sys.exit(any(n.endswith(('.nbi', '.nbc')) for n in zipfile.ZipFile(sys.argv[1]).namelist()))" wheels/rbcourse-*.whl; then :; else
  echo "wheel check: the wheel holds numba machine code (*.nbi, *.nbc)"; exit 1
fi
venv/bin/python "$root/tests/test_public_contract.py"

mkdir run && cd run
venv=../venv
mkdir cache
t0=$(date +%s.%N)
NUMBA_CACHE_DIR="$PWD/cache" MPLBACKEND=Agg $venv/bin/python -W error::RuntimeWarning -m rbcourse demo --out demo_output \
  > demo.log 2>&1 || { cat demo.log; echo "wheel check: python -m rbcourse demo failed"; exit 1; }
seconds=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
cat demo.log
written=$(sed -n 's/^wrote //p' demo.log)
[ -n "$written" ] || { echo "wheel check: the demo wrote nothing"; exit 1; }
for f in $written; do
  [ -s "$f" ] || { echo "wheel check: the demo said it wrote $f, which is missing or empty"; exit 1; }
done
echo "wheel check: ok ($(echo "$written" | wc -l) files written by the demo from outside the checkout, in $seconds s on an empty numba cache)"
