"""Every sentence the library's core says (Trajectory.outcome and describe, the divergence reasons, the contact
solver's failure, Scene.describe and the effects', pivots', impulses' and ground's descriptions, the methods'
summaries) is in the active language: under "fr" no English sentence, under "en" no French one, and the French
ones use the glossary's words (rbcourse.support.glossary)."""
import numpy as np
import pytest

import rbcourse as rb
from rbcourse.support import glossary, language
from rbcourse.driver import contact_failed
from rbcourse.methods import METHODS
from rbcourse.trajectory import blow_up

from helpers import ENGLISH, FRENCH, words

BOX = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))

def sentences():
    """(where, text) for every core sentence, in the active language."""
    scene = rb.Scene(BOX, [rb.Gravity(), rb.PointForce((0.1, 0, 0), (0, 0, 1.0)), rb.Spring((0, 0, 0), (0, 0, 1), 5.0),
                           rb.LinearDrag(0.1), rb.AngularDrag(0.01), rb.Ground(-1.0),
                           rb.Impulse((0, 0, 0), (1.0, 0, 0), 0.05)])
    X0 = rb.State.from_velocities(BOX, (0, 0, 0.5), np.eye(3), (0.1, 0, 0), (1.0, 2.0, 3.0))
    ran = rb.simulate(scene, X0, 0.1, 0.01, "rk4")
    fast = rb.State.from_velocities(BOX, np.zeros(3), np.eye(3), np.zeros(3), (0.1, 0.1, 50.0))
    blew = rb.simulate(BOX, fast, 60.0, 1e-2, "euler", on_divergence="stop")
    pivoted = rb.Scene(BOX, [rb.Gravity(), rb.Pivot((0, 0, 0.1), (0, 0, 0))])
    pushes = rb.Scene(BOX, [rb.PointForce((0, 0, 0), rb.Pulse((0, 0, 1.0), 0.0, 0.1)),
                            rb.PointForce((0, 0, 0), rb.Ramp((1.0, 0, 0), 0.0, 0.1)),
                            rb.PointForce((0, 0, 0), rb.Steps((0.0, 0.5), ((0, 0, 1.0), (0, 1.0, 0))))])
    two = rb.Scene([BOX, BOX], [rb.Spring((0, 0, 0), (0, 0, 0), 1.0, body=0, other_body=1, other_point=(0, 0, 0), rest_length=0.5)])
    out = [("outcome (ran)", ran.outcome), ("outcome (diverged)", blew.outcome), ("Trajectory.describe", ran.describe()),
           ("repr(Trajectory)", repr(ran)), ("repr(Trajectory) (diverged)", repr(blew)),
           ("Scene.describe", scene.describe("rk4")), ("Scene.describe (free)", rb.Scene(BOX).describe()),
           ("Scene.describe (pivot)", pivoted.describe()), ("Scene.describe (profiles)", pushes.describe()), ("Scene.describe (two bodies)", two.describe()),
           ("contact_failed", contact_failed())]
    try:                                         # the error a diverged run raises (on_divergence="raise")
        rb.simulate(BOX, fast, 60.0, 1e-2, "euler")
        raise AssertionError("the fast box under euler at dt = 0.01 should diverge")
    except rb.SimulationDiverged as e:
        out.append(("SimulationDiverged", str(e)))
    for name in ("x", "R"):
        for bad in (np.nan, np.inf, 1e200):
            out.append((f"blow_up({name}, {bad})", blow_up([(name, np.array([bad]))])))
    out += [(f"METHODS[{m!r}].summary", METHODS[m].summary) for m in METHODS]
    return out


@pytest.fixture
def french():
    language.choose("fr")
    yield
    language.choose("en")


def test_every_core_sentence_is_french_under_fr(french):
    for where, text in sentences():
        english = words(text) & ENGLISH
        assert not english, f"{where} says English words {sorted(english)} under 'fr': {text!r}"
        assert words(text) & FRENCH, f"{where} has no French word under 'fr': {text!r}"
        avoided = glossary.avoided_in(text)
        assert not avoided, f"{where} uses {avoided} (the glossary's words instead): {text!r}"


def test_every_core_sentence_is_english_under_en():
    assert language.current() == "en"
    for where, text in sentences():
        french = words(text) & FRENCH
        assert not french, f"{where} says French words {sorted(french)} under 'en': {text!r}"


def test_the_language_is_read_when_the_sentence_is_said(french):
    """A sentence follows the language active when it is asked for (a Method's summary, an outcome), not the one
    active when the object was made."""
    traj = rb.simulate(BOX, rb.State.at_rest(), 0.02, 0.01, "rk4")
    assert traj.outcome.startswith("a tourné jusqu'à t = 0.02 s")
    language.choose("en")
    assert traj.outcome.startswith("ran to t = 0.02 s") and METHODS["rk4"].summary.startswith("classic Runge–Kutta 4")


def test_the_stability_report_in_french(french, tmp_path):
    """`stability --lang fr`'s report (stability.markdown under "fr"): its sentences, outcomes, invariants and what
    goes wrong in French, with no English word; under "en", the English report, unchanged in its words."""
    from rbcourse.bench import stability
    cells, _ = stability.main(["heavy_top_coarse", "sphere"], ["euler", "rk4"], quick=True, out=tmp_path, workers=1)
    text = stability.markdown(cells, quick=True)
    prose = "\n".join(line for line in text.splitlines() if not line.startswith("`"))
    english = words(prose) & ENGLISH
    assert not english, f"English words {sorted(english)} in the French report:\n{text}"
    for said in ("Matrice de stabilité", "Ce qui tourne mal : 2 rad de rotation propre par pas", "| euler | divergé à t =",
                 "| rk4 | fidèle |", "err. énergie", "toutes les promesses ont tenu"):
        assert said in text, said
    language.choose("en")
    text = stability.markdown(cells, quick=True)
    assert not words(text) & FRENCH and "What goes wrong: 2 rad of spin per step" in text and "| rk4 | faithful |" in text


def test_the_command_line_writes_the_french_report(tmp_path):
    from rbcourse.__main__ import main
    assert main(["stability", "--quick", "--cases", "sphere", "--methods", "rk4", "--workers", "1", "--lang", "fr",
                 "--out", str(tmp_path)]) == 0
    assert "# Matrice de stabilité" in (tmp_path / "stability.md").read_text(encoding="utf-8")
    language.choose("en")


def test_the_bench_report_in_french(french, tmp_path):
    """`bench --lang fr`: the work-precision and error-sweep reports in French, no English word; the English ones
    unchanged in their words."""
    from rbcourse.bench import work_precision as bench
    runs, _ = bench.main(["A"], ["rk4", "euler"], quick=True, out=tmp_path, peers=False, repeats=1)
    for report in (bench.markdown(runs), bench.errors_markdown(runs)):
        english = words(report) & ENGLISH
        assert not english, f"English words {sorted(english)} in the French report:\n{report}"
        assert "## Problème A" in report and "| méthode |" in report
    language.choose("en")
    assert "## Problem A" in bench.markdown(runs) and not words(bench.markdown(runs)) & FRENCH


def test_a_3d_view_says_its_legend_and_title_in_french(french):
    """A view's title and legend (arrows' scales, spring, ghost, a blow-up's cut) in the active language."""
    from rbcourse.viz import viewer
    from rbcourse import examples
    ex = examples.box_on_spring()
    run = rb.simulate(ex.scene, ex.X0, 0.5, 1e-2, "rk4")
    drawing = viewer.draw_trajectory(run, ghost=run, ghost_label="la même simulation")
    said = "\n".join([drawing.title] + [text for _, text in drawing.legend])
    assert not words(said) & ENGLISH, said
    assert "boîte au ressort : rk4" in said and "m par rad/s" in said and "ressort (k = 50 N/m)" in said, said
    assert "fantôme : la même simulation" in said, said
    fast = rb.State.from_velocities(BOX, np.zeros(3), np.eye(3), np.zeros(3), (0.1, 0.1, 50.0))
    blew = rb.simulate(BOX, fast, 60.0, 1e-2, "euler", on_divergence="stop")
    said = "\n".join([text for _, text in viewer.draw_trajectory(blew).legend])
    assert "coupées à" in said and not words(said) & ENGLISH, said
