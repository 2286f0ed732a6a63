"""The bodies in meshcat: a still, an animation of a Trajectory, a standalone page, a live viewer.

    from rbcourse.viz import viewer
    d = viewer.draw_trajectory(traj)          # a Drawing: meshcat commands, nothing sent yet
    d                                         # in JupyterLab: the recorded animation, inline
    d.save("box.html")                        # a standalone page: works offline, loads nothing
    d.save_png("box.png", t=1.5)              # a still at t = 1.5 s, for slides (headless Chromium)
    d.show()                                  # live: this process's meshcat server (127.0.0.1 only)
    viewer.close_live_server()                # stop it (also done at exit)

In JupyterLab, a Drawing as the last expression of a cell shows the recorded animation
inline (a sandboxed iframe holding the page: no server, works with a remote kernel too; ~270 kB
for a few seconds, meshcat's script compressed; it stops rendering while out of sight; an
untrusted notebook shows a line saying what it is and what it needs).  The page's URL fragment
#t=1.5 shows that time, paused.  d.show() returns a LiveView, shown as a frame that opens the
live server's page, which the browser reaches only when it runs on the kernel's machine (the
server listens on 127.0.0.1 only); once the server is gone (kernel restarted, notebook reopened)
the frame says so.

What is drawn, all in world axes (z up, metres):
  * each body with its true shape: a box (size = full sides), a cylinder (axis = body z,
    size = (radius, height)), a sphere (size = (radius,)), any other body as the ellipsoid
    of its inertia (body.half_extents(), turned to the principal axes); its body axes
    (x red, y green, z blue);
  * arrows: ω and L from the centre of mass, each force of a PointForce from its point
    r = x + R b (tail at the point).  Each kind of arrow has its own scale: the largest
    value over the run is drawn ``arrow_length`` metres long (Drawing.arrow_scales gives
    the metres per unit);
  * optionally the trail of a body point, and a "ghost": a second trajectory (the exact
    motion, another integrator) drawn semi-transparent in another colour, over or beside;
  * a floor grid (at z = 0 or on the ground), the ground plane of a ``Ground`` effect
    (at its .height), the point of a ``Pivot``.
The camera follows the body of a one-body scene (the drawing is shifted under it), or
frames the whole motion.

The package, one concept a file: draw (draw_state, draw_trajectory: options, frames, the scene
assembled), frames (what is drawn at each frame, from the physics), parts (shapes, arrows, grid,
ground, pivot, camera), commands (meshcat commands and the animation), recording (the commands
and what they show), page (Drawing: a recording and its standalone page), assets (meshcat's script
compressed, the page's runtime: pause out of sight, notes, the LZMA decoder), still (PNG stills by
headless Chromium), live (the live server and its page).

This package is imported on demand (the physics never imports it nor meshcat).
"""
from .draw import draw_state, draw_trajectory
from .frames import DRAWABLE
from .live import LiveServer, LiveView, close_live_server, live_server, live_server_pids
from .page import Drawing
from .parts import COLORS

__all__ = ["Drawing", "draw_state", "draw_trajectory", "LiveServer", "LiveView", "live_server",
           "close_live_server", "live_server_pids", "COLORS"]
