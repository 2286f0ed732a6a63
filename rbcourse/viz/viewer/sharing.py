"""meshcat's script once per notebook: the first 3-D view a kernel shows carries it, the later ones borrow it.

meshcat's viewer script (three.js, compressed: ~225 kB, assets.viewer_script) is the bulk of every inline view;
a notebook with three views and an explorer carried it four times.  Now an inline view (a Drawing's or the
explorer's, shown in a notebook) is a sandboxed iframe whose page does not hold the script: it asks the
notebook's page for it (postMessage to its parent: the frame is another origin, it can read nothing there) and
runs its own scripts once the answer has come.  The answer comes from a small script beside the frame in the
output's HTML, run by JupyterLab in the notebook's page (a trusted notebook): the first view this kernel process
shows puts meshcat's script there (a page-global, window.rbcourseMeshcat, keyed by the script's hash) and
listens for the frames' requests; the later views carry none.

What "already sent" means lives in this process (_SENT): a restarted kernel sends the script again with its
first view.  A cell that carried it and is run again carries it again (its old output, the script with it, is
being replaced).  A view that gets no answer (the first view's output was cleared, or is not rendered yet)
says so in the frame, in the workbook's language, and keeps asking: it starts as soon as the script is there.
A standalone page (Drawing.save, Explorer.save, the demo's files) always holds its own script (assets.viewer_tag).
"""
from __future__ import annotations

import hashlib
import json

from ...support.language import say
from . import assets

_SENT: dict[str, object] = {}
"""Hashes of meshcat's script this process has put in an output -> the cell that did (None outside a kernel)."""


def missing_text() -> str:
    """What a view says when meshcat's script is not on the notebook's page (in the active language)."""
    return say("This 3-D view borrows meshcat's script from the first 3-D view this kernel showed in the notebook, "
               "and it is not on the page (that output was cleared, is not shown yet, or the kernel was restarted): "
               "run the first 3-D view's cell again, or restart the kernel and Run All.",
               "Cette vue 3-D emprunte le script de meshcat à la première vue 3-D affichée par ce noyau dans le "
               "notebook, et il n'est pas sur la page (sortie effacée, pas encore affichée, ou noyau redémarré) : "
               "ré-exécutez la cellule de la première vue 3-D, ou redémarrez le noyau et faites Run All.")


def _cell():
    """The id of the notebook cell being run (JupyterLab sends it with each execution), or None."""
    try:
        from IPython import get_ipython
        kernel = getattr(get_ipython(), "kernel", None)
        return (kernel.get_parent().get("metadata") or {}).get("cellId") if kernel is not None else None
    except Exception:           # no IPython, no kernel, an older kernel: no cell to name
        return None


def forget() -> None:
    """Forget what was sent: the next inline view carries meshcat's script again (as after a kernel restart)."""
    _SENT.clear()


def inline(page: str) -> tuple[str, str]:
    """A standalone page (one holding assets.viewer_tag()) made into an inline view's: (the frame's page, the HTML
    to put beside the frame).  The frame's page asks its parent for meshcat's script (rbShared, assets.RUNTIME)
    and runs its later scripts once it has it; beside the frame, the first view of this process (or of the cell
    that first carried it) holds the script and answers the frames, a later one holds nothing."""
    tag = assets.viewer_tag()
    at = page.find(tag)
    if at < 0:
        raise ValueError("page must be a viewer page holding meshcat's script (assets.viewer_tag())")
    text, size = assets.viewer_script()
    key = hashlib.sha256(text.encode("ascii")).hexdigest()[:16]
    loader = assets.script_tag(f"rbShared({json.dumps(key)}, {json.dumps(missing_text(), ensure_ascii=False)});")
    rest = page[at + len(tag):].replace("<script>\n", f'<script type="{assets.AFTER}">\n')
    frame_page = page[:at] + loader + rest
    cell = _cell()
    if key in _SENT and (cell is None or _SENT[key] != cell):
        return frame_page, ""
    _SENT[key] = cell
    provide = (f"(function (w) {{\n"
               f"  var all = w.rbcourseMeshcat = w.rbcourseMeshcat || {{}};\n"
               f'  all["{key}"] = {{text: "{text}", size: {size}}};\n'
               f"  if (w.rbcourseMeshcatListens) return;\n"
               f"  w.rbcourseMeshcatListens = true;\n"
               f'  w.addEventListener("message", function (e) {{\n'
               f'    var d = e.data, got = d && d.rbcourseMeshcat === "want" && all[d.key];\n'
               f"    if (got && e.source) e.source.postMessage("
               f'{{rbcourseMeshcat: "script", key: d.key, text: got.text, size: got.size}}, "*");\n'
               f"  }});\n"
               f"}})(window);")
    return frame_page, assets.script_tag(provide)
