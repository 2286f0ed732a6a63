"""The adaptive method's step-size control, as numbers (no numba: the layers above read them at import).

After a substep with scaled error err (err <= 1: accepted), the next substep is

    sub · min(MAX_FACTOR, SAFETY · err^(−1/8))   (accepted),    sub · max(MIN_FACTOR, SAFETY · err^(−1/8))   (rejected)

the controller of Hairer, Nørsett & Wanner's DOP853 (Solving ODEs I, §II.4), as scipy's solve_ivp uses it.
RTOL, ATOL: the tolerances a run takes when none are given (methods.METHODS["adaptive"].settings reads them).
"""
SAFETY, MIN_FACTOR, MAX_FACTOR = 0.9, 0.2, 10.0
RTOL, ATOL = 1e-8, 1e-10
