"""Inline views, stills and the live view in headless Chromium: the inline frame draws the box from its
compressed page and fetches nothing, meshcat's controls stay reachable in it, a view out of sight stops
requesting animation frames and resumes where it was, the page shows a time given in its URL, save_png
draws the box at two times, and the live view says when its server is gone."""
import html
import subprocess
import time

import numpy as np
import pytest

pytest.importorskip("meshcat", reason="the viewer needs meshcat (pip install meshcat)")
from PIL import Image  # noqa: E402  (comes with meshcat)

import rbcourse as rb  # noqa: E402
from rbcourse.viz import viewer  # noqa: E402
from rbcourse.viz.viewer.live import GONE, UNREACHABLE  # noqa: E402
from rbcourse.examples import pushed_box  # noqa: E402
from tests.viz.chromium import CHROMIUM, SKIP_REASON, Chromium  # noqa: E402
from tests.viz.test_browser import orange  # noqa: E402

pytestmark = pytest.mark.skipif(CHROMIUM is None, reason=SKIP_REASON)


@pytest.fixture(scope="module")
def chromium():
    browser = Chromium(CHROMIUM)
    yield browser
    browser.close()


@pytest.fixture(scope="module")
def drawing():
    ex = pushed_box()
    traj = rb.simulate(ex.scene, ex.X0, t_end=3.0, dt=0.01, method="rk4")
    return viewer.draw_trajectory(traj, title="pushed box under test")


def notebook_page(tmp_path, body: str, name="notebook.html"):
    """A test page standing for a notebook: outputs one under the other, then room to scroll them away."""
    path = tmp_path / name
    path.write_text(f'<!DOCTYPE html><html><head><meta charset="utf-8"></head><body style="margin:0">{body}'
                    f'<div id="below" style="height:3000px"></div></body></html>', encoding="utf-8")
    return path


def wait_for(check, timeout=20.0, step=0.1):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = check()
        if value:
            return value
        time.sleep(step)
    raise AssertionError(f"timed out waiting for {check}")


def test_the_inline_view_draws_the_box_and_its_controls_fit(chromium, drawing, tmp_path):
    page = notebook_page(tmp_path, drawing._repr_html_())
    chromium.open(page.as_uri())
    frame = chromium.frame_session()
    wait_for(lambda: chromium.frame_js("!!(window.viewer && viewer.animator.actions.length)", frame))
    attrs = chromium.js("(() => { const f = document.querySelector('iframe'); "
                        "return [f.getAttribute('sandbox'), f.title, f.getBoundingClientRect().height]; })()")
    assert attrs[0] == "allow-scripts" and "pushed box under test" in attrs[1] and attrs[2] == 420
    assert chromium.frame_js("window.origin") == "null"                      # its own opaque origin
    chromium.frame_js("viewer.animator.pause(); viewer.animator.seek(1.0); true", frame)
    img = chromium.screenshot(tmp_path / "inline.png")
    assert orange(img[:420]).sum() > 1500, "no box in the inline frame"
    assert orange(img[420:]).sum() == 0
    # meshcat's controls: open them; "Close Controls" lies inside the 420 px frame, every folder is reachable
    chromium.frame_js("document.querySelector('.dg.main .close-button').click(); true", frame)
    chromium.pump(0.3)
    box = chromium.frame_js("(() => { const b = document.querySelector('.dg.main .close-button'); "
                            "const r = b.getBoundingClientRect(); "
                            "const hit = document.elementFromPoint((r.left + r.right) / 2, (r.top + r.bottom) / 2); "
                            "return [b.textContent, r.top, r.bottom, innerHeight, hit === b]; })()", frame)
    assert box[0] == "Close Controls" and 0 <= box[1] < box[2] <= box[3] == 420 and box[4], box
    panel = chromium.frame_js("(() => { const u = document.querySelector('.dg.main > ul'); "
                              "return [u.scrollHeight, u.clientHeight]; })()", frame)
    assert panel[0] > panel[1], "the open panel fits without scrolling: this test would not test the scroll"
    rec = chromium.frame_js("(() => { const t = [...document.querySelectorAll('.dg li.title')]"
                            ".find(e => e.textContent === 'Recording'); const u = document.querySelector('.dg.main > ul'); "
                            "u.scrollTop = u.scrollHeight; const r = t.getBoundingClientRect(); "
                            "return [r.top, r.bottom, document.elementFromPoint(r.left + 20, (r.top + r.bottom) / 2) === t]; })()",
                            frame)
    assert 0 <= rec[0] < rec[1] <= 420 and rec[2], rec
    assert chromium.js("scrollY") == 0
    chromium.screenshot(tmp_path / "inline_controls.png")
    chromium.frame_js("document.querySelector('.dg.main .close-button').click(); true", frame)
    assert chromium.frame_js("document.querySelector('.dg.main .close-button').textContent", frame) == "Open Controls"
    # nothing fetched: the test page, then nothing but inline data (meshcat's own textures)
    assert chromium.requests()[0] == page.as_uri()
    assert all(u.startswith("data:") for u in chromium.requests()[1:]), chromium.requests()
    assert chromium.page_errors() == []


def test_a_view_out_of_sight_stops_requesting_frames_and_resumes_where_it_was(chromium, drawing, tmp_path):
    # two embeddings: the inline view (sandboxed), and the same page in a same-origin frame (as
    # JupyterLab showed it before), which the browser itself never throttles: only the page's code can
    # stop its frames
    same = (f'<div style="height:420px"><iframe id="same" title="same origin" srcdoc="{html.escape(drawing.html())}" '
            f'style="width:100%;height:100%;border:none"></iframe></div>')
    page = notebook_page(tmp_path, same + drawing._repr_html_(), "two_views.html")
    chromium.open(page.as_uri())
    frame = chromium.frame_session()
    wait_for(lambda: chromium.js("!!(document.getElementById('same').contentWindow.viewer"
                                 " && document.getElementById('same').contentWindow.viewer.animator.actions.length)"))
    wait_for(lambda: chromium.frame_js("!!(window.viewer && viewer.animator.actions.length)", frame))
    same_view = "document.getElementById('same').contentWindow"

    def growth(seconds=1.0):
        chromium.pump(0.3)                                               # let the change take effect
        a = chromium.js(f"{same_view}.rbView.callbacks")
        b = chromium.frame_js("rbView.callbacks", frame)
        chromium.pump(seconds)
        return chromium.js(f"{same_view}.rbView.callbacks") - a, chromium.frame_js("rbView.callbacks", frame) - b

    def paused():
        return chromium.js(f"{same_view}.rbView.paused"), chromium.frame_js("rbView.paused", frame)

    def tau():
        return chromium.js(f"{same_view}.viewer.animator.actions.reduce((m, a) => Math.max(m, a.time), 0)")

    grown = growth()
    assert min(grown) > 5 and paused() == (False, False), grown                 # both render (~2 callbacks a frame)
    chromium.js(f"{same_view}.viewer.animator.seek(0.2); true")
    before = tau()
    chromium.js("window.scrollTo(0, 1500); true")                           # both scrolled out of the window
    assert growth(1.5) == (0, 0) and paused() == (True, True)
    chromium.js("window.scrollTo(0, 0); true")
    chromium.pump(0.2)
    after = tau()
    assert 0 < after - before < 1.2, (before, after)         # it goes on from where it was, not 1.8 s further on
    assert min(growth()) > 5 and paused() == (False, False)
    chromium.js("document.querySelectorAll('iframe').forEach(f => f.parentElement.style.display = 'none'); true")
    assert growth() == (0, 0) and paused() == (True, True)
    chromium.js("document.querySelectorAll('iframe').forEach(f => f.parentElement.style.display = ''); true")
    assert min(growth()) > 5 and paused() == (False, False)
    # the tab hidden (visibilitychange): shown by the page's document.hidden
    chromium.js(f"Object.defineProperty({same_view}.document, 'hidden', {{get: () => true, configurable: true}}); "
                f"{same_view}.document.dispatchEvent(new Event('visibilitychange')); true")
    assert growth()[0] == 0 and paused()[0] is True
    chromium.js(f"delete {same_view}.document.hidden; "
                f"{same_view}.document.dispatchEvent(new Event('visibilitychange')); true")
    assert growth()[0] > 5 and paused()[0] is False
    assert chromium.page_errors() == []


def test_the_page_shows_the_time_its_url_asks_for(chromium, drawing, tmp_path):
    path = drawing.save(tmp_path / "box.html")
    chromium.open(path.as_uri() + "#t=1.25")
    state = chromium.js("[viewer.animator.playing, viewer.animator.actions[0].time, "
                        "document.getElementById('rb-time').textContent, document.getElementById('rb-note').hidden, "
                        "viewer.animator.time]")
    assert state[0] is False and state[1] == pytest.approx(1.25) and state[2] == "t = 1.25 s" and state[3]
    assert state[4] == pytest.approx(1.25)                                    # meshcat's time slider says so too
    chromium.js("location.hash = 't=7&controls=hidden'; true")
    chromium.pump(0.3)
    note = chromium.js("[document.getElementById('rb-note').hidden, document.getElementById('rb-note').textContent, "
                       "viewer.gui.domElement.style.display]")
    assert note[0] is False and "t must be a time in [0, 3] s" in note[1] and note[2] == "none"


def test_save_png_draws_the_box_at_the_time_asked(drawing, tmp_path):
    def chromium_pids():
        out = subprocess.run(["pgrep", "-f", "rbcourse-still-"], capture_output=True, text=True).stdout
        return set(out.split())

    assert drawing.save_png(tmp_path / "early.png", t=0.5, size=(640, 400)) == tmp_path / "early.png"
    drawing.save_png(tmp_path / "late.png", t=2.5, size=(640, 400))
    early = np.asarray(Image.open(tmp_path / "early.png").convert("RGB")).astype(int)
    late = np.asarray(Image.open(tmp_path / "late.png").convert("RGB")).astype(int)
    assert early.shape == late.shape == (400, 640, 3)
    assert orange(early).sum() > 1000 and orange(late).sum() > 1000          # the box is there, not a blank page
    assert np.abs(early - late).mean() > 2.0                                   # and it has moved
    assert not (early == early[0, 0]).all(axis=-1).all()
    assert chromium_pids() == set()                                            # no Chromium left running


def test_save_gif_plays_the_animation(drawing, tmp_path):
    path = drawing.save_gif(tmp_path / "clip.gif", frames=6, size=(320, 200))
    with Image.open(path) as gif:
        assert gif.n_frames == 6 and gif.size == (320, 200) and gif.info["loop"] == 0
        assert gif.info["duration"] == round(1000 * 3.0 / 5)                   # real time: 3 s over 5 steps
        frames = []
        for i in range(gif.n_frames):
            gif.seek(i)
            frames.append(np.asarray(gif.convert("RGB")).astype(int))
    assert all(orange(f).sum() > 200 for f in frames)                           # the box in every frame
    assert all(np.abs(a - b).mean() > 1.0 for a, b in zip(frames, frames[1:]))  # moving from frame to frame
    # each frame is the still at its time (the label aside): the first at t = 0, the last at t = 3 s
    drawing.save_png(tmp_path / "end.png", t=3.0, size=(320, 200))
    end = np.asarray(Image.open(tmp_path / "end.png").convert("RGB")).astype(int)
    body = orange(end)
    assert body.sum() > 200 and (orange(frames[-1]) == body).mean() > 0.99


def test_the_live_view_says_when_its_server_is_gone(chromium, drawing, tmp_path):
    try:
        view = drawing.show()
        page = notebook_page(tmp_path, view._repr_html_(), "live.html")
        chromium.open(page.as_uri())
        frame = chromium.frame_session()
        wait_for(lambda: chromium.frame_js("window.rbLive === 'open' && viewer.animator.actions.length > 0", frame))
        assert chromium.frame_js("location.href", frame) == view.frame_url
        assert chromium.frame_js("document.getElementById('rb-note').hidden", frame) is True
        # a wrong token is refused: a sandboxed frame (origin "null") gets the scene only with the server's token
        wrong = viewer.LiveView(view.url, token="not-the-token")
        chromium.open(notebook_page(tmp_path, wrong._repr_html_(), "wrong.html").as_uri())
        frame = chromium.frame_session()
        wait_for(lambda: UNREACHABLE in chromium.frame_js("document.body.textContent", frame))
        # the server stops (the kernel restarts): the open view says so
        chromium.open(page.as_uri())
        frame = chromium.frame_session()
        wait_for(lambda: chromium.frame_js("window.rbLive === 'open'", frame))
        viewer.close_live_server()
        wait_for(lambda: chromium.frame_js("window.rbLive === 'closed'", frame))
        note = chromium.frame_js("[document.getElementById('rb-note').hidden, "
                                 "document.getElementById('rb-note').textContent]", frame)
        assert note == [False, GONE]
        img = chromium.screenshot(tmp_path / "live_gone.png")
        red = (img[:420, :, 0] > 130) & (img[:420, :, 1] < 60) & (img[:420, :, 2] < 60)
        assert red.sum() > 5000, "the note is not visible"
        # the saved output, opened again later: no broken frame on a dead port, but the same message
        chromium.open(page.as_uri())
        frame = chromium.frame_session()
        wait_for(lambda: UNREACHABLE in chromium.frame_js("document.body.textContent", frame))
        assert not any(u.startswith("http://127.0.0.1") for u in chromium.requests())   # it never loaded the page
    finally:
        viewer.close_live_server()
