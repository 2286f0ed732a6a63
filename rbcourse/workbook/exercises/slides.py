"""Where a message sends the student to reread: the slides' titles (FORMULES, ETAT, EULER, ITERATION_1,
ITERATION_2, BIBLIO, all in SLIDES; the same in every language) and the two other sources, ids of texts.py
(PROJECTION: Part 8 of the notebook; BOX: Baraff's notes); slide_text writes one in the active language."""
from __future__ import annotations

from .texts import tr


FORMULES = "Les Formules"
ETAT = "Vecteur d'état du Rigidbody"
EULER = "Evolution temporelle (Euler)"
ITERATION_1 = "Itération 1"
ITERATION_2 = "Itération 2"
BIBLIO = "Bibliographie"
SLIDES = (FORMULES, ETAT, EULER, ITERATION_1, ITERATION_2, BIBLIO)

PROJECTION = "projection"
"""The id (in TEXTS, texts.py) of where the fix for R leaving SO(3) is given: Part 8 of the notebook (not on the
slides: "Bibliographie" holds only the reference)."""

BOX = "box"
"""The id (in TEXTS, texts.py) of where the box's inertia is derived: Baraff's notes (the slides take I_body as given)."""
SOURCES = (PROJECTION, BOX)


def slide_text(slide: str) -> str:
    """Where to reread, in the active language: 'the slide “Les Formules”' for a slide's title, the text of a
    source id (PROJECTION, BOX), any other text as it is."""
    if slide in SLIDES:
        return tr("slide").format(slide=slide)
    return tr(slide) if slide in SOURCES else slide
