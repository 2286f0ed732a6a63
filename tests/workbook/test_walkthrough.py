"""The slides' Itération 1 and 2, against numbers computed by hand."""
import numpy as np
import pytest

import rbcourse as rb

BOX = rb.RigidBody.box(mass=1.0, size=(0.3, 0.2, 0.05))   # I = (0.0425, 0.0925, 0.13)/12
CORNER = (0.15, 0.1, 0.025)
PUSH = (0.0, 0.0, 10.0)
DT = 0.01


@pytest.fixture
def recs():
    return rb.walkthrough(BOX, rb.State.at_rest(), forces=[(CORNER, PUSH)], dt=DT, iterations=2)


def test_iteration_1_by_hand(recs):
    r1 = recs[0]
    assert r1.index == 1
    np.testing.assert_array_equal(r1.v, 0)
    np.testing.assert_array_equal(r1.omega, 0)
    np.testing.assert_array_equal(r1.R_dot, 0)
    np.testing.assert_allclose(r1.I_inv, np.diag([12 / 0.0425, 12 / 0.0925, 12 / 0.13]), rtol=1e-14)
    np.testing.assert_allclose(r1.F, [0, 0, 10])
    np.testing.assert_allclose(r1.tau, [1.0, -1.5, 0.0])        # r ∧ F = (0.1·10, −0.15·10, 0)
    # after iteration 1 the state is (x, R, Δt·F, Δt·τ): nothing has moved but the momenta
    np.testing.assert_array_equal(r1.after.x, [0, 0, 0])
    np.testing.assert_array_equal(r1.after.R, np.eye(3))
    np.testing.assert_allclose(r1.after.P, [0, 0, 0.1])
    np.testing.assert_allclose(r1.after.L, [0.01, -0.015, 0.0])


def test_iteration_2_by_hand(recs):
    r2 = recs[1]
    assert r2.before == recs[0].after
    wx, wy = 0.01 * 12 / 0.0425, -0.015 * 12 / 0.0925            # ω = I⁻¹_body L = (2.8235…, −1.9459…, 0)
    np.testing.assert_allclose(r2.v, [0, 0, 0.1])
    np.testing.assert_allclose(r2.omega, [wx, wy, 0], rtol=1e-14)
    np.testing.assert_allclose(r2.R_dot, [[0, 0, wy], [0, 0, -wx], [-wy, wx, 0]], rtol=1e-14)
    # x and R start to move now
    np.testing.assert_allclose(r2.after.x, [0, 0, 0.001])
    np.testing.assert_allclose(r2.after.R, np.eye(3) + DT * np.array([[0, 0, wy], [0, 0, -wx], [-wy, wx, 0]]),
                               rtol=1e-14)
    np.testing.assert_allclose(r2.after.P, [0, 0, 0.2])
    np.testing.assert_allclose(r2.after.L, [0.02, -0.03, 0.0])
    np.testing.assert_allclose(r2.points, [CORNER])              # R and x unchanged at its start


def test_printed_in_the_slides_order(recs):
    text = str(recs[0])
    order = ["Itération 1", "x(t) connu", "P(t) connu", "v(t) = P(t)/M", "②   R(t) connu", "I⁻¹(t) = R(t)·I⁻¹_body·R(t)ᵀ",
             "②   L(t) connu", "ω(t) = I⁻¹(t)·L(t)", "Ṙ(t) = ω*·R(t)", "①   F = Σ Fᵢ → dP/dt",
             "①   τ = Σ (rᵢ − x(t)) ∧ Fᵢ → dL/dt", "X(t+Δt) = X(t) + Δt·(v, ω*·R, F, τ)", "(x, R, Δt·F, Δt·τ)",
             "itération 2"]
    pos = [text.find(s) for s in order]
    assert -1 not in pos, [s for s, p in zip(order, pos) if p < 0]
    assert pos == sorted(pos)
    assert "τ = [1, -1.5, 0]" in text and "P(t+Δt) = [0, 0, 0.1]" in text
    assert "x and R move now" in str(recs[1])


def test_any_number_of_iterations_matches_simulate():
    recs = rb.walkthrough(BOX, rb.State.at_rest(), forces=[(CORNER, PUSH)], dt=DT, iterations=7)
    assert [r.index for r in recs] == list(range(1, 8))
    scene = rb.Scene(BOX, [rb.PointForce(CORNER, PUSH)])
    # the readable numpy Euler: the very same arithmetic; the float kernel: the same to rounding
    traj = rb.simulate(scene, rb.State.at_rest(), t_end=7 * DT, dt=DT, method="euler", fast=False)
    fast = rb.simulate(scene, rb.State.at_rest(), t_end=7 * DT, dt=DT, method="euler")
    for k, r in enumerate(recs):
        for name in "xRPL":
            np.testing.assert_array_equal(getattr(r.after, name), getattr(traj, name)[k + 1])
            np.testing.assert_allclose(getattr(r.after, name), getattr(fast, name)[k + 1], rtol=0, atol=1e-15)


def test_force_stays_on_its_body_point():
    R0 = rb.rotation.rotation_about([0, 0, 1], np.pi / 2)
    X0 = rb.State(x=[1, 0, 0], R=R0, P=np.zeros(3), L=np.zeros(3))
    r = np.array([1.0, 0.15, 0.025])                 # world point = x + R0 (0.15, 0, 0.025)
    recs = rb.walkthrough(BOX, X0, forces=[(r, PUSH)], dt=DT, iterations=3)
    for rec in recs:
        b = np.linalg.solve(rec.before.R, rec.points[0] - rec.before.x)
        np.testing.assert_allclose(b, [0.15, 0.0, 0.025], atol=1e-12)


@pytest.mark.parametrize("kwargs, match", [
    (dict(dt=0.0), "dt must be > 0"),
    (dict(dt=-1.0), "dt must be > 0"),
    (dict(iterations=0), "iterations must be an integer in"),
    (dict(iterations=1.5), "iterations must be an integer"),
    (dict(forces=[((0, 0, 0), (0, 0))]), "force F_i must have shape"),
])
def test_bad_walkthrough_inputs(kwargs, match):
    args = dict(forces=[(CORNER, PUSH)], dt=DT, iterations=2)
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        rb.walkthrough(BOX, rb.State.at_rest(), **args)




def _numbers(text: str) -> list[str]:
    import re
    return re.findall(r"-?\d+(?:\.\d+)?(?:e[-+]?\d+)?", text)


def test_the_two_languages_have_the_same_texts_and_placeholders():
    import string
    from rbcourse.workbook.walkthrough import TEXTS
    assert set(TEXTS) == set(rb.workbook.LANGUAGES)
    fields = {lang: {k: sorted(f for _, f, _, _ in string.Formatter().parse(v) if f) for k, v in t.items()}
              for lang, t in TEXTS.items()}
    assert fields["fr"] == fields["en"]
    assert all(TEXTS["fr"][k] != TEXTS["en"][k] for k in TEXTS["en"] if k != "head")    # translated


def test_printed_in_french_with_the_same_numbers(french):
    recs = rb.walkthrough(BOX, rb.State.at_rest(), forces=[(CORNER, PUSH)], dt=DT, iterations=2)
    fr = [str(r) for r in recs]
    from rbcourse.workbook import langue
    langue("en")
    en = [str(r) for r in recs]
    langue("fr")
    for f, e in zip(fr, en):
        assert f.count("\n") == e.count("\n")                     # line for line
        assert _numbers(f) == _numbers(e)                         # the same numbers, in the same order
    assert "force 1 : F₁ = [0, 0, 10] appliquée en r₁(t) = [0.15, 0.1, 0.025]" in fr[0]
    assert "au repos, v = 0 et ω = 0 : X(t+Δt) = (x, R, Δt·F, Δt·τ)" in fr[0]
    assert "l'objet n'a pas bougé" in fr[0] and "(état actuel de l'itération 2)" in fr[0]
    assert "x et R bougent désormais (état actuel de l'itération 3)" in fr[1]
    for text in fr:
        for english in ("at rest", " at r", "the body", "momenta", "move now", " and ", " or "):
            assert english not in text, english
    # the slide's own lines are the slide's in both languages
    for line in ("x(t) connu", "②   R(t) connu  → I⁻¹(t) = R(t)·I⁻¹_body·R(t)ᵀ", "①   F = Σ Fᵢ → dP/dt"):
        assert line in fr[0] and line in en[0]


def test_the_language_is_read_when_printed(french):
    rec = rb.walkthrough(BOX, rb.State.at_rest(), forces=[(CORNER, PUSH)], dt=DT, iterations=1)[0]
    assert "au repos" in str(rec)
    from rbcourse.workbook import langue
    langue("en")
    assert "at rest" in str(rec) and "au repos" not in str(rec)


def test_unchanged_x_and_R_said_in_both_languages(french):
    # not at rest (P ≠ 0) but Δt·v rounds to 0 (the smallest subnormal P): x and R stay as they were
    X0 = rb.State(x=np.zeros(3), R=np.eye(3), P=np.array([5e-324, 0, 0]), L=np.zeros(3))
    rec = rb.walkthrough(BOX, X0, forces=[((0, 0, 0), (0, 0, 0))], dt=DT, iterations=1)[0]
    assert "x et R n'ont pas changé" in str(rec)
    from rbcourse.workbook import langue
    langue("en")
    assert "x and R are unchanged" in str(rec)


def test_divergence_told_in_french(french):
    with pytest.raises(rb.SimulationDiverged, match=r"le parcours a divergé à l'Itération \d+ \(t = [\d.]+ s\) : .*"
                                                    r"les itérations précédentes \(\d+\) sont conservées"):
        rb.walkthrough(BOX, rb.State.at_rest(), forces=[(CORNER, (0, 0, 1e5))], dt=0.1, iterations=200)
