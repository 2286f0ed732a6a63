"""The language of the workbook's texts: every check message, hint, verdict and printed walkthrough line.

    from rbcourse.workbook import exercises as ex
    ex.langue("fr")          # from now on, in French (ex.language("fr") is the same function)
    ex.langue("en")          # back to English (the default)

One structure for every text: a table per language keyed by the same ids, with the same {placeholders}
(e.g. TEXTS = {"en": {...}, "fr": {...}}); ``text(table, key)`` picks the entry of the language active
when the message is produced (``current()``), so changing the language takes effect on the next message.
"""
from __future__ import annotations

from ..support.language import LANGUAGES, choose, current, text  # noqa: F401 (text: the workbook's texts read it here)


def langue(code: str) -> str:
    """Set the language of every message of the workbook: "en" (English, the default) or "fr" (français).

    Returns the code.  A code that is not one of LANGUAGES (or not a string) raises ValueError.
    (The state is rbcourse.support.language's, which the layers below the workbook read too.)
    """
    return choose(code)


language = langue
"""The English name of langue."""

