"""The explorer's page in a real browser (headless Chromium over the DevTools protocol, the Chromium class
of test_browser.py): the URL fragment picks the run and draws another picture, a click on the method control
changes the plotted curve, the time cursor follows the animation, clicks on a plot and on the
work-precision panel, a diverged run frozen at its last state, an unknown link value shown as a note,
nothing fetched, and the animation stopped while the view is scrolled out of sight."""
import time

import numpy as np
import pytest

from tests.viz.test_browser import CHROMIUM, Chromium  # noqa: E402

from rbcourse.viz import explore  # noqa: E402
from rbcourse.examples import pushed_box, tennis_racket  # noqa: E402

pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="chromium is not installed (apt-get install chromium): "
                                                         "the browser tests need a real browser")
SIZE = (1280, 800)


@pytest.fixture(scope="module")
def chromium():
    browser = Chromium(CHROMIUM, size=SIZE)
    yield browser
    browser.close()


@pytest.fixture(scope="module")
def explorer():
    """The pushed box: the slides' Euler diverges at dt = 0.02 s (t = 0.32 s), rk4 does not."""
    return explore(pushed_box(), methods=["euler", "rk4", "exact_splitting"], dts=[0.02, 0.005], t_end=2.0)


@pytest.fixture(scope="module")
def url(explorer, tmp_path_factory):
    return explorer.save(tmp_path_factory.mktemp("explorer") / "pushed_box.html").as_uri()


@pytest.fixture(scope="module")
def shots(tmp_path_factory):
    """Where the screenshots go (kept by pytest under its basetemp, for a look)."""
    return tmp_path_factory.mktemp("explorer_screenshots")


def load(chromium, url: str):
    """Open url afresh (about:blank first: a change of fragment alone would not reload the page)."""
    chromium.open("about:blank")
    chromium.open(url)
    assert chromium.js("!!window.rbExplorer"), "the page's script did not start"


def rect(chromium, selector: str):
    """left, top, width, height of an element (CSS px = screenshot px here)."""
    return chromium.js(f"(() => {{ const r = document.querySelector('{selector}').getBoundingClientRect(); "
                       "return [r.left, r.top, r.width, r.height]; })()")


def crop(img, box):
    x, y, w, h = (int(round(v)) for v in box)
    return img[y:y + h, x:x + w]


def click(chromium, x: float, y: float):
    for kind in ("mouseMoved", "mousePressed", "mouseReleased"):
        chromium.send("Input.dispatchMouseEvent", {"type": kind, "x": x, "y": y, "button": "left", "clickCount": 1},
                      session=chromium.session)


def still(chromium, t: float):
    chromium.js(f"rbExplorer.pause(); rbExplorer.seek({t}); true")


def state(chromium) -> dict:
    return chromium.js("rbExplorer.state()")


def amber_columns(pixels) -> np.ndarray:
    """The columns where the time cursor (#f0a000) is drawn: many amber pixels one above the other."""
    r, g, b = pixels[..., 0], pixels[..., 1], pixels[..., 2]
    amber = (r > 200) & (g > 120) & (g < 200) & (b < 70)
    return np.flatnonzero(amber.sum(axis=0) >= 20)


def test_two_fragments_draw_two_pictures_and_the_same_one_twice(chromium, url, shots):
    load(chromium, url + "#method=euler&dt=0.02")
    assert state(chromium)["method"] == "euler" and state(chromium)["dt"] == 0.02
    still(chromium, 0.25)
    euler = chromium.screenshot(shots / "euler_0.02.png")
    load(chromium, url + "#method=rk4&dt=0.005")
    s = state(chromium)
    assert (s["method"], s["dt"], s["note"]) == ("rk4", 0.005, "")
    still(chromium, 0.25)
    rk4 = chromium.screenshot(shots / "rk4_0.005.png")
    load(chromium, url + "#method=euler&dt=0.02")
    still(chromium, 0.25)
    again = chromium.screenshot(shots / "euler_0.02_again.png")
    assert np.abs(euler - again).mean() < 0.5, "the same run at the same time is not drawn the same"
    plots = rect(chromium, "#rb-plots")
    assert np.abs(crop(euler, plots) - crop(rk4, plots)).mean() > 2, "another run, the same plots"
    assert np.abs(euler - rk4).mean() > 1
    assert chromium.page_errors() == []


def test_a_click_on_the_method_control_changes_the_plotted_curve(chromium, url, shots):
    load(chromium, url + "#method=euler&dt=0.005")
    still(chromium, 0.5)
    energy = '#rb-plots canvas[data-key="energy"]'
    before = chromium.js(f"document.querySelector('{energy}').dataset.run")
    first = chromium.screenshot(shots / "before_click.png")
    x, y, w, h = rect(chromium, 'button[data-method="rk4"]')
    click(chromium, x + w / 2, y + h / 2)
    chromium.js("new Promise(r => setTimeout(r, 100))")
    after = chromium.js(f"document.querySelector('{energy}').dataset.run")
    second = chromium.screenshot(shots / "after_click.png")
    assert (before, after) == ("euler 0.005", "rk4 0.005")
    assert state(chromium)["method"] == "rk4"
    assert chromium.js('document.querySelector(\'button[data-method="rk4"]\').getAttribute("aria-pressed")') == "true"
    box = rect(chromium, energy)
    assert np.abs(crop(first, box) - crop(second, box)).mean() > 2, "the energy curve did not change"
    assert chromium.js("location.hash") == "#method=rk4&dt=0.005"        # the link follows the pick


def test_the_time_cursor_follows_the_animation(chromium, url, shots):
    load(chromium, url + "#method=rk4&dt=0.005")
    chromium.js("rbExplorer.seek(0.1); rbExplorer.play(); true")
    box = rect(chromium, '#rb-plots canvas[data-key="rotation"]')
    t1 = state(chromium)["t"]
    a = amber_columns(crop(chromium.screenshot(shots / "cursor_1.png"), box))
    time.sleep(0.8)
    t2 = state(chromium)["t"]
    b = amber_columns(crop(chromium.screenshot(shots / "cursor_2.png"), box))
    assert state(chromium)["playing"] and 0.4 < t2 - t1 < 2.0, (t1, t2)     # real time, while the page is shown
    assert a.size and b.size, "no time cursor drawn"
    assert b.mean() - a.mean() > 20, (a, b)                                  # it moved right, with the time
    # paused, it stays; where it is drawn is where the page says it is (t = 1 s: halfway along the axis)
    still(chromium, 1.0)
    c = amber_columns(crop(chromium.screenshot(shots / "cursor_paused.png"), box))
    time.sleep(0.3)
    d = amber_columns(crop(chromium.screenshot(shots / "cursor_paused_later.png"), box))
    said = chromium.js("Number(document.querySelector('#rb-plots canvas[data-key=\"rotation\"]').dataset.cursorX)")
    assert abs(c.mean() - said) <= 2 and np.array_equal(c, d)
    assert abs(said - (62 + (box[2] - 72) / 2)) <= 2                        # timeplots.js: RbPlot's M.l, M.r


def test_a_click_on_a_plot_and_the_slider_move_the_animation(chromium, url):
    load(chromium, url + "#method=rk4&dt=0.005")
    still(chromium, 0.0)
    x, y, w, h = rect(chromium, '#rb-plots canvas[data-key="energy"]')
    left, right = x + 62, x + w - 10                         # the plot's margins (viewer/js/timeplots.js: M.l, M.r)
    click(chromium, left + 0.75 * (right - left), y + h / 2)
    assert state(chromium)["t"] == pytest.approx(1.5, abs=0.03)
    chromium.js("const s = document.getElementById('rb-slider'); s.value = 250; "
                "s.dispatchEvent(new Event('input')); true")
    assert state(chromium)["t"] == pytest.approx(0.5, abs=1e-9)
    chromium.js("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
    assert chromium.js("document.getElementById('rb-t').textContent") == "t = 0.50 s"
    cursor = chromium.js("Number(document.querySelector('#rb-plots canvas[data-key=\"energy\"]').dataset.cursorX)")
    assert abs(cursor - (62 + 0.25 * (w - 72))) <= 2                  # scrubbing moved the cursor to t = 0.5 s


def test_a_click_on_the_work_precision_panel_picks_that_run(chromium, url):
    load(chromium, url + "#method=euler&dt=0.02")
    chromium.js("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
    points = chromium.js("rbExplorer.points()")
    assert len(points) == 6
    p = next(p for p in points if p["method"] == "exact_splitting" and p["dt"] == 0.005)
    click(chromium, p["x"], p["y"])
    s = state(chromium)
    assert (s["method"], s["dt"]) == ("exact_splitting", 0.005)
    selected = "document.getElementById('rb-wp').dataset.selected"
    deadline = time.monotonic() + 5.0                       # the panel redraws at its next animation frame
    while chromium.js(selected) != "exact_splitting 0.005" and time.monotonic() < deadline:
        time.sleep(0.05)
    assert chromium.js(selected) == "exact_splitting 0.005"


def test_a_diverged_run_stops_at_its_last_state_and_says_why(chromium, url, explorer, shots):
    run = explorer.run("euler", 0.02)
    assert run.diverged
    load(chromium, url + "#method=euler&dt=0.02")
    chromium.js("document.getElementById('rb-ghost').click(); true")          # the ghost off: the run alone
    assert not chromium.js("document.getElementById('rb-ghost').checked")
    view = rect(chromium, "#meshcat-pane")
    centre = (view[0] + 0.1 * view[2], view[1] + 0.2 * view[3], 0.8 * view[2], 0.7 * view[3])   # below the labels
    still(chromium, 1.2)
    a = crop(chromium.screenshot(shots / "diverged_1.2.png"), centre)
    still(chromium, 1.8)
    b = crop(chromium.screenshot(shots / "diverged_1.8.png"), centre)
    assert np.abs(a - b).mean() < 0.5, "a diverged run must stay at its last drawable state"
    warning = chromium.js("(() => { const w = document.getElementById('rb-view-warning'); "
                          "return w.hidden ? '' : w.textContent; })()")
    assert "diverged at t = 0.32 s" in warning and "overflow" in warning
    status = chromium.js("document.getElementById('rb-status').textContent")
    assert "diverged" in status and run.reason in status
    # rk4 at the same step keeps moving between the same two instants
    chromium.js("rbExplorer.select('rk4', 0.02); true")
    still(chromium, 1.2)
    c = crop(chromium.screenshot(shots / "rk4_1.2.png"), centre)
    still(chromium, 1.8)
    d = crop(chromium.screenshot(shots / "rk4_1.8.png"), centre)
    assert np.abs(c - d).mean() > 1


def test_an_unknown_value_in_the_link_falls_back_to_the_default_with_a_note(chromium, url):
    load(chromium, url + "#method=verlet&dt=0.003")
    s = state(chromium)
    assert (s["method"], s["dt"]) == ("rk4", 0.02)                  # the page's default run
    note = chromium.js("(() => { const n = document.getElementById('rb-note'); "
                       "return [n.hidden, n.offsetHeight, n.textContent]; })()")
    assert note[0] is False and note[1] > 10, note
    assert "verlet" in note[2] and "0.003" in note[2] and "default" in note[2]
    load(chromium, url + "#dt=0.005")                                 # one key left out: the default for it
    s = state(chromium)
    assert (s["method"], s["dt"], s["note"]) == ("rk4", 0.005, "")
    assert chromium.js("document.getElementById('rb-note').hidden") is True
    chromium.js("location.hash = '#method=euler&dt=0.02'; new Promise(r => setTimeout(r, 100))")   # hashchange
    s = state(chromium)
    assert (s["method"], s["dt"]) == ("euler", 0.02)


def test_the_page_fetches_nothing(chromium, url):
    load(chromium, url + "#method=rk4&dt=0.005")
    chromium.js("rbExplorer.select('exact_splitting', 0.02); rbExplorer.play(); "
                "new Promise(r => setTimeout(r, 500))")
    requests = chromium.requests()
    assert requests and requests[0].startswith(url.split("#")[0])
    assert all(u.startswith(("file:", "data:")) for u in requests), requests
    assert chromium.page_errors() == []


def test_the_animation_stops_while_the_view_is_scrolled_away(chromium, explorer, tmp_path):
    """In a notebook the page sits in an iframe: out of sight, it requests no animation frames."""
    frame = explorer._repr_html_().replace(' sandbox="allow-scripts"', "")      # same-origin: the test may look in
    parent = tmp_path / "notebook.html"
    parent.write_text(f"<!DOCTYPE html><html><body style='margin:0'>{frame}<div style='height:4000px'></div>"
                      "</body></html>", encoding="utf-8")
    chromium.open("about:blank")
    chromium.open(parent.as_uri())
    inner = "document.querySelector('iframe').contentWindow.rbExplorer"
    deadline = time.monotonic() + 10
    while not chromium.js(f"!!{inner}") and time.monotonic() < deadline:
        time.sleep(0.1)

    def frames_in(seconds: float) -> int:
        f0 = chromium.js(f"{inner}.frames")
        time.sleep(seconds)
        return chromium.js(f"{inner}.frames") - f0
    assert chromium.js(f"{inner}.state().playing")
    assert frames_in(0.5) > 5, "the animation does not run in view"
    chromium.js("window.scrollTo(0, 3000); new Promise(r => setTimeout(r, 300))")
    assert not chromium.js(f"{inner}.state().onscreen")
    assert frames_in(0.5) <= 1, "the animation keeps drawing out of sight"
    chromium.js("window.scrollTo(0, 0); new Promise(r => setTimeout(r, 300))")
    assert frames_in(0.5) > 5, "the animation does not resume"


def test_the_inline_frame_runs_the_page_in_its_sandbox(chromium, tmp_path, shots):
    inline = explore(tennis_racket(), methods=["rk4"], dts=[0.02], t_end=1.0)     # a fixed camera: always in view
    parent = tmp_path / "inline.html"
    parent.write_text(f"<!DOCTYPE html><html><body style='margin:0'>{inline._repr_html_()}</body></html>",
                      encoding="utf-8")
    chromium.open("about:blank")
    chromium.open(parent.as_uri())
    box = rect(chromium, "iframe")
    deadline, drawn = time.monotonic() + 15, 0
    while drawn <= 500 and time.monotonic() < deadline:            # the frame loads and draws on its own
        time.sleep(0.3)
        r, g, b = (crop(chromium.screenshot(shots / "inline.png"), box)[..., k] for k in range(3))
        drawn = int(((r > 110) & (r - b > 70) & (g > b) & (r > g)).sum())   # the box's orange, lit or shaded
    assert drawn > 500, "the sandboxed frame drew no body"
    assert chromium.js("document.querySelector('iframe').getAttribute('sandbox')") == "allow-scripts"
    assert chromium.js("document.querySelector('iframe').title").startswith("rbcourse accuracy explorer")
