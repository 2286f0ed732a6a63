"""The course: the slides' walkthrough ("Itération 1 / 2"), the table of named scenes (examples), the
demo, and the exercise's checks (exercises).  They use the engine; the engine never uses them.

The language of every text they print: ``langue("fr")``, ``current()`` — the module ``language`` (whose
name is why the English alias ``language`` of langue is exported by ``exercises`` only, as ex.language)."""
from .language import LANGUAGES, current, langue

__all__ = ["LANGUAGES", "langue", "current"]
