"""The integrator family.  Each method is a small step function registered in METHODS
with its order, what it keeps exactly, its cost and a reference."""
from .base import METHODS, Method, get_method, register
from .explicit import euler_step, euler_project_step, quaternion_euler_step, rk4_step, rkmk4_step
from .adaptive import adaptive_step
from .splitting_exact import composed_step
from .geometric import implicit_gyro_step, implicit_midpoint_step, splitting_step, symplectic_euler_step

__all__ = ["METHODS", "Method", "get_method", "register", "euler_step", "euler_project_step",
           "quaternion_euler_step", "rk4_step", "rkmk4_step", "symplectic_euler_step", "splitting_step",
           "implicit_midpoint_step", "implicit_gyro_step", "adaptive_step", "composed_step"]
