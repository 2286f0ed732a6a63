"""The integrator family: METHODS, a table of the methods with their properties (order, what they
keep exactly, cost, reference) and where their step is written: in the engine (rbcourse/engine),
once, compiled by numba or run as Python.  Methods as data: the Runge–Kutta ones are tables
(tableaus.py) run by the engine's one stage loop.  What a method promises on the named hard cases
is the bench's (rbcourse.bench.claims)."""
from ..engine import control
from ..engine.plan import (ADAPTIVE, EULER, EXACT_SPLITTING, EXPLICIT_RK, IMPLICIT_GYRO, IMPLICIT_MIDPOINT, LANES,
                           NEWTON, NORMALIZE_Q, PROJECT_R, RKMK4, SPLITTING, SYMPLECTIC_EULER, Stepping, VARIATIONAL)
from ..engine.tableaus import EULER as EULER_TABLE, MIDPOINT, RK4, dop853
from . import adaptive, exact_splitting
from .base import Method

METHODS: dict[str, Method] = {
    "euler": Method(
        "euler", "engine/euler.py: euler_step, X(t + Δt) = X(t) + Δt · dX/dt on (x, R, P, L)", order=1, keeps=frozenset({"L"}),
        cost="1 force evaluation",
        reference="the course slides; Baraff 2001, notes D §2 (explicit Euler on X = (x, R, P, L))",
        said=("the slides' explicit Euler, uncorrected: R leaves SO(3), energy grows",
              "la méthode d'Euler explicite des slides, sans correction : R quitte SO(3), l'énergie croît"),
        kernel=Stepping("euler", EULER, "matrix", EULER_TABLE)),
    "euler_project": Method(
        "euler_project", "engine/euler.py: euler_step, then engine/orthonormalize.py: orthonormalize_rows", order=1, keeps=frozenset({"SO(3)", "L"}),
        cost="1 force evaluation + 2–3 Björck iterations",
        reference="Baraff 2001 notes D §2 remark: re-orthogonalise R",
        said=("the slides' Euler, then R projected onto SO(3): a rotation again, but energy still grows",
              "l'Euler des slides, puis R projetée sur SO(3) : de nouveau une rotation, mais l'énergie croît toujours"),
        kernel=Stepping("euler", EULER, "matrix", EULER_TABLE, PROJECT_R)),
    "quaternion_euler": Method(
        "quaternion_euler", "engine/steps.py: explicit_quat_world_step (table EULER) on (x, q, P, L), L world (engine/quaternion.py: "
        "rates_quat_world)", order=1, keeps=frozenset({"SO(3)", "L", "|L|"}),
        cost="1 force evaluation (and R(q), I⁻¹(t) = R I⁻¹_body Rᵀ per evaluation)",
        reference="Baraff 2001, notes G \"Quaternions\", eq. 4-2 and 4-3: X = (x, q, P, L), q̇ = ½ (0, ω) q, "
                  "ω = R(q) I⁻¹_body R(q)ᵀ L, stepped by Euler, q normalised",
        said=("Baraff's quaternion Euler on (x, q, P, L), L world, q normalised: R stays a rotation and, with no "
                "torque, L is never changed (kept exactly); the energy is not kept (first order). Its price: "
                "R(q) and I⁻¹(t) at every evaluation (quaternion_euler_body needs neither for ω)",
              "l'Euler en quaternion de Baraff sur (x, q, P, L), L dans le monde, q normalisé : R reste une rotation et, sans moment, L n'est jamais modifié (gardé exactement) ; l'énergie n'est pas gardée (ordre 1). Son prix : R(q) et I⁻¹(t) à chaque évaluation (quaternion_euler_body n'a besoin d'aucun des deux pour ω)"),
        kernel=Stepping("explicit_quat_world", EXPLICIT_RK, "quat_world", EULER_TABLE, NORMALIZE_Q)),
    "quaternion_euler_body": Method(
        "quaternion_euler_body", "engine/steps.py: explicit_quat_step (table EULER) on (x, q, P, L_b), L_b = Rᵀ L "
        "(engine/quaternion.py: rates_quat)", order=1, keeps=frozenset({"SO(3)"}),
        cost="1 force evaluation (ω_b = I⁻¹_body L_b: no R needed for ω)",
        reference="Baraff 2001, notes G §4 for q, with the body-frame momentum of Euler's equations "
                  "(L̇_b = L_b × ω_b + Rᵀ τ), as rk4 and adaptive step it",
        said=("Euler on (x, q, P, L_b), q normalised: R stays a rotation and ω_b = I⁻¹_body L_b needs no R, but "
                "L_b turns (the gyroscopic term L_b × ω_b) and Euler on it lets world L drift (first order); "
                "energy grows",
              "Euler sur (x, q, P, L_b), q normalisé : R reste une rotation et ω_b = I⁻¹_body L_b n'a pas besoin de R, mais L_b tourne (le terme gyroscopique L_b × ω_b) et Euler laisse dériver le L du monde (ordre 1) ; l'énergie croît"),
        kernel=Stepping("explicit_quat", EXPLICIT_RK, "quat", EULER_TABLE, NORMALIZE_Q)),
    "rk4": Method(
        "rk4", "engine/steps.py: explicit_quat_step, table RK4, on (x, q, P, L_b)", order=4, keeps=frozenset({"SO(3)"}),
        cost="4 force evaluations",
        reference="Kutta 1901; on (x, q, P, L_b) with a normalised quaternion (as MuJoCo's RK4 on (q, ω_b))",
        said=("classic Runge–Kutta 4 on (x, q, P, L_b): accurate, R on SO(3), slow energy drift",
              "Runge–Kutta 4 classique sur (x, q, P, L_b) : précis, R sur SO(3), lente dérive de l'énergie"),
        kernel=Stepping("explicit_quat", EXPLICIT_RK, "quat", RK4, NORMALIZE_Q,
                        scratch=LANES)),
    "rkmk4": Method(
        "rkmk4", "engine/geometric.py: rkmk4_step", order=4, keeps=frozenset({"SO(3)", "L"}),
        cost="4 force evaluations + 5 exponentials",
        reference="Munthe-Kaas, BIT 38 (1998); Iserles et al., Acta Numerica 9 (2000)",
        said=("Runge–Kutta–Munthe-Kaas 4: RK4 in the Lie algebra, R = exp(u) R stays exactly on SO(3)",
              "Runge–Kutta–Munthe-Kaas 4 : RK4 dans l'algèbre de Lie, R = exp(u) R reste exactement sur SO(3)"),
        kernel=Stepping("rkmk4", RKMK4, "matrix", RK4)),
    "adaptive": Method(
        "adaptive", "engine/adaptive.py: adaptive_step", order=8, keeps=frozenset({"SO(3)"}),
        cost="12 force evaluations per substep; as many substeps as rtol/atol need",
        reference="Dormand & Prince 8(5,3), as in Hairer, Nørsett & Wanner, Solving ODEs I (DOP853); scipy's "
                  "solve_ivp (here with a rotation-invariant error scale: |L_b|, not each component)",
        said=("error-controlled DOP853 on (x, q, P, L): you set rtol/atol, it picks the substeps",
              "DOP853 à contrôle d'erreur sur (x, q, P, L) : vous fixez rtol/atol, il choisit les sous-pas"),
        options=("rtol", "atol"),
        settings={"rtol": control.RTOL, "atol": control.ATOL}, check_options=adaptive.check_tolerances,
        kernel=Stepping("adaptive", ADAPTIVE, "quat", dop853, scratch=2, time_forces=False)),
    "symplectic_euler": Method(
        "symplectic_euler", "engine/geometric.py: symplectic_euler_step", order=1, keeps=frozenset({"SO(3)", "L", "|L|"}),
        cost="1 force evaluation + 1 exponential",
        reference="semi-implicit Euler (momenta first) with an exponential-map rotation (Lie–Euler); "
                  "Hairer, Lubich, Wanner, GNI ch. IV, VI",
        said=("momenta first, then an exact rotation: R on SO(3) and L exact, but for a free body it is "
                "Lie–Euler in the rotation, so the energy error is first order (not symplectic there)",
              "les moments d'abord, puis une rotation exacte : R sur SO(3) et L exact, mais pour un corps libre c'est Lie–Euler en rotation, donc l'erreur d'énergie est d'ordre 1 (pas symplectique là)"),
        kernel=Stepping("symplectic_euler", SYMPLECTIC_EULER, "matrix", EULER_TABLE, nodes=(0.0,))),
    "implicit_gyro": Method(
        "implicit_gyro", "engine/implicit.py: implicit_gyro_step", order=1, keeps=frozenset({"SO(3)"}),
        cost="1 force evaluation + one 3×3 solve",
        reference="E. Catto, 'Numerical Methods', GDC 2015; Bullet Physics (implicit gyroscopic term)",
        said=("implicit gyroscopic step as in game engines: never blows up, but dissipates (a top slows and falls)",
              "pas gyroscopique implicite des moteurs de jeu : ne diverge jamais, mais dissipe (une toupie ralentit et tombe)"),
        kernel=Stepping("implicit_gyro", IMPLICIT_GYRO, "matrix", EULER_TABLE, nodes=(0.0,))),
    "implicit_midpoint": Method(
        "implicit_midpoint", "engine/implicit.py: implicit_midpoint_step", order=2, keeps=frozenset({"SO(3)", "L", "|L|", "energy"}),
        cost="Newton iterations (a few: 3–4 measured), each 1 + 6N force evaluations (the forces' derivative by differences) "
             "and one 6N × 6N solve; without forces one 3×3 solve per body",
        reference="implicit midpoint on the world momenta, R' = R exp(h ω̄*), ω̄ from the mean body momentum "
                  "(the Lie–Poisson midpoint of Austin, Krishnaprasad & Wang, J. Comput. Phys. 107 (1993), with "
                  "the torque kept in the world frame)",
        said=("implicit midpoint: a free body keeps energy, L and |L| exactly; R on SO(3); a top keeps L_z about "
                "its pivot exactly (Noether); symmetric, second order",
              "point milieu implicite : un corps libre garde exactement l'énergie, L et |L| ; R sur SO(3) ; une toupie garde exactement L_z autour de son pivot (Noether) ; symétrique, ordre 2"),
        kernel=Stepping("implicit_midpoint", IMPLICIT_MIDPOINT, "matrix", EULER_TABLE, nodes=(0.5,),
                        scratch=NEWTON)),
    "splitting": Method(
        "splitting", "engine/geometric.py: splitting_step", order=2, keeps=frozenset({"SO(3)", "L", "|L|"}),
        cost="2 force evaluations (1 with FSAL) + 5 axis rotations",
        reference="free-rotor splitting: McLachlan, SIAM J. Sci. Comput. 16 (1995); Touma & Wisdom, AJ 107 (1994); "
                  "Dullweber, Leimkuhler & McLachlan, J. Chem. Phys. 107 (1997)",
        said=("kick / drift + free-rotor splitting / kick: symplectic, L exact, energy bounded, second order",
              "impulsion / dérive + rotor libre / impulsion : symplectique, L exact, énergie bornée, ordre 2"),
        kernel=Stepping("splitting", SPLITTING, "matrix", MIDPOINT, nodes=(0.0, 0.0, 1.0, 1.0))),
    "exact_splitting": Method(
        "exact_splitting", "engine/exact_flow.py: exact_splitting_step", order=4, keeps=frozenset({"SO(3)", "L", "|L|", "energy"}),
        cost="6 exact free flows + 7 kicks (force evaluations) per step",
        reference="Celledoni, Fassò, Säfström & Zanna, SIAM J. Sci. Comput. 30 (2008); composition: Blanes & Moan, "
                  "J. Comput. Appl. Math. 142 (2002)",
        said=("kick / exact torque-free flow / kick composed to order 4: exact for a free body, big steps "
                "with torques",
              "impulsion / flot exact sans moment / impulsion, composés à l'ordre 4 : exact pour un corps libre, grands pas avec des moments"),
        uses_exact_flow=True, options=("composition",), check_options=exact_splitting.check_composition,
        kernel=Stepping("exact", EXACT_SPLITTING, "matrix", RK4, scratch=1)),
    "variational": Method(
        "variational", "engine/variational.py: variational_step", order=2, keeps=frozenset({"SO(3)", "L", "|L|"}),
        cost="2 force evaluations (1 with FSAL) + a Newton solve (3×3) for the discrete rotor",
        reference="Hamilton–Pontryagin Lie group variational integrator with the Cayley map: N. Bou-Rabee & "
                  "J. E. Marsden, Found. Comput. Math. 9 (2009); M. Kobilarov, K. Crane & M. Desbrun, ACM Trans. "
                  "Graph. 28 (2009); after the Lie group variational integrator of T. Lee, M. Leok & "
                  "N. H. McClamroch, IEEE CCA 2005",
        said=("variational on SO(3): kick / Cayley rotor h Π = J a + ½ a × J a + ¼ (a·J a) a, R' = R cay(a) / kick; "
                "symplectic, R exactly on SO(3), a free body's L and |L| exact, its energy bounded (exact if "
                "symmetric), a top's L_z about its pivot exact (Noether), second order; a step exists at any h |ω| "
                "(the rotor turns behind the body: by (h|ω|)²/3 of the angle about a principal axis)",
              "variationnel sur SO(3) : impulsion / rotor de Cayley h Π = J a + ½ a × J a + ¼ (a·J a) a, R' = R cay(a) / impulsion ; symplectique, R exactement sur SO(3), L et |L| d'un corps libre exacts, son énergie bornée (exacte s'il est symétrique), L_z d'une toupie autour de son pivot exact (Noether), ordre 2 ; un pas existe à tout h |ω| (le rotor tourne en retard sur le corps : de (h|ω|)²/3 de l'angle autour d'un axe principal)"),
        kernel=Stepping("variational", VARIATIONAL, "matrix", MIDPOINT, nodes=(0.0, 0.0, 1.0, 1.0))),
}


def get_method(method) -> Method:
    """A Method from its name (or a Method itself)."""
    if isinstance(method, Method):
        return method
    if not isinstance(method, str) or method not in METHODS:
        raise ValueError(f"method must be one of {sorted(METHODS)}, got {method!r}")
    return METHODS[method]


__all__ = ["METHODS", "Method", "get_method"]
