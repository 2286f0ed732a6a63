"""The inline frame every view of the notebooks uses (the 3-D drawing, the live view, the explorer):
a sandboxed, titled iframe with a text fallback under it.  Imports nothing heavy (no meshcat)."""
from __future__ import annotations

import html as _html

from ..support.language import current

INLINE_HEIGHT = 420          # px: a 3-D view's inline frame, a Drawing's or the live view's (meshcat's controls panel
                             # scrolls inside it)


TRUST = {
    "en": "run the cell, or trust the notebook: open the command palette (Ctrl+Shift+C, or View ▸ Activate Command "
          "Palette) and choose “Trust Notebook”",
    "fr": "exécutez la cellule, ou faites confiance au notebook : ouvrez la palette de commandes (Ctrl+Maj+C, ou "
          "View ▸ Activate Command Palette) et choisissez « Trust Notebook »",
}
"""How to trust a notebook in JupyterLab 4 (its command palette: "Trust Notebook" is in no menu), in the
workbook's language (rbcourse.support.language): the one wording of every view's fallback and of the README."""


def trust_hint() -> str:
    """TRUST in the workbook's language."""
    return TRUST[current()]


def iframe(*, height: int, title: str, fallback: str, src: str | None = None, srcdoc: str | None = None) -> str:
    """A resizable box holding a sandboxed iframe on src (a URL) or srcdoc (a whole page).

    The frame is titled (title) and sandboxed (scripts only: its own opaque origin, not the notebook's).
    Under it lies fallback (HTML text), covered by the frame, seen when the frame is not there: an
    untrusted notebook's sanitizer removes frames and scripts but keeps text.
    """
    attr = f'src="{_html.escape(src)}"' if src is not None else f'srcdoc="{_html.escape(srcdoc)}"'
    return (f'<div class="rbcourse-view" style="position:relative;height:{height}px;width:100%;overflow:hidden;'
            f'resize:vertical">'
            f'<div style="padding:12px 14px;font:14px/1.5 sans-serif;color:#333;background:#f3f3f3;height:100%;'
            f'box-sizing:border-box">{fallback}</div>'
            f'<iframe title="{_html.escape(title)}" sandbox="allow-scripts" {attr} '
            f'style="position:absolute;left:0;top:0;width:100%;height:100%;border:none;background:#fff"></iframe></div>')
