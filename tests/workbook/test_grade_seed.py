"""The check inputs of a grading come from a secret seed (grading/plan.py: draw_seed), printed in the grader's log,
kept in the grader's process; --seed S draws the same inputs again, --seed 0 the notebook's own (issue 44, item 2)."""
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from rbcourse.workbook.grading import checker, plan

SOLUTION = Path(__file__).resolve().parents[2] / "notebooks" / "solutions" / "01_exercise_euler.ipynb"


def test_every_check_has_a_seed_of_its_own():
    seeds = [checker.own_seed(check) for _, check in checker.checks()]
    assert all(isinstance(s, int) for s in seeds) and len(set(seeds)) == len(seeds)


def test_seeds_are_drawn_anew_and_checked():
    assert len({plan.draw_seed() for _ in range(20)}) == 20
    assert plan.check_seed(0) == 0 and plan.check_seed(plan.MAX_SEED) == plan.MAX_SEED
    for bad in (-1, plan.MAX_SEED + 1, 1.5, True, "3"):
        with pytest.raises(ValueError, match="--seed must be an integer from 0 to"):
            plan.check_seed(bad)


def _wrong_velocity(tmp_path) -> Path:
    nb = json.loads(SOLUTION.read_text("utf-8"))
    nb["cells"].append({"cell_type": "code", "metadata": {}, "execution_count": None, "outputs": [],
                        "source": "def velocity(P, M):\n    return P / M + 0.1 * np.cos(7.3 * P)\n"})   # no named mistake: its inputs are quoted
    subs = tmp_path / "subs"
    subs.mkdir()
    (subs / "eve.ipynb").write_text(json.dumps(nb), encoding="utf-8")
    return subs


def _grade(subs: Path, out: Path, *seed: str) -> tuple[str, str]:
    run = subprocess.run([sys.executable, "-m", "rbcourse", "grade", str(subs), "--out", str(out / "g.csv"),
                          "--workers", "1", "--no-sandbox", *seed], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-2000:]
    said = re.search(r"check inputs drawn from seed (\d+)", run.stdout)
    feedback = (out / "feedback" / "eve.md").read_text("utf-8")
    return said.group(1), re.sub(r"Graded in [\d.]+ s\.", "", feedback)          # (its time varies)


def test_a_grading_draws_its_inputs_from_its_seed_and_says_it(tmp_path):
    subs = _wrong_velocity(tmp_path)
    seed_a, first = _grade(subs, tmp_path / "a")
    seed_b, second = _grade(subs, tmp_path / "b")
    assert seed_a != seed_b and "0" not in (seed_a, seed_b)
    again = _grade(subs, tmp_path / "c", "--seed", seed_a)[1]
    assert again == first                                  # the same seed: the same inputs, the same feedback
    assert first != second                                 # another seed: other inputs, quoted in the feedback
    notebook = _grade(subs, tmp_path / "d", "--seed", "0")[1]
    assert notebook not in (first, second)
