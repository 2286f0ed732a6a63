"""Drift diagnostics in one call, and the side-by-side plot."""
import numpy as np
import pytest

import rbcourse as rb
from rbcourse.viz.plots import drift, plot_drift, plot_energy_momentum
from rbcourse.examples import tennis_racket


def test_drift_of_euler_against_rk4():
    ex = tennis_racket()
    eu = rb.simulate(ex.scene, ex.X0, 2.0, 1e-3, "euler")
    k4 = rb.simulate(ex.scene, ex.X0, 2.0, 1e-3, "rk4")
    d_eu, d_k4 = drift(eu), drift(k4)
    assert set(d_eu) == {"t", "energy", "angular_momentum", "orthogonality", "plan"}
    assert d_eu["plan"].energy_conserved and d_eu["plan"].momentum == "com"      # a free body keeps E and L
    assert d_eu["energy"][0] == 0 and d_eu["energy"][-1] > 1e-5                # the slides' Euler gains energy
    assert abs(d_k4["energy"]).max() < 1e-9
    np.testing.assert_array_equal(d_eu["angular_momentum"], 0)               # L is constant under Euler...
    assert d_eu["orthogonality"][-1] > 1e-3 > d_k4["orthogonality"].max()    # ...while R leaves SO(3)
    late = drift(eu, t_from=1.0)
    assert late["t"][0] == pytest.approx(1.0) and late["energy"][0] == 0
    with pytest.raises(ValueError, match="t_from must be within"):
        drift(eu, t_from=5.0)


def test_plots_return_axes_and_draw_one_line_per_method():
    ex = tennis_racket()
    runs = [rb.simulate(ex.scene, ex.X0, 0.5, 1e-2, m) for m in ("euler", "rk4", "splitting")]
    axes = plot_drift(runs)
    assert len(axes) == 3 and all(len(ax.lines) == 3 for ax in axes)
    assert [line.get_label() for line in axes[0].lines] == ["euler", "rk4", "splitting"]
    axes = plot_energy_momentum(runs[1])
    assert len(axes) == 2
    import matplotlib.pyplot as plt
    plt.close("all")


def test_momentum_sphere_names_the_axes_by_inertia_and_draws_the_ellipsoid():
    import matplotlib.pyplot as plt
    from rbcourse.viz.plots import momentum_sphere
    fig = plt.figure()
    ax = fig.add_subplot(projection="3d")
    assert momentum_sphere(ax, [3.0, 1.0, 2.0], 2.0, title="t") is ax
    names = [t.get_text() for t in ax.texts]
    assert names == ["x (largest inertia)", "y (least inertia)", "z (intermediate)"]
    assert len(ax.collections) == 1                                   # the sphere only
    momentum_sphere(ax, np.diag([1.0, 2.0, 3.0]), 2.0, energy=1.0)
    assert len(ax.collections) == 3                                   # + a sphere and the energy ellipsoid
    lim = ax.get_xlim()
    assert lim == pytest.approx((-2.2, 2.2))
    with pytest.raises(ValueError, match="inertia must be"):
        momentum_sphere(ax, [1.0, -1.0, 2.0], 1.0)
    with pytest.raises(ValueError, match="L_norm must be"):
        momentum_sphere(ax, [1.0, 1.0, 2.0], 0.0)
    plt.close("all")




def _words(axes):
    return [ax.get_title() for ax in axes] + [ax.get_xlabel() for ax in axes] + \
        [t.get_text() for ax in axes if ax.get_legend() for t in ax.get_legend().get_texts()] + \
        [t.get_text() for legend in axes[0].figure.legends for t in legend.get_texts()]


def test_the_plots_words_in_both_languages_have_the_same_ids_and_placeholders():
    import string
    from rbcourse.viz.plots import TEXTS
    fields = {lang: {k: sorted(f for _, f, _, _ in string.Formatter().parse(v) if f) for k, v in t.items()}
              for lang, t in TEXTS.items()}
    assert set(TEXTS) == {"en", "fr"} and fields["fr"] == fields["en"]


def test_plots_in_french_and_english_by_default(french):
    import matplotlib.pyplot as plt
    from rbcourse.viz.plots import momentum_sphere
    from rbcourse.workbook import langue
    ex = tennis_racket()
    run = rb.simulate(ex.scene, ex.X0, 0.2, 1e-2, "rk4")
    fr = _words(plot_drift([run])) + _words(plot_energy_momentum(run))
    assert "|E − E₀| / |E₀|  (dérive de l'énergie)" in fr and "énergie (J) — quantité conservée" in fr and "cinétique T" in fr
    assert "|L| au centre de masse (kg m²/s) — quantité conservée" in fr
    ax = plt.figure().add_subplot(projection="3d")
    momentum_sphere(ax, [3.0, 1.0, 2.0], 2.0)
    assert [t.get_text() for t in ax.texts] == ["x (plus grande inertie)", "y (plus petite inertie)", "z (intermédiaire)"]
    langue("en")
    en = _words(plot_drift([run])) + _words(plot_energy_momentum(run))
    assert "|E − E₀| / |E₀|  (energy drift)" in en and "energy (J) — conserved" in en and "kinetic T" in en
    assert not set(fr) & {"|E − E₀| / |E₀|  (energy drift)", "energy (J) — conserved", "kinetic T"}
    plt.close("all")


def test_a_diverged_run_labelled_in_french(french):
    import matplotlib.pyplot as plt
    ex = tennis_racket()
    run = rb.simulate(ex.scene, ex.X0, 20.0, 0.2, "euler", on_divergence="stop")
    assert run.diverged
    axes = plot_drift([run])
    assert axes[0].figure.legends[0].get_texts()[0].get_text().startswith("euler (divergé à t = ")
    plt.close("all")


def test_the_heavy_top_drifts_are_its_energy_and_L_z_about_the_pivot_not_L():
    """Gravity's torque turns L: a top keeps E and L_z about its pivot, and only those are drifts."""
    from rbcourse.examples import get_scene
    ex = get_scene("heavy_top")
    run = rb.simulate(ex.scene, ex.X0, 0.5, ex.dt, "rk4")
    d = drift(run)
    assert d["plan"].momentum == "vertical" and d["plan"].energy_conserved
    L = run.angular_momentum(ex.scene.effects[1].world_point)                # about the pivot
    assert np.linalg.norm(L[-1] - L[0]) / np.linalg.norm(L[0]) > 1e-3        # L itself turns (physics)...
    assert np.abs(d["angular_momentum"]).max() < 1e-6 and np.abs(d["energy"]).max() < 1e-6   # ...L_z and E do not
    import matplotlib.pyplot as plt
    titles = [ax.get_title() for ax in plot_drift([run])]
    assert "L_z about the pivot (0, 0, 0)" in titles[1] and "energy" in titles[0]
    plt.close("all")


def test_an_exact_zero_is_drawn_on_its_own_row_labelled_exactly_0():
    import matplotlib.pyplot as plt
    ex = tennis_racket()
    eu = rb.simulate(ex.scene, ex.X0, 0.5, 1e-2, "euler")          # Euler keeps L exactly: its drift is 0
    axes = plot_drift([eu], floor=1e-17)
    y = axes[1].lines[0].get_ydata()
    assert y == pytest.approx(np.full(len(y), 1e-19), rel=1e-12)       # below the floor, on the zero row
    labels = {t.get_text(): v for t, v in zip(axes[1].get_yticklabels(), axes[1].get_yticks())}
    assert labels["exactly 0"] == pytest.approx(1e-19)
    assert [t.get_text() for t in axes[1].texts] == ["exactly 0 throughout: euler"] and not axes[0].texts
    plt.close("all")


def test_the_legend_covers_no_curve():
    """Under the panels (02's five methods once hid their curves), for a figure made here and on given axes."""
    import matplotlib.pyplot as plt
    ex = tennis_racket()
    runs = [rb.simulate(ex.scene, ex.X0, 0.5, 1e-2, m) for m in ("euler", "euler_project", "rk4", "splitting",
                                                                 "implicit_midpoint")]
    fig, given = plt.subplots(1, 3, figsize=(13, 4.2))
    fig.subplots_adjust(bottom=0.26)
    for axes in (plot_drift(runs), plot_drift(runs, axes=given)):
        fig = axes[0].figure
        fig.canvas.draw()
        assert all(ax.get_legend() is None for ax in axes)
        box = fig.legends[0].get_window_extent()
        assert not any(box.overlaps(ax.get_window_extent()) for ax in axes)
    plt.close("all")


def test_plots_of_a_scene_that_keeps_neither_say_why_instead_of_a_curve():
    import matplotlib.pyplot as plt
    from rbcourse.examples import get_scene
    ex = get_scene("dropped_box")
    run = rb.simulate(ex.scene, ex.X0, 0.3, ex.dt, "rk4")
    d = drift(run)
    assert set(d) == {"t", "orthogonality", "plan"}
    axes = plot_drift([run])
    assert not axes[0].lines and not axes[1].lines and len(axes[2].lines) == 1
    assert "not conserved" in axes[0].texts[0].get_text() and "contacts" in axes[0].texts[0].get_text()
    plt.close("all")
