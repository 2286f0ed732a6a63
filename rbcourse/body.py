"""The rigid body's constants: its mass M and its inertia tensor in body axes, I_body.

Both are fixed for the life of a body: a simulation never changes them (the
arrays are read-only).  What changes is the state X = (x, R, P, L) (state.py).
"""
from __future__ import annotations

import numpy as np

from .support import checks

SYMMETRY_TOL = 2e-15      # principal moments closer than this (relative to the largest) are equal


class RigidBody:
    """A rigid body: mass M (kg) and inertia tensor I_body (kg m², body axes, about the centre of mass).

    ``RigidBody(mass=2.0, inertia=[1.0, 2.0, 3.0])`` takes the principal moments
    (I_body = diag(...)) or a full 3×3 symmetric positive-definite matrix.  A
    physical inertia satisfies the triangle inequality: each principal moment is
    at most the sum of the other two (equality: flat plates, thin disks).

    What is accepted: mass a real number (int or float, not a string or a bool) and the
    principal moments, all within [2.2e-308, 4.5e307] (normal floats whose inverses are
    normal floats: 1/M and I_body⁻¹ are finite); inertia an array of ints/floats (not
    strings, bools or complex).  shape one of SHAPES, with the size it needs: "box"
    (a, b, c) > 0, "cylinder" (radius > 0, height >= 0), "sphere" (radius > 0,); "body"
    (the default: no geometry) takes no size.  name a string or None.
    """

    __slots__ = ("mass", "I_body", "I_body_inv", "principal_moments", "principal_axes", "shape", "size", "name")

    def __init__(self, mass, inertia, *, shape: str = "body", size=None, name: str | None = None):
        mass = checks.scale("mass", mass)
        shape = checks.choice("shape", shape, SHAPES)
        size = _shape_size(shape, size)
        name = checks.text("name", name, optional=True)
        I_body = inertia_matrix(inertia)
        moments, axes = _eigh(I_body)
        if np.linalg.det(axes) < 0:
            axes[:, 2] *= -1.0
        if moments.min() < checks.TINY or moments.max() > checks.HUGE:
            raise ValueError(
                f"inertia's principal moments must be in [{checks.TINY:.3g}, {checks.HUGE:.3g}] (normal floats, "
                f"so that I_body⁻¹ is finite), got moments {moments.tolist()}")
        for i in range(3):
            others = moments.sum() - moments[i]
            if moments[i] > others * (1.0 + 1e-9):
                raise ValueError(
                    "inertia is not physically possible: each principal moment must be <= the sum of the "
                    f"other two (triangle inequality), got moments {moments.tolist()}")
        I_inv = _inverse(I_body)
        if not np.all(np.isfinite(I_inv)):
            raise ValueError(f"inertia must have a finite inverse I_body⁻¹, got {I_body.tolist()} "
                             f"(inverse {I_inv.tolist()})")
        self._set(mass, I_body, I_inv, moments, axes, shape, size, name)

    def _set(self, mass, I_body, I_inv, moments, axes, shape, size, name):
        """Store the checked constants (read-only arrays)."""
        for arr in (I_body, I_inv, moments, axes):
            arr.setflags(write=False)
        set_ = object.__setattr__
        set_(self, "mass", mass)
        set_(self, "I_body", I_body)
        set_(self, "I_body_inv", I_inv)
        set_(self, "principal_moments", moments)
        set_(self, "principal_axes", axes)
        set_(self, "shape", shape)
        set_(self, "size", size)
        set_(self, "name", name or shape)

    def __setattr__(self, key, value):
        raise AttributeError("a RigidBody's mass and inertia are constants: make a new body instead")

    def __reduce__(self):
        """Pickled as its checked constants, rebuilt by _set (a copy of the body, not a new check)."""
        return _rebuilt, (self.mass, np.array(self.I_body), np.array(self.I_body_inv), np.array(self.principal_moments),
                          np.array(self.principal_axes), self.shape, self.size, self.name)

    def __repr__(self) -> str:
        diag = np.allclose(self.I_body, np.diag(np.diag(self.I_body)))
        inertia = np.diag(self.I_body).round(10).tolist() if diag else self.I_body.round(10).tolist()
        size = f", size={self.size}" if self.size else ""
        return f"RigidBody({self.name}, mass={self.mass:g}, inertia={inertia}{size})"

    # --- factories ----------------------------------------------------------------
    @classmethod
    def box(cls, mass, size) -> "RigidBody":
        """A solid box with full side lengths size = (a, b, c) along body x, y, z (Baraff, eq. 2-27):

            I_body = M/12 · diag(b² + c², a² + c², a² + b²)
        """
        a, b, c = _sizes("size", size, 3)
        m = checks.scale("mass", mass)
        moments = [m / 12 * (b * b + c * c), m / 12 * (a * a + c * c), m / 12 * (a * a + b * b)]
        return cls(m, _usable(moments, "mass and size"), shape="box", size=(a, b, c))

    @classmethod
    def boxes(cls, masses, sizes) -> tuple:
        """N solid boxes at once, masses (N,) and sizes (N, 3), checked as arrays (no per-body check):
        the same bodies, to the bit, as RigidBody.box(masses[i], sizes[i]) — I_body = M/12 · diag(b² + c², ...)."""
        m = checks.numbers("masses", masses, "N masses (an array of shape (N,))")
        a = checks.numbers("sizes", sizes, "N box sizes (an array of shape (N, 3))")
        if m.ndim != 1 or m.size == 0 or a.shape != (m.size, 3):
            raise ValueError(f"masses must have shape (N,) and sizes (N, 3) with N >= 1, got {m.shape} and {a.shape}")
        bad = ~((m >= checks.TINY) & (m <= checks.HUGE))
        if bad.any():
            raise ValueError(f"masses must be in [{checks.TINY:.3g}, {checks.HUGE:.3g}], got {m[bad][:5].tolist()}")
        bad = ~np.all(np.isfinite(a) & (a > 0), axis=1)
        if bad.any():
            raise ValueError(f"sizes must be finite lengths > 0, got {a[bad][:5].tolist()}")
        A, B, C = a.T
        moments = np.stack([m / 12 * (B * B + C * C), m / 12 * (A * A + C * C), m / 12 * (A * A + B * B)], axis=-1)
        if not np.all((moments >= checks.TINY) & (moments <= checks.HUGE)):
            raise ValueError(f"masses and sizes give principal moments outside [{checks.TINY:.3g}, {checks.HUGE:.3g}] "
                             "(normal floats, so that I_body⁻¹ is finite): some body is too small or too large")
        I_body = moments[:, :, None] * np.eye(3)
        eig, axes = np.linalg.eigh(I_body)
        axes[np.linalg.det(axes) < 0, :, 2] *= -1.0
        I_inv = _inverse(I_body)
        bodies = []
        for i, (mi, size) in enumerate(zip(m.tolist(), a.tolist())):
            body = object.__new__(cls)
            body._set(mi, I_body[i], I_inv[i], eig[i], axes[i], "box", tuple(size), None)
            bodies.append(body)
        return tuple(bodies)

    @classmethod
    def cylinder(cls, mass, radius, height) -> "RigidBody":
        """A solid cylinder along body z:  I_body = diag(M(3r² + h²)/12, M(3r² + h²)/12, M r²/2)."""
        m = checks.scale("mass", mass)
        r = checks.positive("radius", radius)
        h = checks.real("height", height, low=0.0)
        side = m * (3 * r * r + h * h) / 12
        moments = [side, side, m * r * r / 2]
        return cls(m, _usable(moments, "mass, radius and height"), shape="cylinder", size=(r, h))

    @classmethod
    def sphere(cls, mass, radius) -> "RigidBody":
        """A solid sphere:  I_body = 2/5 M r² · Id."""
        m = checks.scale("mass", mass)
        r = checks.positive("radius", radius)
        return cls(m, _usable([0.4 * m * r * r] * 3, "mass and radius"), shape="sphere", size=(r,))

    # --- helpers the engine uses -----------------------------------------------
    def inertia_about(self, body_point) -> np.ndarray:
        """Inertia in body axes about a body point b (from the centre of mass), parallel-axis theorem:

            I_b = I_body + M (|b|² Id − b bᵀ)
        """
        b = checks.vector3("body_point", body_point)
        return self.I_body + self.mass * (b @ b * np.eye(3) - np.outer(b, b))

    def half_extents(self) -> np.ndarray:
        """Half sizes of the body's bounding box in body axes (for drawing and contact)."""
        if self.shape == "box":
            return np.array(self.size) / 2
        if self.shape == "cylinder":
            r, h = self.size
            return np.array([r, r, h / 2])
        if self.shape == "sphere":
            return np.full(3, self.size[0])
        # an ellipsoid of the same inertia: I_i = M/5 (b² + c²) ...
        s = np.diag(self.principal_axes.T @ self.I_body @ self.principal_axes)
        return np.sqrt(np.maximum(2.5 / self.mass * (s.sum() - 2 * s), 0.0))


def _inverse(I: np.ndarray) -> np.ndarray:
    """I_body⁻¹, symmetrised: ½ (I⁻¹ + I⁻ᵀ)  (one or N inertias)."""
    I_inv = np.linalg.inv(I)
    return 0.5 * (I_inv + np.swapaxes(I_inv, -1, -2))


def _eigh(I: np.ndarray, values_only: bool = False):
    """np.linalg.eigh (or eigvalsh), scaled by a power of two (exactly) when the entries are huge or
    tiny, so that LAPACK neither overflows nor underflows; ordinary inertias are decomposed as they are."""
    decompose = np.linalg.eigvalsh if values_only else np.linalg.eigh
    big = np.abs(I).max()
    if 2.0**-500 <= big <= 2.0**500:
        return decompose(I)
    s = 2.0 ** -np.round(np.log2(big))
    if values_only:
        return decompose(I * s) / s
    moments, axes = decompose(I * s)
    return moments / s, axes


def inertia_matrix(inertia) -> np.ndarray:
    """I as a symmetric 3×3 matrix of floats, from 3 principal moments (a diagonal) or a 3×3 matrix;
    a ValueError names `inertia` otherwise."""
    arr = checks.numbers("inertia", inertia, "3 principal moments or a 3x3 matrix of numbers")
    if arr.shape == (3,):
        arr = np.diag(arr)
    elif arr.shape != (3, 3):
        raise ValueError(f"inertia must have shape (3,) (principal moments) or (3, 3), got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"inertia must contain only finite numbers, got {arr.tolist()}")
    scale = np.abs(arr).max()
    if scale != 0 and not checks.TINY <= scale <= checks.HUGE:
        raise ValueError(f"inertia's entries must be in [{checks.TINY:.3g}, {checks.HUGE:.3g}] (normal floats, so "
                         f"that I_body⁻¹ is finite), got {arr.tolist()}")
    if not np.allclose(arr, arr.T, rtol=0, atol=1e-12 * max(scale, 1e-300)):
        raise ValueError(f"inertia must be a symmetric matrix, got {arr.tolist()}")
    arr = 0.5 * (arr + arr.T)
    if scale == 0 or _eigh(arr, values_only=True).min() <= 1e-12 * scale:
        raise ValueError(f"inertia must be positive definite (all principal moments > 0), got {arr.tolist()}")
    return arr


def _sizes(name: str, size, n: int) -> tuple:
    """n finite lengths > 0 (a sequence of numbers: not a string, not booleans)."""
    arr = checks.numbers(name, size, f"{n} positive lengths")
    if arr.shape != (n,):
        raise ValueError(f"{name} must be {n} positive lengths, got {size!r}")
    return tuple(checks.positive(f"{name}[{i}]", v) for i, v in enumerate(arr.tolist()))


SHAPES = ("body", "box", "cylinder", "sphere")   # what `shape` may be; "body": no geometry (an ellipsoid is drawn)
_SIZES = {"box": "(a, b, c), three side lengths > 0",
          "cylinder": "(radius, height) with radius > 0 and height >= 0",
          "sphere": "(radius,) with radius > 0"}


def _shape_size(shape: str, size):
    """The size a shape needs (None for "body"), checked: present, finite, positive."""
    if shape == "body":
        if size is not None:
            raise ValueError(f"size must be None for shape 'body' (sizes are for {', '.join(_SIZES)}), got {size!r}")
        return None
    if size is None:
        raise ValueError(f"size is needed for shape {shape!r}: size = {_SIZES[shape]}")
    if shape == "box":
        return _sizes("size", size, 3)
    arr = checks.numbers("size", size, f"{_SIZES[shape]} for shape {shape!r}")
    if arr.shape != ((2,) if shape == "cylinder" else (1,)):
        raise ValueError(f"size must be {_SIZES[shape]} for shape {shape!r}, got {size!r}")
    r = checks.positive("size[0] (radius)", arr[0])
    if shape == "sphere":
        return (r,)
    return (r, checks.real("size[1] (height)", arr[1], low=0.0))


def _usable(moments, given: str) -> list:
    """The factories' moments, each within [TINY, HUGE] (else a message naming what gave them)."""
    if not all(checks.TINY <= v <= checks.HUGE for v in moments):
        raise ValueError(f"{given} give principal moments {moments} outside [{checks.TINY:.3g}, "
                         f"{checks.HUGE:.3g}] (normal floats, so that I_body⁻¹ is finite): the body is too "
                         "small or too large")
    return moments


def _rebuilt(mass, I_body, I_inv, moments, axes, shape, size, name) -> RigidBody:
    """A RigidBody from its pickled constants (RigidBody.__reduce__)."""
    body = RigidBody.__new__(RigidBody)
    body._set(mass, I_body, I_inv, moments, axes, shape, size, name)
    return body
