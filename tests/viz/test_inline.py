"""The inline views' display bundles, without a browser: small enough to save in a notebook, a text
fallback that an untrusted notebook still shows, sandboxed and titled frames, save_png's and save_gif's checks."""
import base64
import html
import json
import re
from html.parser import HTMLParser
from pathlib import Path

import nbformat
import pytest

pytest.importorskip("meshcat", reason="the viewer needs meshcat (pip install meshcat)")

import rbcourse as rb  # noqa: E402
from rbcourse.viz import viewer  # noqa: E402
from rbcourse.viz.viewer import assets  # noqa: E402
from rbcourse.examples import pushed_box  # noqa: E402

BUDGET = 300_000          # bytes of a saved notebook per inline view (issue 14)


@pytest.fixture(scope="module")
def demo_drawing():
    """The demo's drawing of the pushed box at full length: rk4 for 5 s at dt = 1 ms, the slides' Euler beside."""
    ex = pushed_box()
    run = rb.simulate(ex.scene, ex.X0, ex.t_end, ex.dt, "rk4")
    euler = rb.simulate(ex.scene, ex.X0, ex.t_end, ex.dt, "euler", on_divergence="stop")
    return viewer.draw_trajectory(run, ghost=euler, ghost_offset=(0.0, 0.45, 0.0), ghost_label="euler",
                                  title="pushed box: rk4, dt = 0.001 s")


class Untrusted(HTMLParser):
    """What an untrusted notebook's sanitizer keeps of an output: the text, without frames, scripts, styles."""

    DROPPED = ("iframe", "script", "style")

    def __init__(self):
        super().__init__()
        self.text, self.frames, self._skip = [], [], 0

    def handle_starttag(self, tag, attrs):
        if tag == "iframe":
            self.frames.append(dict(attrs))
        if tag in self.DROPPED:
            self._skip += 1

    def handle_endtag(self, tag):
        if tag in self.DROPPED:
            self._skip -= 1

    def handle_data(self, data):
        if not self._skip:
            self.text.append(data)


def parsed(html: str) -> Untrusted:
    p = Untrusted()
    p.feed(html)
    return p


def saved_output_bytes(bundle: dict) -> int:
    """Bytes the display adds to a saved notebook (nbformat's own writer, as JupyterLab saves)."""
    empty = nbformat.writes(nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell("d")]))
    out = nbformat.v4.new_output("display_data", data=bundle)
    full = nbformat.writes(nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell("d", outputs=[out])]))
    return len(full.encode()) - len(empty.encode())


def test_a_saved_inline_view_stays_under_300_kB(demo_drawing):
    bundle = demo_drawing._repr_mimebundle_()
    size = saved_output_bytes(bundle)
    assert 150_000 < size <= BUDGET, f"the demo's inline view adds {size} bytes to a saved notebook"
    script = assets.VIEWER_JS.read_text(encoding="utf-8")
    assert script[1000:1200] not in bundle["text/html"]                 # meshcat's script is not there as text
    # ... but compressed, and it decodes to exactly meshcat's script (Python's LZMA here; the page's own
    # decoder is tested in Chromium)
    page = demo_drawing.html()
    (text, n), = re.findall(r'rbScript\("([^"]+)", (\d+)\)', page)
    assert assets.decompress(text) == assets.VIEWER_JS.read_bytes()
    assert int(n) == assets.VIEWER_JS.stat().st_size
    assert len(text) < 0.27 * int(n)                                     # LZMA in base 85: ~225 kB for 853 kB


def test_the_encoding_needs_no_escaping_in_html_javascript_or_json():
    assert len(set(assets.ALPHABET)) == 85 and all(0x21 <= ord(c) <= 0x7E for c in assets.ALPHABET)
    assert html.escape(assets.ALPHABET) == assets.ALPHABET
    assert json.dumps(assets.ALPHABET) == '"' + assets.ALPHABET + '"' and "\\" not in assets.ALPHABET
    data = bytes(range(256)) * 3 + b"rigid body" * 50 + bytes(7)           # any bytes, any length
    for chunk in (b"", b"x", data[:5], data):
        text, n = assets.compress(chunk)
        assert n == len(chunk) and set(text) <= set(assets.ALPHABET) and assets.decompress(text) == chunk
    # Python's own base 85 under the four replaced characters, and LZMA's "alone" header (lc 3, lp 0, pb 2: 93)
    raw = base64.b85decode(assets.compress(data)[0].translate(str.maketrans(",.:]", "&<>`")))
    assert raw[0] == (2 * 5 + 0) * 9 + 3 and len(raw) % 4 == 0
    with pytest.raises(ValueError, match="compress"):
        assets.decompress(assets.compress(data)[0][:-10])


def test_an_untrusted_notebook_shows_what_the_view_is_and_what_it_needs(demo_drawing):
    bundle = demo_drawing._repr_mimebundle_()
    assert set(bundle) == {"text/html", "text/plain"}
    for text in (bundle["text/plain"], " ".join(parsed(bundle["text/html"]).text)):
        assert "pushed box: rk4" in text and "an animation of 5 s" in text          # what it shows
        assert "trusted notebook" in text and "Trust Notebook" in text and "run the cell" in text
        assert "command palette (Ctrl+Shift+C, or View ▸ Activate Command Palette)" in text
    still = viewer.draw_state(rb.RigidBody.box(1.0, (0.3, 0.2, 0.05)), rb.State.at_rest(), title="X(0)")
    assert "X(0) (a still at t = 0 s)" in still._repr_mimebundle_()["text/plain"]


def test_frames_are_sandboxed_and_titled(demo_drawing):
    server_free = viewer.LiveView("http://127.0.0.1:7000/static/", token="abc_DEF-123")
    for html in (demo_drawing._repr_html_(), server_free._repr_html_()):
        frames = parsed(html).frames
        assert len(frames) == 1
        assert frames[0]["sandbox"] == "allow-scripts"                   # no allow-same-origin
        assert len(frames[0]["title"]) > 20
    assert "pushed box: rk4" in parsed(demo_drawing._repr_html_()).frames[0]["title"]
    assert "127.0.0.1:7000" in parsed(server_free._repr_html_()).frames[0]["title"]


def test_a_saved_live_view_holds_no_viewer_and_no_bare_port():
    view = viewer.LiveView("http://127.0.0.1:7000/static/", token="abc_DEF-123")
    bundle = view._repr_mimebundle_()
    assert set(bundle) == {"text/html", "text/plain"}
    assert saved_output_bytes(bundle) < 10_000                            # a probe, not a viewer
    frame = parsed(bundle["text/html"]).frames[0]
    assert "src" not in frame                                            # no frame on the port itself
    probe = frame["srcdoc"]
    assert json.dumps("http://127.0.0.1:7000/static/?token=abc_DEF-123") in probe
    assert "new WebSocket" in probe and "location.replace" in probe and "run the cell again" in probe
    text = " ".join(parsed(bundle["text/html"]).text)
    assert "live 3-D view" in text and "trusted" in text and "kernel" in text
    with pytest.raises(ValueError, match="url"):
        viewer.LiveView("127.0.0.1:7000")
    with pytest.raises(ValueError, match="token"):
        viewer.LiveView("http://127.0.0.1:7000/static/", token="a b")


def test_the_live_page_says_when_its_server_is_gone():
    from rbcourse.viz.viewer.live import GONE, live_page
    page = live_page()
    assert json.dumps(GONE) in page and "kernel restarted" in GONE and "run the cell again" in GONE
    assert '<script src="main.min.js"></script>' in page and "onclose" in page


def test_save_png_checks_its_arguments(demo_drawing, tmp_path, monkeypatch):
    lo, hi = demo_drawing.time_range
    assert (lo, hi) == (0.0, pytest.approx(5.0))
    for t in (float("nan"), float("inf"), -0.1, 5.1, "1.0", True, [1.0]):
        with pytest.raises(ValueError, match=r"t must be a finite simulated time in \[0, 5\] s"):
            demo_drawing.save_png(tmp_path / "a.png", t=t)
    for size in ((0, 100), (100,), (100.0, 100), (100, 5000), "640x480"):
        with pytest.raises(ValueError, match="size"):
            demo_drawing.save_png(tmp_path / "a.png", t=1.0, size=size)
    with pytest.raises(ValueError, match="path"):
        demo_drawing.save_png(None, t=1.0)
    with pytest.raises(ValueError, match="path"):
        demo_drawing.save_png(tmp_path / "missing" / "a.png", t=1.0)
    monkeypatch.setenv("PATH", str(tmp_path))                            # no Chromium on PATH
    with pytest.raises(RuntimeError, match="apt-get install chromium"):
        demo_drawing.save_png(tmp_path / "a.png", t=1.0)
    with pytest.raises(RuntimeError, match="not an executable"):
        demo_drawing.save_png(tmp_path / "a.png", t=1.0, chromium=tmp_path / "chromium")
    assert not (tmp_path / "a.png").exists()


def test_save_gif_checks_its_arguments(demo_drawing, tmp_path):
    for frames in (1, 201, 2.5, True):
        with pytest.raises(ValueError, match="frames"):
            demo_drawing.save_gif(tmp_path / "a.gif", frames=frames)
    with pytest.raises(ValueError, match="size"):
        demo_drawing.save_gif(tmp_path / "a.gif", size=(2000, 100))
    with pytest.raises(ValueError, match="8192"):
        demo_drawing.save_gif(tmp_path / "a.gif", frames=200, size=(1024, 1024))
    with pytest.raises(ValueError, match="path"):
        demo_drawing.save_gif(tmp_path / "missing" / "a.gif")
    still = viewer.draw_state(rb.RigidBody.box(1.0, (0.3, 0.2, 0.05)), rb.State.at_rest())
    with pytest.raises(ValueError, match="save_png"):
        still.save_gif(tmp_path / "a.gif")
    assert not (tmp_path / "a.gif").exists()


def test_a_still_has_a_one_point_range():
    body = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
    d = viewer.draw_state(body, rb.State.at_rest(), t=2.5)
    assert d.time_range == (2.5, 2.5)
    with pytest.raises(ValueError, match=r"\[2.5, 2.5\]"):
        d.save_png("x.png", t=2.6)


def test_the_trust_instruction_is_the_command_palettes_everywhere():
    """JupyterLab 4 has "Trust Notebook" in its command palette only, not in the File menu: every fallback, the
    live view's, the explorer's and the workbook's page say that path (and in French after langue("fr"))."""
    import re
    from rbcourse.viz import frame
    from rbcourse.workbook import langue
    root = Path(__file__).resolve().parents[2]
    files = [*(root / "rbcourse").rglob("*.py"), root / "README.md", *(root / "docs").glob("*.md"),
             *(root / "notebooks").rglob("*.ipynb")]
    stale = [str(f.relative_to(root)) for f in files if re.search(r"File\s*(▸|>|&gt;)\s*Trust", f.read_text("utf-8"))]
    assert not stale, f"File ▸ Trust Notebook (no such menu item in JupyterLab 4) in {stale}"
    assert "command palette (Ctrl+Shift+C, or View ▸ Activate Command Palette)" in (root / "docs" / "workbook.md").read_text("utf-8")
    live = viewer.LiveView("http://127.0.0.1:7000/static/")._repr_mimebundle_()["text/plain"]
    assert frame.TRUST["en"] in live
    langue("fr")
    try:
        assert frame.trust_hint() == frame.TRUST["fr"] and "palette de commandes" in frame.trust_hint()
    finally:
        langue("en")
