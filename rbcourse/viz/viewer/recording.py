"""A Recording: the lowered meshcat commands of a still or an animation, and what they show (duration, the
simulated times, the legend, the arrows' scales) — what the page (page.py: Drawing, a Recording with its
pages) and the live server (live.py) both read."""
from __future__ import annotations

import numpy as np

from ...support.language import current, say
from .commands import pack


class Recording:
    """What a viewer shows: lowered meshcat commands (dicts), in the order they are applied.

    commands: set_object / set_transform / set_property, then at most one set_animation.
    duration: playback length in seconds (0 for a still); t0, speed: the simulated time
    shown at playback time τ is t0 + speed·τ.  arrow_scales: metres per unit of each
    kind of arrow ("omega": m per rad/s, "L": m per kg m²/s, "force": m per N).  plots: the data of the
    plots drawn under the scene with one time cursor (a linked view: linked.panels), or None.
    """

    def __init__(self, commands, *, duration=0.0, t0=0.0, speed=1.0, title="rbcourse", legend=(),
                 arrow_scales=None, frame_times=None, plots=None):
        self.commands = list(commands)
        self.duration = float(duration)
        self.t0 = float(t0)
        self.speed = float(speed)
        self.title = str(title)
        self.legend = list(legend)
        self.arrow_scales = dict(arrow_scales or {})
        self.frame_times = None if frame_times is None else np.asarray(frame_times, dtype=float)
        self.plots = plots              # the linked view's plots under the scene (linked.panels), or None
        self.language = current()       # the language of its title, legend and page (rbcourse.support.language)

    def __repr__(self) -> str:
        kind = f"an animation of {self.duration:g} s" if self.duration else "a still"
        return f"<{type(self).__name__} {self.title!r}: {kind}, {len(self.commands)} meshcat commands>"

    @property
    def animation(self) -> dict | None:
        """The set_animation command, or None for a still."""
        return next((c for c in self.commands if c["type"] == "set_animation"), None)

    def packed(self) -> list[bytes]:
        """Each command as the msgpack bytes meshcat's viewer decodes (commands.pack: animations in float32)."""
        return [pack(c) for c in self.commands]

    @property
    def time_range(self) -> tuple[float, float]:
        """The simulated times shown: [t0, t0 + speed · duration] (s)."""
        return self.t0, self.t0 + self.speed * self.duration

    def describe(self) -> str:
        """One line: what the view shows."""
        if self.duration:
            kind = say(f"an animation of {self.duration:g} s", f"une animation de {self.duration:g} s")
        else:
            kind = say(f"a still at t = {self.t0:g} s", f"une image fixe à t = {self.t0:g} s")
        return say("3-D view: ", "vue 3-D : ") + f"{self.title} ({kind})"
