"""The one explicit Runge–Kutta stage loop, over the state layouts of the engine (and the same loop for rk4, LANES
bodies at a time, rk_stages_lanes).

    K_i = f(Y + h Σ_{j<i} a_ij K_j),   out = Y + h/den Σ b_i K_i

f is dX/dt of the state: the slides' state S = [x, R, P, L] (MATRIX), the body-frame quaternion state
Y = [x, q, P, L_b] (QUAT), Baraff's quaternion state Y = [x, q, P, L], L world (QUAT_WORLD), or the
momenta's rates at fixed positions (KICK, the splittings' kicks).
"""
from __future__ import annotations

from .jit import inline, njit, unrolled
from .motion import alike, body_resultants, stage
from .system import GRAVITY
from .algebra import axpy, identity, quat_axpy, quat_normalize
from .quaternion import WIDTH, free_rate, normalize_quats, quat_body_rate


@inline
def rk_stages(rate, sys, values, A, b, den, Y, out, h, K, U, w, first=0, normalize=False):
    """The stage loop of an explicit Runge–Kutta table: K_i = f(Y + h Σ a_ij K_j), out = Y + h/den Σ b_i K_i.
    rate(sys, values, Y, dY, w): f, the rate of the state's layout — motion.dxdt (the slides' state),
    quaternion.rates_quat, quaternion.rates_quat_world, motion.rates_kick (the momenta's rates at fixed
    positions: the splittings' kicks); numba compiles this loop for each rate it is given, and only those
    (inlined where it is called: a function given as an argument is a pointer to a Python object until then,
    and numba caches no code that holds one).
    first = 1: K[0] is given (f at the start known already: "first same as last", as DOP853 reuses f at
    the end of its last substep).  normalize: then each body's q normalised (the quaternion layouts)."""
    n, m = Y.shape
    for i in range(first, len(b)):
        for p in range(n):
            for q in range(m):
                acc = 0.0
                for j in range(i):
                    if A[i, j] != 0.0:          # a zero of the table adds nothing (acc is never −0): skipped
                        acc += A[i, j] * K[j, p, q]
                U[p, q] = Y[p, q] + h * acc
        rate(sys, stage(values, i), U, K[i], w)
    for p in range(n):
        for q in range(m):
            acc = 0.0
            for i in range(len(b)):
                acc += b[i] * K[i, p, q]
            out[p, q] = Y[p, q] + (h / den) * acc
    if normalize:
        normalize_quats(out)


LANES = 64      # bodies stepped side by side by rk_stages_lanes
STATE_ROW, F_ROW, OUT_ROW = 0, WIDTH, WIDTH + 3   # a lane block's rows, LANES numbers each: Y, F (3), out (WIDTH)
LANE_BLOCK = (OUT_ROW + WIDTH) * LANES
LANE_STAGES = 4


@njit
def lanes_fit(sys, A, b, Y, K):
    """Can rk_stages_lanes step this: a table of LANE_STAGES stages, chained (rk4's), K with room for a lane
    block past the stages, and bodies that do not act on one another (motion.alike)?"""
    return len(b) == LANE_STAGES and K.size >= LANE_BLOCK + len(b) * Y.size and chained(A) and alike(sys)


def lane_scratch(n: int) -> int:
    """Work slots (N, 13) a method adds to its stages so that its K also holds a lane block (rk_stages_lanes)."""
    return -(-LANE_BLOCK // (n * WIDTH))


@njit
def central(sys):
    """Is every effect row gravity, and no body pivoted: each body's force M g at its centre of mass, with no
    torque, the same at every stage of every step (central_force; a free scene too: F = 0)?"""
    for e in range(len(sys.code)):
        if sys.code[e] != GRAVITY:
            return False
    for i in range(len(sys.pivoted)):       # (no sys.pivoted.any(): it would load numba's array registries,
        if sys.pivoted[i]:                  # 0.3-0.5 s at each start: test_machine_code)
            return False
    return True


@unrolled
def central_force(sys, values, i):
    """Body i's F in a central scene (central), summed as body_resultants sums it: gravity's M g does not
    depend on the body's motion, so it is taken once, before the step (the motion given: at rest, unturned)."""
    zero = (0.0, 0.0, 0.0)
    return body_resultants(sys, values, 0, i, zero, identity(), zero, zero, zero)[0]


@njit
def rk_stages_lanes(sys, values, A, b, den, Y, out, h, K, normalize):
    """The same stage loop for a table of LANE_STAGES stages (rk4) and bodies that do not act on one another
    (motion.alike), LANES bodies at a time: their Y copied into a lane block (rows of LANES numbers, one per
    body, in K's memory past the stages; I⁻¹_body and M are read from the System's rows, sys.I_inv_rows and
    sys.mass), then one loop over the block's bodies, each pass a whole step of one body with its stages held
    as numbers (registers), not written to arrays.  The passes are independent: the compiler does several at
    once in vector instructions where the rate has no branch (free bodies, or a central scene: gravity alone,
    each body's M g summed once into the block's F rows, central).
    The table is chained (a stage from the one before alone: chained): each term a_ij K_j that is not one of
    the zeros rk_stages skips, and each b_i K_i, is added in rk_stages' order, and q normalised as
    quaternion.normalize_quats does (normalize): the same numbers."""
    W = K.reshape(-1)[-LANE_BLOCK:]
    n = Y.shape[0]
    if values is None:                          # free: F = 0 known to the compiler, the block's F rows unread
        for p0 in range(0, n, LANES):
            lanes = min(LANES, n - p0)
            load_block(sys, Y[:0, :3], Y, p0, lanes, W, False)
            step_block(sys, Y[:0, :3], 0, A, b, den, h, p0, lanes, W, False, False, normalize)
            unload_block(W, p0, lanes, out)
        return
    weighed = central(sys)                      # gravity alone: each body's M g, given
    slots = values.shape[1]
    flat = values.reshape((-1, 3))              # the stages' forces over time as rows: no view per body
    for p0 in range(0, n, LANES):
        lanes = min(LANES, n - p0)
        load_block(sys, flat, Y, p0, lanes, W, weighed)
        if weighed:
            step_block(sys, flat, slots, A, b, den, h, p0, lanes, W, False, True, normalize)
        else:                                   # forces that change with the motion, or a pivot
            step_block(sys, flat, slots, A, b, den, h, p0, lanes, W, True, False, normalize)
        unload_block(W, p0, lanes, out)


@unrolled
def load_block(sys, flat, Y, p0, lanes, W, weighed):
    """The block's rows Y and F := those of bodies p0 … p0 + lanes − 1 (F: gravity's force on each where
    weighed, central_force; else not written — a free body evaluates no force)."""
    for l in range(lanes):
        p = p0 + l
        for q in range(WIDTH):
            W[(STATE_ROW + q) * LANES + l] = Y[p, q]
        if weighed:
            F = central_force(sys, flat, p)
            W[F_ROW * LANES + l], W[(F_ROW + 1) * LANES + l], W[(F_ROW + 2) * LANES + l] = F[0], F[1], F[2]


TILE = 4        # bodies and numbers a tile of unload_block moves together


@unrolled
def unload_block(W, p0, lanes, out):
    """out's rows p0 … p0 + lanes − 1 := the block's out rows, in tiles of TILE bodies × TILE numbers (read along
    the block's rows, written along out's: the compiler moves a tile in vector instructions)."""
    whole = WIDTH - WIDTH % TILE
    for l0 in range(0, lanes - lanes % TILE, TILE):
        for k in range(TILE):
            for q0 in range(0, whole, TILE):
                for j in range(TILE):
                    out[p0 + l0 + k, q0 + j] = W[(OUT_ROW + q0 + j) * LANES + l0 + k]
            for q in range(whole, WIDTH):
                out[p0 + l0 + k, q] = W[(OUT_ROW + q) * LANES + l0 + k]
    for l in range(lanes - lanes % TILE, lanes):
        for q in range(WIDTH):
            out[p0 + l, q] = W[(OUT_ROW + q) * LANES + l]


@unrolled
def step_block(sys, flat, slots, A, b, den, h, p0, lanes, W, torqued, weighed, normalize):
    """One step of each body of the block: K_i = f(Y + h a_i,i−1 K_i−1) (a chained table: rk4's), out =
    Y + h/den Σ_i b_i K_i, summed as the stages come (so that only one K is held at a time), its q then
    normalised (normalize).  The forces: the effects' at each stage (torqued), or the block's F (weighed:
    gravity alone), or none (a free body: F = 0, a constant the compiler folds in)."""
    for l in range(lanes):
        Y = lane_state(W, STATE_ROW, l)
        p = p0 + l
        I = sys.I_inv_rows
        I_inv = ((I[0, p], I[1, p], I[2, p]), (I[3, p], I[4, p], I[5, p]), (I[6, p], I[7, p], I[8, p]))
        M = sys.mass[p]
        F = (W[F_ROW * LANES + l], W[(F_ROW + 1) * LANES + l], W[(F_ROW + 2) * LANES + l]) if weighed else \
            (0.0, 0.0, 0.0)
        K = lane_rate(sys, flat, 0, p, torqued, I_inv, M, F, plus_scaled(Y, h, NO_STATE))
        S = plus_scaled(NO_STATE, b[0], K)
        K = lane_rate(sys, flat, slots, p, torqued, I_inv, M, F, stage_state(Y, h, A[1, 0], K))
        S = plus_scaled(S, b[1], K)
        K = lane_rate(sys, flat, 2 * slots, p, torqued, I_inv, M, F, stage_state(Y, h, A[2, 1], K))
        S = plus_scaled(S, b[2], K)
        K = lane_rate(sys, flat, 3 * slots, p, torqued, I_inv, M, F, stage_state(Y, h, A[3, 2], K))
        x, q, P, Lb = plus_scaled(Y, h / den, plus_scaled(S, b[3], K))
        put_lane(W, OUT_ROW, l, (x, quat_normalize(q) if normalize else q, P, Lb))


@njit
def chained(A):
    """Is each stage of the table taken from the one before alone (a_ij = 0 for j < i − 1: rk4's table), as
    step_block takes it?"""
    for i in range(A.shape[0]):
        for j in range(i - 1):
            if A[i, j] != 0.0:
                return False
    return True


@inline
def stage_state(Y, h, a, K):
    """Y + h (0 + a K): a stage's state from the stage before alone, summed as rk_stages sums it."""
    return plus_scaled(Y, h, plus_scaled(NO_STATE, a, K))


NO_STATE = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))


@inline
def plus_scaled(S, c, D):
    """S + c D, part by part, for a body's state or rate S, D = (x, q, P, L_b)."""
    return axpy(S[0], c, D[0]), quat_axpy(S[1], c, D[1]), axpy(S[2], c, D[2]), axpy(S[3], c, D[3])


@unrolled
def lane_rate(sys, flat, base, p, torqued, I_inv, M, F, S):
    """Body p's rate [v, q̇, F, L̇_b] at its stage state S: its forces in registers (quaternion.quat_body_rate,
    the stage's forces over time from row base of flat), or in a central scene (central: gravity, or
    nothing) the force F it was given and no torque (quaternion.free_rate)."""
    x, q, P, Lb = S
    if torqued:
        return quat_body_rate(sys, flat, base, p, x, q, P, Lb)
    return free_rate(I_inv, M, q, P, Lb, F)


@inline
def lane_state(W, row, l):
    """Body l's (x, q, P, L_b) from the block's 13 rows from `row` (row r of body l at r · LANES + l)."""
    u = row * LANES + l
    return ((W[u], W[u + LANES], W[u + 2 * LANES]),
            (W[u + 3 * LANES], W[u + 4 * LANES], W[u + 5 * LANES], W[u + 6 * LANES]),
            (W[u + 7 * LANES], W[u + 8 * LANES], W[u + 9 * LANES]),
            (W[u + 10 * LANES], W[u + 11 * LANES], W[u + 12 * LANES]))


@inline
def put_lane(W, row, l, S):
    """The block's 13 rows from `row`, body l := S = (x, q, P, L_b)."""
    u = row * LANES + l
    (x, q, P, Lb) = S
    W[u], W[u + LANES], W[u + 2 * LANES] = x[0], x[1], x[2]
    W[u + 3 * LANES], W[u + 4 * LANES], W[u + 5 * LANES], W[u + 6 * LANES] = q[0], q[1], q[2], q[3]
    W[u + 7 * LANES], W[u + 8 * LANES], W[u + 9 * LANES] = P[0], P[1], P[2]
    W[u + 10 * LANES], W[u + 11 * LANES], W[u + 12 * LANES] = Lb[0], Lb[1], Lb[2]
