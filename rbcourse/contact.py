"""Contact with the ground, the plane z = height (Baraff 2001, notes part II, "Nonpenetration constraints").

A scene asks its Ground once, when it is built, for the contact points of the bodies it acts on
(``Ground.prepare``: ``ContactPoints``), and calls ``Ground.resolve`` with them after each step.  Contact points r: a box's 8 corners, 4 points
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

Vectorised over bodies; the only loops are over mode passes, sweeps and contact slots.
Pivoted bodies are refused (ValueError when the scene is built): leave them out with ``body=``.
"""
from __future__ import annotations

import numpy as np

from . import checks
from .effects import Z_UP, Effect, Gravity, body_selection
from .rotation import exp_so3, matvec, star, transpose

CONTACT_TOL = 1e-6     # m: a point this close above the plane counts as touching
REST_SPEED = 0.01      # m/s: ε = REST_SPEED + 2 g Δt, below which contact is resting (no restitution)
MODE_PASSES = 8        # exact solves with corrected contact modes, at most
MAX_SWEEPS = 20        # then Gauss–Seidel sweeps, at most ...
SWEEP_TOL = 1e-6       # ... until no impulse changes by more than this fraction of the largest one
SHAPE_CODES = {"box": 0, "cylinder": 1, "ellipsoid": 2}   # engine/contact.py: BOX, CYLINDER, ELLIPSOID
GRAM_RCOND = 1e-6      # the 6×6 normal equations are solved directly if this well conditioned (error ~1e-16/GRAM_RCOND)


def _param(name: str, value, low: float, high: float, allowed: str) -> float:
    try:
        if low <= checks.real(name, value) <= high:
            return float(value)
    except ValueError:
        pass
    raise ValueError(f"{name} must be {allowed}, got {value!r}")


class Ground(Effect):
    """The horizontal plane z = height: colliding and resting contact, Coulomb friction.

    restitution e in [0, 1] (0: no bounce, 1: elastic); friction μ >= 0 (0: frictionless).
    """
    kind = "contact"

    def __init__(self, height=0.0, restitution=0.5, friction=0.5, *, body=None):
        self.height = _param("height", height, -np.inf, np.inf, "a finite real number")
        self.restitution = _param("restitution", restitution, 0.0, 1.0, "a real number in [0, 1]")
        self.friction = _param("friction", friction, 0.0, np.inf, "a finite real number >= 0")
        self.body = body_selection(body)

    def describe(self):
        return (f"a ground plane z = {self.height:g} m (restitution e = {self.restitution:g}, friction "
                f"μ = {self.friction:g}): collisions by impulses, resting contact, no sinking")

    def __repr__(self):
        return f"Ground(height={self.height:g}, restitution={self.restitution:g}, friction={self.friction:g})"

    def prepare(self, scene, idx) -> "ContactPoints":
        """The contact points of the scene's bodies idx (called once, by the Scene being built)."""
        return ContactPoints(scene, idx, self)

    def resolve(self, scene, X, idx, dt, geo: "ContactPoints | None" = None):
        """The state after collisions and resting contact with the plane (X itself if nothing touches).

        geo: what prepare(scene, idx) returned for these bodies (the Scene passes it; built here if None).
        The solver is the engine's, per body (engine/contact.py: compiled with numba, or run as Python);
        a contact system that is not finite raises np.linalg.LinAlgError."""
        if geo is None:
            geo = self.prepare(scene, idx)
        from .engine import contact as solver        # numba is loaded here, not by `import rbcourse`
        S = np.concatenate([X.x, X.R.reshape(-1, 9), X.P, X.L], axis=1)
        system, S0, work = geo.engine_arrays(scene, S.shape[0], solver)
        touched = solver.resolve(S, S0, system, geo.rows, geo.shape, geo.half, geo.axes, self.height,
                                 self.restitution, self.friction, geo.g, float(dt), work)
        if touched < 0:
            raise np.linalg.LinAlgError("a contact system is not finite")
        if touched == 0:
            return X
        return type(X).unchecked(S[:, 0:3].copy(), S[:, 3:12].reshape(-1, 3, 3), S[:, 12:15].copy(), S[:, 15:18].copy())

    def _resolve_numpy(self, scene, X, idx, dt, geo=None):   # the numpy solver, until the compiled one matches
        if geo is None:
            geo = self.prepare(scene, idx)
        x, R, P, L = X.x[idx], X.R[idx], X.P[idx], X.L[idx]
        rho = geo.offsets(R)                                    # (n, K, 3): ρ = r − x, world axes
        I_inv = R @ scene.I_body_inv[idx] @ transpose(R)
        v, omega = P / scene.mass[idx][:, None], matvec(I_inv, L)
        u_n = v[:, None, 2] - matvec(star(rho), omega[:, None])[..., 2]   # n·(v + ω × ρ)
        gap = x[:, None, 2] + rho[..., 2] - self.height
        active = geo.valid & (gap + np.minimum(u_n, 0.0) * dt <= CONTACT_TOL)
        touch = np.flatnonzero(active.any(axis=1))
        if touch.size == 0:
            return X
        slots = np.flatnonzero(active.any(axis=0))             # only the slots some body touches with
        rows = np.arange(scene.n_bodies)[idx][touch]            # the touching bodies, in the scene
        points, valid = rho[touch], geo.valid[touch]
        rho, gap, u_n, active = (a[touch][:, slots] for a in (rho, gap, u_n, active))
        P, L, M, I_inv, v, omega = P[touch], L[touch], scene.mass[rows], I_inv[touch], v[touch], omega[touch]
        S = star(rho)                                           # S a = ρ × a
        eps = REST_SPEED + 2.0 * geo.g * dt
        target = np.where(u_n < -eps, -self.restitution * u_n, -gap.clip(min=0.0) / dt) * active
        J = _impulses(v, omega, M, I_inv, S, active, target, self.friction)
        xs, Rs, Ps, Ls = X.x.copy(), X.R.copy(), X.P.copy(), X.L.copy()
        Ps[rows] = P + J.sum(axis=1)                            # ΔP = Σ j_k
        Ls[rows] = L + matvec(S, J).sum(axis=1)                 # ΔL = Σ ρ_k × j_k
        depth = np.where(active, -gap, 0.0).clip(min=0.0)
        if depth.any():                 # lift: pseudo-velocities that move each point up by its depth in Δt
            Jp = _impulses(0.0 * v, 0.0 * v, M, I_inv, S, active, depth / dt, 0.0)
            turn = exp_so3(dt * matvec(I_inv, matvec(S, Jp).sum(axis=1)))
            xs[rows] += dt * Jp.sum(axis=1) / M[:, None]
            Rs[rows] = turn @ Rs[rows]
            z = xs[rows, None, 2] + matvec(turn[:, None], points)[..., 2] - self.height   # what is left, O(Δt²)
            xs[rows, 2] -= np.where(valid, z, 0.0).min(axis=1).clip(max=0.0)
        return _no_energy_gain(scene, rows, X, type(X).unchecked(xs, Rs, Ps, Ls))


def _impulses(v, omega, M, I_inv, S, active, target, mu):
    """The impulses j (m, K, 3) at the contact points: u_n >= target, j_n >= 0, |j_t| <= μ j_n.

    An impulse j at point l changes v by j/M and ω by I⁻¹(ρ_l × j), so the velocity
    u_k = v + ω × ρ_k of point k by W_kl j, with W_kl = Id/M − ρ_k* I⁻¹ ρ_l* = G_k H_l:
    G_k = [Id, −ρ_k*] (3×6) the point's velocity from (v, ω), H_l = [Id/M; I⁻¹ρ_l*] (6×3) the
    body's response (Δv, Δω) to an impulse at l.
    """
    m, K = active.shape
    G = np.concatenate([np.broadcast_to(np.eye(3), S.shape), -S], axis=-1)            # u_k = G_k (v, ω)
    H = np.concatenate([np.broadcast_to(np.eye(3), S.shape) / M[:, None, None, None], I_inv[:, None] @ S], axis=-2)
    W = np.einsum("mkij,mljn->mkiln", G, H)                     # W_kl = G_k H_l, H_l = M⁻¹ G_lᵀ: (Δv, Δω) = H_l j
    u0 = v[:, None] - matvec(S, omega[:, None])                 # u = v + ω × ρ
    stick, slide = active & (mu > 0.0), active & (mu == 0.0)    # without friction: "sliding" freely
    s, J, live = np.zeros((m, K, 3)), np.zeros((m, K, 3)), np.arange(m)
    for _ in range(MODE_PASSES):
        J[live], (stick[live], slide[live], s[live], changed) = _solve_modes(
            W[live], G[live], H[live], u0[live], active[live], target[live], stick[live], slide[live], s[live], mu)
        live = live[changed]
        if live.size == 0:
            break
    J[..., 2] = J[..., 2].clip(min=0.0)                        # projected on the cones
    J[..., :2] *= np.minimum(1.0, mu * J[..., 2] / np.maximum(np.hypot(J[..., 0], J[..., 1]), 1e-300))[..., None]
    if live.size:
        J[live] = _sweeps(J[live], v[live], omega[live], M[live], I_inv[live][:, None] @ S[live], S[live], W[live],
                          active[live], target[live], mu)
    return J


def _solve_modes(W, G, H, u0, active, target, stick, slide, s, mu):
    """Solve for the modes: sticking u_k = (0, 0, target_k); sliding along s_k, u_n = target_k with
    j_k = j_n (n − μ s_k); off, j_k = 0.  Then correct them: the most negative j_n: off; |j_t| > μ j_n:
    slides against j_t; sliding stopped (u·s <= 0): sticks; off but approaching: on."""
    m, K = active.shape
    goal = target[..., None] * Z_UP
    E = np.zeros((m, K, 3, 3))                                  # j_k = E_k y_k
    E[stick] = np.eye(3)
    E[..., 2] += slide[..., None] * (Z_UP - mu * s)
    D = np.where(stick[..., None], 1.0, slide[..., None] * Z_UP)   # the equations kept
    B = (D[..., None] * G).reshape(m, 3 * K, 6)                 # the kept equations: D_k u_k = D_k goal_k
    C = np.einsum("mlnp,mlpq->mnlq", H, E).reshape(m, 6, 3 * K)  # (Δv, Δω) = C y
    y = _min_norm_solve(B, C, (D * (goal - u0)).reshape(m, -1)).reshape(m, K, 3)
    J = matvec(E, y)
    u = u0 + np.einsum("mkiln,mln->mki", W, J)
    tol_j = 1e-9 * np.abs(J).max(axis=(1, 2))[:, None] + 1e-300
    tol_u = 1e-9 * np.abs(goal - u0).max(axis=(1, 2))[:, None] + 1e-300
    jn = np.where(stick | slide, J[..., 2], np.inf)
    off = (jn == jn.min(axis=1, keepdims=True)) & (jn < -tol_j)
    to_slide = stick & (np.hypot(J[..., 0], J[..., 1]) > mu * J[..., 2] + tol_j) & ~off
    stopped = slide & (mu > 0.0) & (np.sum(u * s, -1) <= tol_u) & ~off
    back = active & ~(stick | slide) & (u[..., 2] < target - tol_u)
    j_t = J * [1.0, 1.0, 0.0]
    s = np.where(to_slide[..., None], -j_t / np.maximum(np.linalg.norm(j_t, axis=-1, keepdims=True), 1e-300), s)
    stick, slide = ((stick & ~off & ~to_slide) | stopped | (back & (mu > 0.0)),
                    (slide & ~off & ~stopped) | to_slide | (back & (mu == 0.0)))
    return J, (stick, slide, s, (off | to_slide | stopped | back).any(axis=1))


def _min_norm_solve(B, C, b):
    """y = A⁺ b, the least-squares solution of least norm of A y = b, A = B C = D W E (m, p, p).

    A has rank 6 at most (a body has 6 velocities), so it is singular from 2 points on (rank 5 on an edge);
    with only normal equations kept (frictionless, sliding, the lift) B's columns vx, vy, ωz are
    0 and its rank is 3 at most.  With P the r <= 6 columns of B that are not 0, A = (B Pᵀ)(P C);
    where B Pᵀ and P C have rank r, well conditioned (the eigenvalues of their Gram matrices
    within a factor GRAM_RCOND of each other: a box flat on its face, 3 points or more not on a line),
        A⁺ = (P C)ᵀ (P C Cᵀ Pᵀ)⁻¹ (P Bᵀ B Pᵀ)⁻¹ P Bᵀ,
    two 6×6 solves (the unused rows and columns padded by the trace: no effect on y).  The other
    bodies (1 or 2 points, on an edge) take np.linalg.pinv(A, rcond=1e-9), an SVD of A; a
    non-finite A raises np.linalg.LinAlgError there.
    """
    unused = ~(B != 0.0).any(axis=1)                             # (m, 6): P's complement
    C = np.where(unused[..., None], 0.0, C)                      # P C
    BtB, CCt = np.swapaxes(B, 1, 2) @ B, C @ np.swapaxes(C, 1, 2)
    for Q in (BtB, CCt):
        Q += np.where(unused[..., None] & np.eye(6, dtype=bool), np.trace(Q, axis1=1, axis2=2)[:, None, None], 0.0)
    lam_B, lam_C = np.linalg.eigvalsh(BtB), np.linalg.eigvalsh(CCt)     # ascending
    fast = (lam_B[:, 0] > GRAM_RCOND * lam_B[:, -1]) & (lam_C[:, 0] > GRAM_RCOND * lam_C[:, -1])
    y = np.empty_like(b)
    if fast.any():
        z = np.linalg.solve(CCt[fast], np.linalg.solve(BtB[fast], matvec(np.swapaxes(B[fast], 1, 2), b[fast])[..., None]))
        y[fast] = matvec(np.swapaxes(C[fast], 1, 2), z[..., 0])
    if not fast.all():
        rest = ~fast
        y[rest] = matvec(np.linalg.pinv(B[rest] @ C[rest], rcond=1e-9), b[rest])
    return y


def _sweeps(J, v, omega, M, B, S, W, active, target, mu):
    """Projected Gauss–Seidel from J: sweeps over the points, each accumulated impulse projected on
    j_n >= 0 and |j_t| <= μ j_n, until no body's impulses change any more (B j = Δω)."""
    v, omega = v + J.sum(axis=1) / M[:, None], omega + matvec(B, J).sum(axis=1)
    slots, running = list(range(J.shape[1])), np.ones(len(M))
    for sweep in range(MAX_SWEEPS):
        change = np.zeros(len(M))
        for k in (slots if sweep % 2 == 0 else slots[::-1]):   # symmetric sweeps: no bias to one corner
            Wk = W[:, k, :, k]
            u = v - matvec(S[:, k], omega)
            jn = np.where(active[:, k], np.maximum(J[:, k, 2] + (target[:, k] - u[:, 2]) / Wk[:, 2, 2], 0.0), 0.0)
            dj = np.zeros_like(v)
            dj[:, 2] = jn - J[:, k, 2]
            if mu > 0.0:
                u_t = u[:, :2] + Wk[:, :2, 2] * dj[:, 2:]      # sliding velocity after the normal impulse
                speed = np.hypot(u_t[:, 0], u_t[:, 1])[:, None]
                d = u_t / np.maximum(speed, 1e-300)
                jt = J[:, k, :2] - speed / np.sum(d * matvec(Wk[:, :2, :2], d), 1, keepdims=True) * d  # stops it
                size = np.hypot(jt[:, 0], jt[:, 1])
                jt *= np.minimum(1.0, mu * jn / np.maximum(size, 1e-300))[:, None]            # within the cone
                dj[:, :2] = jt - J[:, k, :2]
            dj *= running[:, None]
            J[:, k] += dj
            v, omega = v + dj / M[:, None], omega + matvec(B[:, k], dj)
            change = np.maximum(change, np.abs(dj).max(axis=1))
        running = running * (change > SWEEP_TOL * np.abs(J).max(axis=(1, 2)))
        if not running.any():
            break
    return J


def _no_energy_gain(scene, rows, X, Y):
    """Y, the touching bodies' P and L scaled so that T + U is not above its value in X (the lift, round-off)."""
    def energies(Z):
        R, P, L = Z.R[rows], Z.P[rows], Z.L[rows]
        I_inv = R @ scene.I_body_inv[rows] @ transpose(R)
        T = 0.5 * (np.sum(P * P, -1) / scene.mass[rows] + np.sum(L * matvec(I_inv, L), -1))
        U = scene.potential_energy(Z.x, Z.R)
        return T, (0.0 if U is None else U[rows])
    (T0, U0), (T1, U1) = energies(X), energies(Y)
    excess = T1 + U1 - T0 - U0
    lose = np.divide(excess, T1, out=(excess > 0.0) * 1.0, where=(excess > 0.0) & (T1 > 0.0))
    scale = np.sqrt(np.clip(1.0 - lose, 0.0, 1.0))[:, None]     # 1 where no energy was gained
    Y.P[rows] *= scale
    Y.L[rows] *= scale
    return Y


class ContactPoints:
    """The contact points of the bodies a Ground acts on, sorted by shape once per scene.

    g: the scene's gravity (for the resting-contact threshold); valid (n, K): which of the K
    slots each body uses; offsets(R) gives ρ = r − x of every point, world axes.
    """

    def __init__(self, scene, idx, ground):
        rows = np.arange(scene.n_bodies)[idx]
        if scene.pivoted[rows].any():
            raise ValueError(f"{ground!r} cannot act on pivoted bodies (bodies {np.flatnonzero(scene.pivoted).tolist()}"
                             " are held by a Pivot): leave them out with body=[...]")
        self.g = sum(e.g for e in scene.effects if isinstance(e, Gravity))
        bodies = [scene.bodies[i] for i in rows]
        shapes = np.array([b.shape if b.shape in ("box", "cylinder") else "ellipsoid" for b in bodies])
        half = np.array([b.half_extents() for b in bodies]).reshape(-1, 3)
        self.groups = {}                        # shape -> (which bodies, their half extents)
        for shape in ("box", "cylinder", "ellipsoid"):
            sel = np.flatnonzero(shapes == shape)
            if sel.size:
                self.groups[shape] = (slice(None) if sel.size == len(rows) else sel), half[sel]
        self.K = 1 if set(self.groups) == {"ellipsoid"} else 8
        self.rows = np.ascontiguousarray(rows, dtype=np.int64)          # the engine's solver: its bodies,
        self.shape = np.array([SHAPE_CODES[s] for s in shapes], dtype=np.int64).reshape(-1)   # shapes,
        self.half = np.ascontiguousarray(half, dtype=float)             # half extents,
        self.axes = np.zeros((len(rows), 3, 3))                         # principal axes (ellipsoids)
        self._engine = None
        self.valid = np.ones((len(rows), self.K), dtype=bool)
        signs = np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)], dtype=float)
        self.corners = signs * self.groups["box"][1][:, None, :] if "box" in self.groups else None
        if "ellipsoid" in self.groups:          # semi-axes along the principal axes (a sphere: all r)
            sel = np.arange(len(rows))[self.groups["ellipsoid"][0]]
            self.valid[sel, 1:] = False
            self.ellipsoid_axes = np.stack([bodies[i].principal_axes for i in sel])
            self.axes[sel] = self.ellipsoid_axes

    def engine_arrays(self, scene, n, solver):
        """(the scene's System, S0, Work) for the engine's solver, built at the first call (n bodies)."""
        if self._engine is None or self._engine[1].shape[0] != n:
            from .engine.system import compile_scene
            self._engine = (compile_scene(scene).system, np.zeros((n, 18)), solver.work(n))
        return self._engine

    def offsets(self, R):
        """ρ = r − x of every contact point, (n, K, 3) (unused slots: 0)."""
        rho = np.zeros((len(R), self.K, 3))
        if "box" in self.groups:
            sel = self.groups["box"][0]
            rho[sel] = self.corners @ transpose(R[sel])
        if "cylinder" in self.groups:
            sel, h = self.groups["cylinder"]
            rho[sel] = _cylinder_points(R[sel], h[:, 0], h[:, 2])
        if "ellipsoid" in self.groups:          # the lowest point: −Q A² Qᵀ n / |A Qᵀ n|
            sel, h = self.groups["ellipsoid"]
            Q = R[sel] @ self.ellipsoid_axes
            a_n = h * Q[:, 2, :]
            rho[sel, 0] = -matvec(Q, h * a_n) / np.maximum(np.linalg.norm(a_n, axis=-1, keepdims=True), 1e-300)
        return rho


def _cylinder_points(R, radius, half_height):
    """4 points on each rim: the lowest one and those at 90°, 180°, 270° from it (axis: body z)."""
    a = R[:, :, 2] / np.linalg.norm(R[:, :, 2], axis=-1, keepdims=True)
    down = a[:, 2:] * a - Z_UP                                  # −(n − (n·a) a): towards the lowest rim point
    size = np.linalg.norm(down, axis=-1, keepdims=True)
    side = R[:, :, 0] - np.sum(R[:, :, 0] * a, -1, keepdims=True) * a   # standing upright: any direction ⟂ a
    u = np.where(size > 1e-9, down / np.maximum(size, 1e-300), side / np.linalg.norm(side, axis=-1, keepdims=True))
    rim = radius[:, None, None] * np.stack([u, np.cross(a, u), -u, -np.cross(a, u)], axis=1)
    cap = half_height[:, None, None] * a[:, None, :]
    return np.concatenate([rim - cap, rim + cap], axis=1)
