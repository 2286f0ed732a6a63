"""The notebooks' inline figures as 256-colour PNGs (rbcourse/viz/figures.py): smaller, the same picture."""
import io

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
from matplotlib.figure import Figure  # noqa: E402
from PIL import Image  # noqa: E402

from rbcourse.viz import figures  # noqa: E402


def drift_like_figure() -> bytes:
    fig = Figure(figsize=(11, 3.5), dpi=100)
    ax = fig.subplots()
    t = np.linspace(0, 10, 4000)
    for k in range(5):
        ax.semilogy(t, np.abs(np.sin(3 * t + k)) * 10.0 ** -k + 1e-12, label=f"run {k}")
    ax.legend()
    ax.set_title("energy drift")
    out = io.BytesIO()
    fig.savefig(out, format="png")
    return out.getvalue()


def test_a_figure_shrinks_and_keeps_its_picture():
    png = drift_like_figure()
    small = figures.quantised(png)
    assert len(small) < 0.6 * len(png), (len(png), len(small))
    a = np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=int)
    b = np.asarray(Image.open(io.BytesIO(small)).convert("RGB"), dtype=int)
    assert a.shape == b.shape
    assert np.mean(np.abs(a - b)) < 1.0 and np.mean(np.abs(a - b).max(-1) > 40) < 0.002


def test_a_transparent_image_is_kept_and_bad_inputs_are_named():
    out = io.BytesIO()
    Image.new("RGBA", (20, 20), (255, 0, 0, 100)).save(out, "PNG")
    assert figures.quantised(out.getvalue()) == out.getvalue()
    with pytest.raises(ValueError, match="png must be the bytes"):
        figures.quantised("not bytes")
    with pytest.raises(ValueError, match="colours"):
        figures.quantised(out.getvalue(), colours=1000)


def test_outside_ipython_nothing_is_registered():
    assert figures.register() is False


def test_outside_ipython_the_plots_do_not_import_it():
    """A script (the demo) that imports the plots does not pay for importing IPython only to learn it is not in it."""
    import subprocess
    import sys
    code = "import sys, rbcourse.viz.plots; assert 'IPython' not in sys.modules, 'IPython imported'"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                         env={**__import__("os").environ, "MPLBACKEND": "Agg"})
    assert out.returncode == 0, out.stderr


def test_in_ipython_every_figure_is_shown_quantised():
    import subprocess
    import sys
    code = ("from IPython.core.interactiveshell import InteractiveShell; sh = InteractiveShell.instance(); "
            "import rbcourse.viz.plots; from matplotlib.figure import Figure; from rbcourse.viz.figures import figure_png; "
            "f = sh.display_formatter.formatters['image/png'].lookup_by_type(Figure); assert f is figure_png, f")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                         env={**__import__("os").environ, "MPLBACKEND": "Agg"})
    assert out.returncode == 0, out.stderr
