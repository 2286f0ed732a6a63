"""The words of the French texts: one French word for each term of the course, used by every French sentence
rbcourse prints or draws (the engine's descriptions and outcomes, the methods' summaries, the workbook's
checks, views and reports), and the synonyms they do not use.

The course's slides are French; its students say "slide" (la slide) as the notebooks do.  The text tests
(tests/test_french_core.py, tests/test_french_views.py) read every French sentence against AVOIDED
(avoided_in).
"""
from __future__ import annotations

TERMS = {
    "box": "boîte",
    "rigid body": "corps rigide",
    "slide": "slide",
    "angular momentum": "moment cinétique",
    "linear momentum": "quantité de mouvement",
    "inertia tensor": "tenseur d'inertie",
    "angular velocity": "vitesse angulaire",
    "time step": "pas de temps",
    "drift": "dérive",
    "integrator": "intégrateur",
    "explicit Euler": "méthode d'Euler explicite",
    "energy": "énergie",
    "torque": "moment (couple)",
    "force": "force",
    "spring": "ressort",
    "pivot": "pivot",
    "ground": "sol",
    "impulse": "impulsion",
    "gravity": "gravité",
    "drag": "frottement fluide",
    "restitution": "restitution",
    "friction": "frottement (Coulomb)",
    "diverged": "a divergé",
    "step": "pas",
}
"""English term -> the one French word every French text uses for it."""

AVOIDED = {
    "pavé": "boîte",
    "boite": "boîte",
    "diapositive": "slide",
    "diapo": "slide",
    "moment angulaire": "moment cinétique",
    "impulsion angulaire": "moment cinétique",
    "tenseur inertiel": "tenseur d'inertie",
}
"""A French word the texts do not use -> the glossary's word for it."""


def avoided_in(text: str) -> list[tuple[str, str]]:
    """The AVOIDED words in a French text, with the word to use instead: [(word, instead), …]."""
    low = text.lower()
    return [(w, instead) for w, instead in AVOIDED.items() if w in low]
