"""The accuracy explorer: a grid of methods × time steps, run, timed and measured, on one self-contained
page — pick a method and a step, watch the body and its drift together, with no kernel and no server.

    import rbcourse as rb
    from rbcourse.viz import explore
    from rbcourse.examples import pushed_box

    ex = explore(pushed_box(), methods=["euler", "splitting", "rk4", "exact_splitting"],
                 dts=[0.02, 0.01, 0.005, 0.0025], t_end=5.0)       # an Example: its X0, drift_from, name
    ex = explore(scene, X0, methods=[...], dts=[...], t_end=5.0)   # or any Scene / RigidBody and its X0
    ex                      # in a notebook: the page inline (an iframe, sandbox="allow-scripts", with a title)
    ex.save("box.html")     # one HTML file, works offline, fetches nothing (about 0.5-0.65 MB for 4 × 4, one body:
                            0.23 MB of it meshcat's viewer script, compressed)
    ex.html()               # the same page as a string
    ex.runs                 # the runs: .method .dt .steps .seconds .error (rad at t_end) .diverged .reason ...
    ex.run("rk4", 0.005); ex.fragment("rk4", 0.005)   # one run; '#method=rk4&dt=0.005', the link that opens it
    print(ex.summary())     # the runs as text

explore(scene, X0=None, *, methods=None, dts=None, t_end=None, drift_from=None, frames=None, default=None,
        name=None, description=None, progress=False) -> Explorer

    scene       a Scene, a RigidBody (a free body), or an Example of rbcourse.examples (then X0,
                t_end, drift_from, name and description default to its own, and dts to its dt × 20, 10, 5, 2.5)
    X0          the initial State (one body, or N bodies stacked)
    methods     names in rb.METHODS, at most MAX_METHODS = 6 (default: euler, splitting, rk4, exact_splitting)
    dts         time steps (s, finite, > 0, <= t_end, distinct step counts), at most MAX_DTS = 6 (default
                0.02, 0.01, 0.005, 0.0025 for a bare scene); each run takes n = round(t_end / dt) steps
                of t_end / n, and steps × bodies <= MAX_STEPS = 10⁶ per run
    t_end       duration (s, > 0; default 5 s for a bare scene)
    drift_from  drifts are measured from this time on (a push that is over by then: the Example's)
    frames      points per curve and animation frames, MIN_FRAMES = 30 … MAX_FRAMES = 1000 (default 60 per
                second, within 200 … 600); with many bodies the animation keeps fewer frames, so that
                frames × bodies × (runs + 1) <= MAX_BODY_FRAMES = 120 000 (a ValueError below 30)
    default     (method, dt): the run shown first, and when a link names none or an unknown one
                (default: rk4 if it is in the grid, else the first method; the first dt)
    progress    a progress bar over the runs

What it does (runs.py): one untimed warm-up run per method (numba compiles a method's step at its first
run), then every run timed with time.perf_counter around rb.simulate(..., on_divergence="stop"), and
measured at each of its steps against the reference at the same times (reference.py: the exact torque-free
motion for a scene with no effect, else rk4 with steps 8× finer than the finest of the grid, whose own
accuracy the page states).  What is plotted depends on what the scene conserves (viz/quantities.py): energy
and angular-momentum drift where the physics keeps them, errors against the reference where it does not,
‖RᵀR − I‖, and the rotation error against the reference.  The page (page.py with data.py,
view.py, text.py; the script in js/, explorer.css; explorer.py the Explorer):
method and step buttons; the bodies in meshcat's three.js scene (the viewer's script and pieces: view.py makes
the scene's objects, js/scene.js moves them from the page's time cursor), the reference as a ghost, the body
axes, springs and pivots; the four plots (the linked view's plotting code, viewer/js/timeplots.js: the chosen run,
the method's other steps in pale) with a time cursor that follows the animation (click or drag a plot to jump
there), play/pause, a time slider, a work-precision panel (wall time vs rotation error at t_end, log-log; click a
point to pick that run), a run that diverged marked where it stopped and why; the URL fragment #method=…&dt=…
selects a run (either key may be left out; an unknown value falls back to the default with a visible note), kept
updated (history.replaceState) and followed (hashchange); #…&t=1.5 opens it at that time, paused.  The animation
runs on requestAnimationFrame and stops while the page is hidden or scrolled out of view.

Command line: python -m rbcourse explore [scene] [--methods ...] [--dts ...] [--t-end T] [--out DIR]
writes DIR/SCENE_explorer.html.
"""
from __future__ import annotations

from .explorer import Explorer
from .runs import (DEFAULT_METHODS, MAX_BODY_FRAMES, MAX_DTS, MAX_FRAMES, MAX_METHODS, MAX_STEPS, MIN_FRAMES,
                   check_arguments, run_grid)

__all__ = ["explore", "Explorer", "check_arguments", "DEFAULT_METHODS", "MAX_METHODS", "MAX_DTS", "MAX_STEPS",
           "MAX_FRAMES", "MIN_FRAMES", "MAX_BODY_FRAMES"]


def explore(scene, X0=None, *, methods=None, dts=None, t_end=None, drift_from=None, frames=None, default=None,
            name=None, description=None, progress: bool = False) -> Explorer:
    """Run every method × every step on the scene and build its explorer page (module docstring).
    Every argument is checked before anything is computed (a ValueError names the first bad one)."""
    settings = check_arguments(scene, X0, methods=methods, dts=dts, t_end=t_end, drift_from=drift_from,
                               frames=frames, default=default, name=name, description=description)
    if not isinstance(progress, bool):
        raise ValueError(f"progress must be True or False, got {progress!r}")
    return Explorer(run_grid(settings, progress=progress))
