"""How the explorer writes a time step, a count and a wall time, the same on the page, in its links and in
Explorer.summary()."""
from __future__ import annotations


def dt_text(dt: float) -> str:
    """dt as the page and its links write it: the shortest text that reads back as the same float."""
    return repr(float(dt))


def count(n: int, word: str) -> str:
    return f"{n} {word}{'' if n == 1 else 's'}"


def fmt_seconds(x: float) -> str:
    return f"{x * 1e3:.3g} ms" if x < 1 else f"{x:.3g} s"
