"""The checks of the fix for R leaving SO(3): check_project_so3, R = U Σ Vᵀ → U Vᵀ (det(U Vᵀ) = −1 among the
inputs), and check_euler_step_projected, the Euler step then R ← U Vᵀ."""
from __future__ import annotations

import numpy as np

from ...rotation import project_so3 as engine_project_so3
from . import reference as ref
from .harness import N, close, random_rotation
from .reference import as_floats
from .result import CheckResult
from .slides import PROJECTION
from .stepping import STATE_LABELS, step_cases
from .texts import tr
from .variants import euler_variants, part
from . import ladders
from .spec import Case, Spec
from .verdict import run


def _is_rotation(Q) -> bool:
    return bool(np.all(np.isfinite(Q)) and np.abs(Q.T @ Q - np.eye(3)).max() < 1e-9
                and abs(np.linalg.det(Q) - 1.0) < 1e-9)


def gram_schmidt(A):
    """A's columns made orthonormal in turn (Gram–Schmidt): e₁ = a₁/|a₁|, e₂ = a₂ − (a₂·e₁) e₁ normalised, …"""
    E = np.zeros((3, 3))
    for j in range(3):
        e = A[:, j] - E[:, :j] @ (E[:, :j].T @ A[:, j])
        E[:, j] = e / np.linalg.norm(e)
    return E


def _not_nearest(got, R):
    """"not_nearest" (with "Gram–Schmidt" when it is that, on R's columns or rows) for a rotation that is not the one
    nearest R; else None.  Gram–Schmidt gives a rotation close to R, but the fix asks the nearest one, U Vᵀ."""
    if got.shape != (3, 3) or not _is_rotation(got):
        return None
    if close(got, gram_schmidt(R)) or close(got, gram_schmidt(R.T).T):
        return "not_nearest", tr("gram_schmidt")
    return "not_nearest", ""


def projection_variants(R, Q):
    """The wrong projections of R (Q its nearest rotation): (id, value) — project_so3's mistakes, wherever they show."""
    U, _, Vt = np.linalg.svd(R)
    flip = np.diag([1.0, 1.0, -1.0])
    if np.linalg.det(U @ Vt) < 0:
        yield "svd_no_det_fix", U @ Vt
        yield "svd_negated", -(U @ Vt)
        yield "svd_wrong_column", U @ np.diag([-1.0, 1.0, 1.0]) @ Vt
        yield "svd_wrong_column", U @ np.diag([1.0, -1.0, 1.0]) @ Vt
    else:
        yield "svd_flip_always", U @ flip @ Vt
    yield "svd_factors_swapped", Vt @ U
    yield "svd_U_only", U
    yield "scaled_by_det", R / np.cbrt(np.linalg.det(R))
    yield "svd_V_transposed", U @ Vt.T
    yield "svd_not_projected", R
    yield "columns_normalized", R / np.linalg.norm(R, axis=0)
    yield "columns_normalized", R / np.linalg.norm(R, axis=1)[:, None]
    yield "projection_transposed", Q.T


def check_project_so3(project_so3, *, verbose: bool = True, seed: int = 2008) -> CheckResult:
    """project_so3(R) -> the rotation nearest to R (R a little off SO(3), as after Euler steps):

        R = U Σ Vᵀ  (np.linalg.svd)   →   U Vᵀ
    """
    spec = Spec("project_so3", "formula_project", PROJECTION, ladder=ladders.PROJECTION,
                reference=engine_project_so3)

    def cases(rng):
        out = []
        for i in range(N):
            if i % 4 == 3:          # det(U Vᵀ) = −1: the nearest rotation flips U's last column
                s = np.sort(rng.uniform(0.2, 1.2, 3))[::-1] * [1.0, 1.0, -1.0]
                R = random_rotation(rng) @ np.diag(s) @ random_rotation(rng)
            elif i == N - 2:        # off SO(3) by 1e-6, as after one step of 1 ms: it still needs its projection
                R = random_rotation(rng) + 1e-6 * rng.normal(size=(3, 3))
            else:                   # a little off SO(3), as after Euler's steps
                R = random_rotation(rng) + 0.08 * rng.normal(size=(3, 3))
            Q = engine_project_so3(R)

            def candidates(R=R, Q=Q):
                return ((m, wrong, "") for m, wrong in projection_variants(R, Q))
            out.append(Case((R,), ("R",), Q, candidates))
        return out

    def last_resort(got, case):
        if got.shape != (3, 3):
            return None
        return _not_nearest(got, case.args[0]) or "not_a_rotation"

    return run(spec, project_so3, cases, verbose, seed, last_resort=last_resort)


def check_euler_step_projected(euler_step_projected, *, verbose: bool = True, seed: int = 2009) -> CheckResult:
    """euler_step_projected(M, I_body_inv, X, forces, dt): the Euler step, then R(t+Δt) ← its nearest
    rotation U Vᵀ (the fix for R drifting off SO(3))."""
    spec = Spec("euler_step_projected", "formula_projected", PROJECTION, labels=STATE_LABELS,
                ladder=ladders.scale_rungs(ladders.STEP, ladders.SCALES["state"]),
                reference=lambda *a: tuple(ref.euler_step_projected(*a)), scales=ladders.SCALES["state"])

    def variants(M, Ib, X, forces, dt):
        x, R, P, L = ref.euler_step(M, Ib, X, forces, dt)
        yield "step_not_projected", (x, R, P, L), ""
        for mistake, R_bad in projection_variants(R, engine_project_so3(R)):     # project_so3's own mistakes
            if mistake != "svd_not_projected":
                yield mistake, (x, R_bad, P, L), part("project_so3")
        x0, R0, P0, L0 = as_floats(X)
        yield "projected_before", tuple(ref.euler_step(M, Ib, (x0, engine_project_so3(R0), P0, L0), forces, dt)), ""
        for mistake, (xb, Rb, Pb, Lb), prefix in euler_variants(M, Ib, X, forces, dt):
            if np.shape(Rb) == (3, 3):          # (a variant with the parts out of order has no R to project)
                yield mistake, (xb, engine_project_so3(Rb), Pb, Lb), part(tr("the_euler_step")) + prefix

    def cases(rng):
        return step_cases(rng, lambda *a: tuple(ref.euler_step_projected(*a)), variants,
                          ("M", "I_body_inv", "X", "forces", "dt"), off_so3=0.05, with_dt=True)

    def last_resort(got, case):
        """A rotation for R(t+Δt), the rest as the Euler step's, but not the projection of the step's R."""
        x, R, P, L = ref.euler_step(*case.args)
        if all(close(g, w) for g, w in zip((got[0], got[2], got[3]), (x, P, L))):
            return _not_nearest(got[1], R)
        return None
    return run(spec, euler_step_projected, cases, verbose, seed, last_resort=last_resort)
