"""The course: the slides' walkthrough ("Itération 1 / 2"), the table of named scenes (examples), the
demo, and the exercise's checks (exercises).  They use the engine; the engine never uses them.

The language of every text they print: ``langue("fr")`` (or ``language``), ``current()`` — see language.py."""
from .language import LANGUAGES, current, langue, language

__all__ = ["LANGUAGES", "langue", "language", "current"]
