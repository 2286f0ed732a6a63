"""The exact torque-free motion of a rigid body: the motion in closed form (free_body: Jacobi's
solution, closed forms for symmetric bodies and principal-axis spins), the elliptic functions it
needs near the separatrix (elliptic), and its flow over a step for the splitting methods (flow)."""
from .flow import FreeRotationFlow, free_rotation_flow
from .free_body import exact_free_body

__all__ = ["exact_free_body", "FreeRotationFlow", "free_rotation_flow"]
