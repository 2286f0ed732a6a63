"""Contact with the ground, the plane z = height (Baraff 2001, notes part II, "Nonpenetration constraints").

A scene asks its Ground once, when it is built, for the contact points of the bodies it acts on
(``Ground.prepare``: ``ContactPoints``), and lays them out as the kernel's data (``Ground.ground_rows``); the
kernel solves the contacts after each step, inside its compiled loop (engine/run.py, engine/contact.py:
contacts).  ``Ground.resolve`` solves one step's contacts from Python.  Contact points r: a box's 8 corners, 4 points
on each rim of a cylinder, the lowest point of a sphere (or of the ellipsoid of the same inertia).
With n = (0, 0, 1), ρ = r − x, v_rel = n·(v + ω × ρ), a point is in contact if it is below the
plane or would get there within Δt.

* colliding contact, v_rel⁻ < −ε: an impulse j n with v_rel⁺ = −e v_rel⁻, for one point
      j = −(1 + e) v_rel⁻ / (1/M + n·(I⁻¹(ρ × n)) × ρ);
  slower (resting) contacts get v_rel⁺ = 0, or what just reaches the plane in Δt: no bounce, no
  jitter.  ε = 0.01 m/s + 2 g Δt, a bit more than gravity gives a resting contact in one step.
* Coulomb friction: a point sticks if |j_t| <= μ j_n can stop it, else slides with j_t = −μ j_n s.
* Several points at once (a box landing flat has 4): one small linear system per body for the
  points' modes (off, sticking, sliding along s), solved (least squares, least norm: singular with
  more than 6 equations; through the body's 6 velocities, two 6×6 solves), the modes corrected,
  solved again; the rare body whose modes do not settle finishes by projected Gauss–Seidel sweeps.
* Position: penetrating points are lifted out by a pseudo-impulse with the same response (a box
  pivoting on an edge turns about it), so bodies never sink; energy this would still add is taken
  from the body's kinetic energy: contact never creates energy (so also no Kane's paradox).

The solver is written once, per body, in the engine: engine/contact.py (compiled with numba, or run as
Python without it); this module holds the effect, its parameters, and the bodies' contact points as data.
Pivoted bodies are refused (ValueError when the scene is built): leave them out with ``body=``.
"""
from __future__ import annotations

import numpy as np

from .support import checks
from .effects import Effect, Gravity, body_selection
from .engine.system import GroundRows
from .state import from_matrix, to_matrix
from .support.language import say

SHAPE_CODES = {"box": 0, "cylinder": 1, "ellipsoid": 2}   # engine/contact.py: BOX, CYLINDER, ELLIPSOID
MAX_HEIGHT = 1e8          # m: |height| at most this; there float64 resolves a height to ε (|z| + |height|) <= 4.4e-8 m,
                          # under a tenth of the contact tolerance CONTACT_TOL = 1e-6 m (at 1e15 m: 0.44 m)
EPS = float(np.finfo(float).eps)    # 2.2e-16
ROUNDING_SHARE = 0.1      # the start check's rounding may be at most this share of CONTACT_TOL (Ground.check_start)


def _param(name: str, value, low: float, high: float, allowed: str) -> float:
    try:
        if low <= checks.real(name, value) <= high:
            return float(value)
    except ValueError:
        pass
    raise ValueError(f"{name} must be {allowed}, got {value!r}")


class Ground(Effect):
    """The horizontal plane z = height: colliding and resting contact, Coulomb friction.

    height within ±MAX_HEIGHT = 1e8 m (the contact tolerance, 1e-6 m, is resolved there: float64 rounds a
    height near 1e8 m to 1.5e-8 m; near 1e15 m, to 0.125 m); restitution e in [0, 1] (0: no bounce, 1: elastic);
    friction μ >= 0 (0: frictionless).
    """
    kind = "contact"

    def __init__(self, height=0.0, restitution=0.5, friction=0.5, *, body=None):
        self.height = _param("height", height, -MAX_HEIGHT, MAX_HEIGHT,
                             f"a real number within ±{MAX_HEIGHT:g} m (where the contact tolerance, 1e-6 m, is "
                             f"resolved by float64)")
        self.restitution = _param("restitution", restitution, 0.0, 1.0, "a real number in [0, 1]")
        self.friction = _param("friction", friction, 0.0, np.inf, "a finite real number >= 0")
        self.body = body_selection(body)

    def describe(self):
        return say(f"a ground plane z = {self.height:g} m (restitution e = {self.restitution:g}, friction "
                   f"μ = {self.friction:g}): collisions by impulses, resting contact, no sinking",
                   f"un sol plan z = {self.height:g} m (restitution e = {self.restitution:g}, frottement "
                   f"μ = {self.friction:g}) : chocs par impulsions, contact au repos, sans enfoncement")

    def __repr__(self):
        return f"Ground(height={self.height:g}, restitution={self.restitution:g}, friction={self.friction:g})"

    def check_start(self, X, geo: "ContactPoints"):
        """Refuse a start with a body below the plane (the solver would lift it out at the first step: a jump
        nobody asked for): ValueError naming X0, the body, its depth and the height, if the lowest contact
        point of a body this Ground acts on is below z = height by more than the tolerance.

        X: the start over the scene's N bodies (scene.batch(X0): x the centres of mass); geo: prepare's
        ContactPoints.  The lowest point is engine/contact_points.py's lowest_gap, run as Python (the solver's
        own contact points: a box's corners, a cylinder's rim points, an ellipsoid's or a sphere's lowest
        point; a body with no shape is the ellipsoid of its inertia).  Tolerance: the engine's CONTACT_TOL
        (1e-6 m: what the solver counts as touching), whatever the coordinates: a body resting on the plane, its
        lowest point at z = height, is accepted, one 2e-6 m below is not.  The gap z + ρ_z − height is computed to
        within b = ε (|z| + |height| + 16 |half|) (float64 rounding, ε = 2.2e-16: each sum to ε/2 of its size,
        ρ_z to a few ε of the body's size |half|).  Where b <= ROUNDING_SHARE × CONTACT_TOL = 1e-7 m (every small
        body on a Ground within ±MAX_HEIGHT), the computed gap is compared with −CONTACT_TOL; where b is larger
        (a body of 10⁷ m and more, or z beyond 10⁸ m), a body surely below (gap < −CONTACT_TOL − b) is refused as
        below, and one the rounding cannot place (|gap| <= CONTACT_TOL + b) is refused naming X0 and the range."""
        h = self.height
        z = X.x[geo.rows, 2]
        with np.errstate(over="ignore"):
            rounding = EPS * (np.abs(z) + abs(h) + 16.0 * geo.reach)
        near = np.flatnonzero(~(z - geo.reach - rounding >= h))     # the others' points are all above the plane
        if not near.size:
            return
        from .engine import interpreted
        lowest_gap = interpreted.module("contact_points").lowest_gap
        tol = interpreted.module("contact").CONTACT_TOL
        for k, i, z_k, b in zip(near.tolist(), geo.rows[near].tolist(), z[near].tolist(), rounding[near].tolist()):
            half = geo.half[k].tolist()
            gap = lowest_gap(int(geo.shape[k]), X.R[i].tolist(), half, geo.axes[k].tolist(), z_k, h)
            resolved = b <= ROUNDING_SHARE * tol
            if gap < -tol - (0.0 if resolved else b):
                raise ValueError(f"X0 puts body {i} {-gap:.6g} m below the ground z = {h:g} (its lowest point at "
                                 f"z = {h + gap:.6g}): start every body on or above it (within {tol:g} m)")
            if not resolved and gap <= tol + b:
                raise ValueError(f"X0 puts body {i} (at z = {z_k:.6g} m, of size |half| = {geo.reach[k]:.3g} m) "
                                 f"within {tol + b:.3g} m of the ground z = {h:g}, where float64 places its lowest "
                                 f"point to ±{b:.2g} m only: the start is checked to {tol:g} m where "
                                 f"ε (|z| + |height| + 16 |half|) <= {ROUNDING_SHARE * tol:g} m (ε = {EPS:.3g}): "
                                 f"|z| + |height| + 16 |half| within {ROUNDING_SHARE * tol / EPS:.3g} m")

    def prepare(self, scene, idx) -> "ContactPoints":
        """The contact points of the scene's bodies idx (called once, by the Scene being built)."""
        return ContactPoints(scene, idx, self)

    def ground_rows(self, geo: "ContactPoints") -> GroundRows:
        """This ground and its bodies' contact points as the kernel's System holds them (engine/system.py)."""
        return GroundRows(self.height, self.restitution, self.friction, geo.g, geo.rows, geo.shape, geo.half,
                          geo.axes)

    def resolve(self, scene, X, idx=None, dt=1e-3, geo=None):
        """The state X after this ground's collisions and resting contact over a step dt (X itself if nothing
        touches): the kernel's solver (engine/contact.py: resolve), run as Python, on the scene's System,
        where this ground is one of the scene's (its bodies are those it was given: idx and geo are kept
        for the callers of earlier versions and not used); dt a finite real number > 0.  A contact system that is
        not finite raises np.linalg.LinAlgError."""
        from .engine import interpreted
        solver = interpreted.module("contact")
        g = [k for k, (e, *_) in enumerate(getattr(scene, "_contacts", ())) if e is self]
        if not g:
            raise ValueError(f"scene must be a Scene holding this ground ({self!r}) among its effects")
        dt = checks.positive("dt", dt)
        sys = scene.compile().system
        S = to_matrix(scene.batch(X))
        w = solver.work(S.shape[0])
        touched = solver.resolve(S, w.S0, sys, g[0], float(dt), w)
        if touched < 0:
            raise np.linalg.LinAlgError("a contact system is not finite")
        if touched == 0:
            return X
        return from_matrix(S)


class ContactPoints:
    """The contact points of the bodies a Ground acts on, as the engine's solver reads them (once per scene).

    g: the scene's gravity (for the resting-contact threshold ε); rows (n,) the bodies, in the scene;
    shape (n,) SHAPE_CODES (a box: its 8 corners σ ∘ half, σ = (±1, ±1, ±1); a cylinder, axis body z: 4 points
    on each rim; an ellipsoid of semi-axes half along its principal axes, a sphere: the lowest point);
    half (n, 3) the half extents (a cylinder: radius, radius, half height); axes (n, 3, 3) the principal
    axes (ellipsoids; 0 for the others).  engine/contact.py computes ρ = r − x from them and R.  reach (n,): |half|,
    a bound on |ρ| (a box's corners are at |half|, a cylinder's rim points at √(r² + (h/2)²) <= |half|, an
    ellipsoid's lowest point within its largest semi-axis).
    """

    def __init__(self, scene, idx, ground):
        rows = np.arange(scene.n_bodies)[idx]
        if scene.pivoted[rows].any():
            raise ValueError(f"{ground!r} cannot act on pivoted bodies (bodies {np.flatnonzero(scene.pivoted).tolist()}"
                             " are held by a Pivot): leave them out with body=[...]")
        self.g = sum(e.g for e in scene.effects if isinstance(e, Gravity))
        bodies = [scene.bodies[i] for i in rows]
        shapes = [b.shape if b.shape in ("box", "cylinder") else "ellipsoid" for b in bodies]
        self.rows = np.ascontiguousarray(rows, dtype=np.int64)
        self.shape = np.array([SHAPE_CODES[s] for s in shapes], dtype=np.int64).reshape(-1)
        self.half = np.ascontiguousarray(np.array([b.half_extents() for b in bodies], dtype=float).reshape(-1, 3))
        self.axes = np.zeros((len(rows), 3, 3))
        for k, (b, s) in enumerate(zip(bodies, shapes)):
            if s == "ellipsoid":
                self.axes[k] = b.principal_axes
        self.reach = np.sqrt((self.half ** 2).sum(axis=1))   # |ρ| <= |half| for every contact point of every shape
