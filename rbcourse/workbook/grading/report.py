"""What grading writes: grades.csv (one row per hand-in), a feedback file per student, and optionally
Gradescope's results.json (one hand-in).

A check's cell in the CSV: ``passed``, the mistake's id (``velocity_times_mass``, ``wrong_result``,
``library_call`` — the answer taken from rbcourse, …), ``not-done`` (NotImplementedError, or no such function),
``crashed`` (the student's function raised), ``timed-out`` (it was still running when the check's time was up),
or ``not-run`` (the hand-in was stopped, or invalid, before the check could run).  The columns: student, status
(ok, error, timeout, invalid), each check, the number passed, ``protected`` (yes: graded in the sandbox; no:
--no-sandbox), the note.  No cell starts with = + - @ (or a tab, a carriage return): a spreadsheet would read it
as a formula; such a cell is written after a quote ('=HYPERLINK(…)).  The CSV holds nothing that depends on who
ran the hand-ins or how fast (the seconds are in the feedback and on the command's output).

The feedback's own words come from TEXTS by the hand-in's language (runner.notebook_language: "en" or
"fr"); the checks' messages are in that language too.  A feedback file is named after its student, when the
name can be a file's (not hidden, no control character, not another row's: feedback_names).
"""
from __future__ import annotations

import csv
import io
import json

from ...support.outputs import write_text
from ..exercises.slides import SLIDES, SOURCES
from .runner import GRACE

TEXTS = {
    "en": {
        "title": "Feedback on your exercise notebook — {name}",
        "status": {"ok": "your notebook ran to the end",
                   "error": "your notebook ran, but something in it failed (below)",
                   "timeout": "your notebook was stopped at its time limit: something in it runs for too long "
                              "(an endless loop?)",
                   "invalid": "your hand-in could not be graded (below)"},
        "headline": "**{status}**: {said}.",
        "status_word": {},
        "score": "Checks passed: {passed} of {total}.",
        "fix": "What to fix",
        "reread": "Reread: {slide}.",
        "mistake": "mistake",
        "passed": "Passed",
        "not_done": "Not done yet",
        "not_run": "Not run (your notebook was stopped before this check)",
        "notebook": "Your notebook",
        "cell_error": "code cell {cell} of {cells} (`{first_line}`) raised {error}",
        "killed": "it was killed {timeout:g} s after its start: it did not stop when interrupted at its time limit",
        "interrupted": "code cell {cell} of {cells} (`{first_line}`) was still running at its time limit ({seconds} s):"
                       " it was interrupted, and the cells after it did not run",
        "ended": "it ended before the end of the notebook (exit code {code})",
        "note": "what the grader noted: {note}",
        "seconds": "Graded in {seconds:.1f} s.",
    },
    "fr": {
        "title": "Retour sur votre notebook d'exercice — {name}",
        "status": {"ok": "votre notebook s'est exécuté jusqu'au bout",
                   "error": "votre notebook s'est exécuté, mais quelque chose y a échoué (voir plus bas)",
                   "timeout": "votre notebook a été arrêté à sa limite de temps : quelque chose y tourne trop "
                              "longtemps (une boucle sans fin ?)",
                   "invalid": "votre rendu n'a pas pu être noté (voir plus bas)"},
        "headline": "**{status}** : {said}.",
        "status_word": {"error": "erreur", "timeout": "temps dépassé", "invalid": "invalide"},
        "score": "Vérifications réussies : {passed} sur {total}.",
        "fix": "À corriger",
        "reread": "À relire : {slide}.",
        "mistake": "erreur",
        "passed": "Réussi",
        "not_done": "Pas encore fait",
        "not_run": "Non exécuté (votre notebook a été arrêté avant cette vérification)",
        "notebook": "Votre notebook",
        "cell_error": "la cellule de code {cell} sur {cells} (`{first_line}`) a levé {error}",
        "killed": "il a été tué {timeout:g} s après son démarrage : il ne s'est pas arrêté quand il a été interrompu "
                  "à sa limite de temps",
        "interrupted": "la cellule de code {cell} sur {cells} (`{first_line}`) tournait encore à sa limite de temps "
                       "({seconds} s) : elle a été interrompue, et les cellules suivantes n'ont pas été exécutées",
        "ended": "il s'est terminé avant la fin du notebook (code de sortie {code})",
        "note": "ce que le correcteur a noté : {note}",
        "seconds": "Noté en {seconds:.1f} s.",
    },
}


def texts(language: str) -> dict:
    """The feedback's words in that language, English when it has no edition."""
    return TEXTS.get(language, TEXTS["en"])


def cell(outcome: dict | None, stopped: bool) -> str:
    """A check's cell in grades.csv."""
    if outcome is None:
        return "not-run" if stopped else "not-done"
    if outcome.get("passed"):
        return "passed"
    mistake = outcome.get("mistake") or "wrong_result"
    return {"not_done": "not-done", "error": "crashed", "crashes_when": "crashed",
            "out_of_time": "timed-out"}.get(mistake, mistake)


def stopped(g) -> bool:
    """The hand-in stopped before all its checks ran (killed, interrupted at its limit, unusable, or invalid)."""
    return g.timed_out or bool(g.interrupted) or not g.finished or g.status == "invalid"


def columns(check_names) -> list[str]:
    return ["student", "status", *check_names, "passed", "protected", "note"]


FORMULA = ("=", "+", "-", "@", "\t", "\r")


def neutral(text) -> str:
    """A CSV cell a spreadsheet reads as text: one starting like a formula (= + - @, a tab, a carriage return)
    gets a quote first."""
    text = str(text)
    return "'" + text if text.startswith(FORMULA) else text


def csv_text(graded, check_names) -> str:
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(columns(check_names))
    for g in graded:
        cells = [cell(g.checks.get(n), stopped(g)) for n in check_names]
        w.writerow([neutral(c) for c in [g.name, g.status, *cells, cells.count("passed"),
                                         "yes" if g.protected else "no", g.note]])
    return out.getvalue()


MAX_NAME_BYTES = 255              # a file name, in bytes, on the file systems a class is graded on


def feedback_names(rows) -> dict:
    """{student: the feedback file's name} for the rows (hand-ins or Graded) whose name can be a file's: not
    hidden, no control character, and no other row's (two rows of one name: none).  STUDENT.md; a name too long
    for a file (over MAX_NAME_BYTES in UTF-8 with .md) is cut, whole characters, and ends with a digest of it
    (STUDE…-1a2b3c4d.md): each student keeps a file of their own."""
    counts: dict = {}
    for r in rows:
        counts[r.name] = counts.get(r.name, 0) + 1
    return {r.name: _file_name(r.name) for r in rows
            if counts[r.name] == 1 and r.name and not r.name.startswith(".") and r.name.isprintable()
            and "/" not in r.name}


def _file_name(name: str, suffix: str = ".md") -> str:
    """name + suffix, or when that is over MAX_NAME_BYTES: its start (whole characters) + "-" + a digest + suffix."""
    if len((name + suffix).encode()) <= MAX_NAME_BYTES:
        return name + suffix
    import hashlib
    tail = f"-{hashlib.sha256(name.encode()).hexdigest()[:8]}{suffix}"
    head = name.encode()[:MAX_NAME_BYTES - len(tail.encode())].decode("utf-8", errors="ignore")
    return head + tail


def _line(outcome) -> str:
    """The first line of a check's message ('' for none)."""
    lines = (outcome or {}).get("message", "").strip().splitlines()
    return lines[0] if lines else ""


def _slide(slide, language: str = "en") -> str:
    """'the slide “Les Formules”' (in the hand-in's language) for a slide's title; another source as it is (the
    worker wrote it in the hand-in's language)."""
    from ..exercises.texts import TEXTS as CHECK_TEXTS
    words = CHECK_TEXTS.get(language, CHECK_TEXTS["en"])
    if slide in SLIDES:
        return words["slide"].format(slide=slide)
    return words[slide] if slide in SOURCES else str(slide)


def feedback_text(g, check_names) -> str:
    """The student's feedback (Markdown): the status, each mistake with its explanation and the slide to reread,
    what passed, what is not done, and what went wrong when the notebook ran."""
    t = texts(g.language)
    cells = {n: cell(g.checks.get(n), stopped(g)) for n in check_names}
    status = t["status_word"].get(g.status, g.status)
    lines = [f"# {t['title'].format(name=g.name)}", "", t["headline"].format(status=status, said=t["status"][g.status]), "",
             t["score"].format(passed=list(cells.values()).count("passed"), total=len(check_names)), ""]
    wrong = [n for n, c in cells.items() if c not in ("passed", "not-done", "not-run")]
    if wrong:
        lines += [f"## {t['fix']}", ""]
        for n in wrong:
            o = g.checks[n]
            lines += [f"### {n} — {t['mistake']} `{cells[n]}`", "", "```", o.get("message", "").strip(), "```"]
            if o.get("slide"):
                lines += ["", t["reread"].format(slide=_slide(o["slide"], g.language))]
            lines.append("")
    for key, wanted in (("passed", "passed"), ("not_done", "not-done"), ("not_run", "not-run")):
        names = [n for n, c in cells.items() if c == wanted]
        if names:
            lines += [f"## {t[key]}", ""] + [f"- {_line(g.checks.get(n)) or n}" for n in names] + [""]
    problems = [t["cell_error"].format(**{"first_line": "", **e}) for e in g.cell_errors]
    if g.timed_out:
        problems.append(t["killed"].format(timeout=g.timeout + GRACE))
    elif g.interrupted:
        problems.append(t["interrupted"].format(**{"first_line": "", "cells": "?", "cell": "?", "seconds": "?",
                                                   **g.interrupted}))
    elif g.ended:
        problems.append(t["ended"].format(code=g.returncode))
    problems += [t["note"].format(note=r) for r in g.remarks]
    if problems:
        lines += [f"## {t['notebook']}", ""] + [f"- {p}" for p in problems] + [""]
    if g.status != "invalid":
        lines += [t["seconds"].format(seconds=g.seconds), ""]
    return "\n".join(lines)


def gradescope(g, check_names) -> str:
    """Gradescope's results.json for one hand-in: one test per check (1 point each)."""
    tests = []
    for n in check_names:
        o, c = g.checks.get(n), cell(g.checks.get(n), stopped(g))
        message = o.get("message", "") if o else c
        if o and o.get("slide") and c != "passed":
            message += "\n" + texts(g.language)["reread"].format(slide=_slide(o["slide"], g.language))
        tests.append({"name": n, "score": 1.0 if c == "passed" else 0.0, "max_score": 1.0,
                      "status": "passed" if c == "passed" else "failed", "output": message})
    score = sum(x["score"] for x in tests)
    return json.dumps({"score": score, "max_score": float(len(tests)), "execution_time": round(g.seconds, 1),
                       "output": f"{g.status}" + (f": {g.note}" if g.note else ""), "visibility": "visible",
                       "tests": tests}, ensure_ascii=False, indent=1)


def write_all(graded, check_names, out, feedback, gradescope_path=None, warn=None) -> list:
    """Write grades.csv, feedback/STUDENT.md for each row that can have one (feedback_names), and results.json;
    each file whole (outputs.write_text).  Returns the paths written; warn(line): a feedback file that could not
    be written (every other one is)."""
    paths = [write_text(out, csv_text(graded, check_names))]
    feedback.mkdir(parents=True, exist_ok=True)
    names = feedback_names(graded)
    for g in graded:
        if g.name in names:
            try:                        # one file that cannot be written costs no one else theirs
                paths.append(write_text(feedback / names[g.name], feedback_text(g, check_names)))
            except OSError as err:
                (warn or print)(f"feedback of {g.name[:60]!r} not written: {err.strerror or err}")
    if gradescope_path is not None:
        paths.append(write_text(gradescope_path, gradescope(graded[0], check_names)))
    return paths
