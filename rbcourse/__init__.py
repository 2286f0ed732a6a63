"""rbcourse — rigid-body simulation as in the course (after Baraff, SIGGRAPH 2001), and beyond.

The state X = (x, R, P, L); the derived v, I⁻¹(t), ω; forces at points and their
resultants F, τ; dX/dt = (v, ω* R, F, τ); the slides' explicit Euler and better
integrators; scenes that compute only the effects they call for.
"""
from .support import interrupts as _interrupts
_interrupts.install_if_command()     # `python -m rbcourse`: Ctrl-C is the command line's from here on (its one line)
from .body import RigidBody
from .contact import Ground
from .dynamics import StateDerivative, dxdt
from .effects import AngularDrag, Gravity, LinearDrag, PointForce, Spring
from .forces import resultants
from .impulse import Impulse
from .methods import METHODS, Method
from .pivot import Pivot
from .profiles import Constant, Pulse, Ramp, Sine, Steps
from .rotation import exp_so3, project_so3, rotation_angle, star
from .scene import Scene
from .simulate import simulate
from .state import Derived, State, angular_velocity, derived, inverse_inertia, velocity
from .trajectory import SimulationDiverged, Trajectory
from .workbook.walkthrough import IterationRecord, walkthrough

__version__ = "0.1.0"


def __getattr__(name):
    """exact_free_body is loaded at its first use (rbcourse.exact, with scipy.special): not at import."""
    if name == "exact_free_body":
        from .exact import exact_free_body
        globals()[name] = exact_free_body
        return exact_free_body
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))

__all__ = [
    "RigidBody", "State", "Derived", "derived", "velocity", "inverse_inertia", "angular_velocity",
    "Scene", "Gravity", "PointForce", "Spring", "LinearDrag", "AngularDrag", "Pivot", "Impulse", "Ground",
    "Constant", "Pulse", "Ramp", "Sine", "Steps",
    "resultants", "dxdt", "StateDerivative", "METHODS", "Method", "simulate", "Trajectory",
    "SimulationDiverged", "walkthrough", "IterationRecord", "star", "exp_so3", "project_so3", "rotation_angle",
    "exact_free_body",
]
