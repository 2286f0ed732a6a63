"""The exact torque-free motion of a rigid body (Jacobi elliptic functions; closed forms for symmetric
bodies and principal-axis spins), and its flow over a step for the splitting methods."""
from .free_body import FreeRotationFlow, exact_free_body, free_rotation_flow

__all__ = ["exact_free_body", "FreeRotationFlow", "free_rotation_flow"]
