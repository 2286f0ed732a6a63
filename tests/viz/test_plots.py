"""Drift diagnostics in one call, and the side-by-side plot."""
import numpy as np
import pytest

import rbcourse as rb
from rbcourse.viz.plots import drift, plot_drift, plot_energy_momentum
from rbcourse.workbook.examples import tennis_racket


def test_drift_of_euler_against_rk4():
    ex = tennis_racket()
    eu = rb.simulate(ex.scene, ex.X0, 2.0, 1e-3, "euler")
    k4 = rb.simulate(ex.scene, ex.X0, 2.0, 1e-3, "rk4")
    d_eu, d_k4 = drift(eu), drift(k4)
    assert set(d_eu) == {"t", "energy", "angular_momentum", "orthogonality"}
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
        [t.get_text() for ax in axes if ax.get_legend() for t in ax.get_legend().get_texts()]


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
    assert "|E − E₀| / |E₀|  (dérive de l'énergie)" in fr and "énergie (J)" in fr and "cinétique T" in fr
    assert "|L| par rapport à l'origine (kg m²/s)" in fr
    ax = plt.figure().add_subplot(projection="3d")
    momentum_sphere(ax, [3.0, 1.0, 2.0], 2.0)
    assert [t.get_text() for t in ax.texts] == ["x (plus grande inertie)", "y (plus petite inertie)", "z (intermédiaire)"]
    langue("en")
    en = _words(plot_drift([run])) + _words(plot_energy_momentum(run))
    assert "|E − E₀| / |E₀|  (energy drift)" in en and "energy (J)" in en and "kinetic T" in en
    assert not set(fr) & {"|E − E₀| / |E₀|  (energy drift)", "energy (J)", "kinetic T"}
    plt.close("all")


def test_a_diverged_run_labelled_in_french(french):
    import matplotlib.pyplot as plt
    ex = tennis_racket()
    run = rb.simulate(ex.scene, ex.X0, 20.0, 0.2, "euler", on_divergence="stop")
    assert run.diverged
    axes = plot_drift([run])
    assert axes[0].get_legend().get_texts()[0].get_text().startswith("euler (divergé à t = ")
    plt.close("all")
