#!/usr/bin/env bash
# A real install, as `pip install .` gives it: build the wheel, install it (with its dependencies, pinned
# as in requirements.txt) into a fresh venv in a folder outside the checkout, check the public contract
# there (tests/test_public_contract.py run as a script, against the installed package) and run
# `python -m rbcourse demo`, checking the files it says it wrote.
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
# the machine code it ships (rbcourse/engine/compiled/), built from these sources: the demo below compiles nothing
ls "$where"/engine/compiled/*.nbc >/dev/null 2>&1 || { echo "wheel check: the wheel has no engine/compiled/*.nbc"; exit 1; }
venv/bin/python "$root/tests/test_public_contract.py"

mkdir run && cd run
venv=../venv
MPLBACKEND=Agg $venv/bin/python -W error::RuntimeWarning -m rbcourse demo --out demo_output > demo.log 2>&1 \
  || { cat demo.log; echo "wheel check: python -m rbcourse demo failed"; exit 1; }
cat demo.log
written=$(sed -n 's/^wrote //p' demo.log)
[ -n "$written" ] || { echo "wheel check: the demo wrote nothing"; exit 1; }
for f in $written; do
  [ -s "$f" ] || { echo "wheel check: the demo said it wrote $f, which is missing or empty"; exit 1; }
done
if grep -q "compiling the engine" demo.log; then
  echo "wheel check: the demo compiled the engine (the shipped machine code was not used)"; exit 1
fi
echo "wheel check: ok ($(echo "$written" | wc -l) files written by the demo from outside the checkout, nothing compiled)"
