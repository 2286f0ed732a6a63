"""The accuracy explorer's page (rbcourse.viz.explorer): one standalone file that holds its runs compactly and
exactly, fetches nothing, shows inline as a sandboxed frame (a text line for an untrusted notebook), is
written whole, and stays within 5 MB.  The runs, the numbers and the rest: test_explorer.py."""
import html as _html
import re

import numpy as np
import pytest

from rbcourse.viz import explorer as xp
from rbcourse.viz import quantities
from rbcourse.viz.explorer import page, runs
from rbcourse.examples import box_on_spring, many_bodies, tennis_racket
from test_explorer import f32, page_json, racket, view_commands  # noqa: F401 (racket: the fixture)


def test_the_page_holds_its_runs_compactly_and_exactly(racket):
    data = page_json(racket.html())
    s = racket.settings
    assert [m["name"] for m in data["methods"]] == list(s.methods) and data["dts"] == list(s.dts)
    assert len(data["runs"]) == len(s.methods) * len(s.dts)
    for d, r in zip(data["runs"], racket.runs):
        assert (d["method"], d["dt"], d["steps"]) == (r.method, r.dt, r.steps)
        assert d["error"] == pytest.approx(r.error) and d["seconds"] == r.seconds
        t = f32(d["curve_t"])
        assert np.array_equal(t, r.curve_t.astype(np.float32))
        for k in quantities.KEYS:
            assert np.array_equal(f32(d["curves"][k]), r.curves[k].astype(np.float32), equal_nan=True)
        tr = d["track"]
        assert len(f32(tr["t"])) == tr["n"] and len(f32(tr["x"])) == 3 * tr["n"] and len(f32(tr["q"])) == 4 * tr["n"]
    assert [p["key"] for p in data["panels"]] == list(quantities.KEYS)
    assert all(p["ylim"][0] < p["ylim"][1] for p in data["panels"])
    assert data["reference"]["exact"] and data["reference"]["accuracy"] is None


def test_the_page_fetches_nothing():
    html = xp.explore(box_on_spring(), methods=["rk4"], dts=[0.05], t_end=0.5).html()
    low = html.lower()
    for needle in ("http://", "https://", "//cdn", "<link", "@import", "url(", "fetch(", "xmlhttprequest",
                   "<img", "<iframe", "src="):
        assert needle not in low, needle
    tags = re.findall(r"^<script[^>]*>", html, re.M)      # the data block; the viewer's runtime and plots; meshcat; ours
    assert tags == ['<script type="application/json" id="rb-data">', "<script>", "<script>", "<script>"], tags
    from rbcourse.viz.viewer.assets import TIMEPLOTS, script_tag
    assert script_tag(page.script()) in html and page.asset("explorer.css") in html
    assert TIMEPLOTS.replace("</", "<\\/") in html                  # one plotting code: the linked view's


def test_the_inline_view_is_a_sandboxed_titled_frame_holding_the_page(racket):
    from rbcourse.viz.viewer import sharing
    out = racket._repr_html_()
    assert out.count("<iframe ") == 1 and "</iframe></div><script>" in out    # then meshcat's script (sharing.py)
    assert 'sandbox="allow-scripts"' in out and "allow-same-origin" not in out
    title = re.search(r'<iframe title="([^"]+)"', out).group(1)
    assert "tennis racket" in title and "3 methods × 2 steps" in title
    srcdoc = re.search(r'srcdoc="([^"]*)"', out).group(1)
    sharing.forget()
    assert _html.unescape(srcdoc) == sharing.inline(racket.html())[0]       # the page, borrowing meshcat's script


def test_an_untrusted_notebook_keeps_a_line_saying_what_the_view_needs(racket):
    """JupyterLab sanitises untrusted HTML: frames and scripts go, text stays. What stays must say what the
    view is and what it needs; text/plain holds the runs."""
    bundle = racket._repr_mimebundle_()
    kept = re.sub(r"<iframe.*?</iframe>", "", bundle["text/html"], flags=re.S)
    text = _html.unescape(re.sub(r"<[^>]+>", "", kept))
    assert "tennis racket" in text and "trusted" in text and "explorer.save" in text
    assert bundle["text/plain"] == racket.summary() and "rk4" in bundle["text/plain"]


def test_save_writes_the_page_whole(racket, tmp_path):
    path = racket.save(tmp_path / "racket.html")
    assert path.read_text(encoding="utf-8") == racket.html()
    for bad in (tmp_path, tmp_path / "missing" / "x.html", "", 3):
        with pytest.raises(ValueError, match="path"):
            racket.save(bad)


def _size(e) -> int:
    return len(e.html().encode("utf-8"))


def test_a_4x4_page_stays_within_5_MB_one_body_and_many():
    one = xp.explore(tennis_racket(), methods=["euler", "splitting", "rk4", "exact_splitting"],
                     dts=[0.02, 0.01, 0.005, 0.0025], t_end=5.0)
    assert one.settings.frames == 300 and _size(one) < 1_000_000          # measured: 0.62 MB (0.23 MB: meshcat)
    field = xp.explore(many_bodies(), methods=["euler", "symplectic_euler", "splitting", "rk4"],
                       dts=[0.04, 0.02, 0.01, 0.005], t_end=5.0)
    assert field.settings.track_frames < field.settings.frames and _size(field) < 5_000_000   # about 3.9 MB
    data = page_json(field.html())
    assert len(data["bodies"]) == 200 and not data["show_ghost"]
    shapes = [c["path"] for c in view_commands(data) if c["type"] == "set_object"]
    assert sum(p.endswith("/shape") for p in shapes) == 200                    # the bodies, no ghost, no axes
    assert not any(p.startswith("/meshcat/ghost") or p.endswith("/axes") for p in shapes)


def test_the_largest_grid_of_one_body_stays_within_5_MB():
    e = xp.explore(tennis_racket(), methods=["euler", "symplectic_euler", "splitting", "rk4", "rkmk4",
                                             "exact_splitting"],
                   dts=[0.02, 0.0125, 0.01, 0.008, 0.005, 0.004], t_end=5.0, frames=runs.MAX_FRAMES)
    assert len(e.runs) == 36 and _size(e) < 5_000_000                       # measured: about 1.7 MB


