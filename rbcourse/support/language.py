"""The language of every text rbcourse says: which one is active, and which exist.

The state lives here, at the bottom of the package, so that any layer can read it (the engine's compile
notice, rbcourse.compiling, as well as the workbook's messages); the workbook's switch,
rbcourse.workbook.language (langue / language), sets it.

    from rbcourse.support import language
    language.choose("fr")      # what rbcourse.workbook.langue("fr") does
    language.current()         # "fr"
"""
from __future__ import annotations

LANGUAGES = ("en", "fr")
"""The languages every text exists in."""

_active = ["en"]


def checked(code, name: str = "langue") -> str:
    """code itself when it is one of LANGUAGES; else ValueError naming the parameter `name` and the allowed
    codes (a code that is not a string is refused, never coerced)."""
    if not isinstance(code, str) or code not in LANGUAGES:
        allowed = ", ".join(repr(c) for c in LANGUAGES)
        raise ValueError(f"{name}: code must be one of {allowed}, got {code!r}")
    return code


def choose(code: str) -> str:
    """Make `code` the active language ("en", the default, or "fr"); returns it.  A bad code raises ValueError
    and changes nothing."""
    _active[0] = checked(code)
    return code


def current() -> str:
    """The active language's code ("en" or "fr")."""
    return _active[0]


def say(en: str, fr: str) -> str:
    """The sentence in the active language: `en` or `fr` (both given where the sentence is written, so the two
    stay side by side; the French words are the glossary's, rbcourse.support.glossary)."""
    return fr if _active[0] == "fr" else en


def text(table: dict[str, dict[str, str]], key: str) -> str:
    """table[current()][key]: the text of id ``key`` in the active language (a table keyed by language, each with
    the same ids and {placeholders}), picked when the message is produced."""
    return table[_active[0]][key]
