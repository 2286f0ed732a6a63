"""What grading writes: grades.csv (one row per student), a feedback file per student, and optionally
Gradescope's results.json (one hand-in).

A check's cell in the CSV: ``passed``, the mistake's id (``velocity_times_mass``, ``wrong_result``, …),
``not-done`` (NotImplementedError, or no such function), ``crashed`` (the student's function raised),
``not-run`` (the hand-in was stopped before the check could run), or ``timeout`` (the student's function
was still running when the check's time was up).

The feedback's own words come from TEXTS by the hand-in's language (runner.notebook_language: "en" or
"fr"); the checks' messages and the slides to reread are the worker's, which ran in that language (it starts
in it, and the notebook's own ex.langue(…) call, which decided it, runs again there).  The CSV is the same
in every language (the mistakes' ids).
"""
from __future__ import annotations

import csv
import io
import json

from ...outputs import write_text
from ..exercises.slides import SLIDES, SOURCES
from .runner import GRACE

TEXTS = {
    "en": {
        "title": "Feedback on your exercise notebook — {name}",
        "status": {"ok": "your notebook ran to the end",
                   "error": "your notebook ran, but something in it failed (below)",
                   "timeout": "your notebook was stopped at its time limit: something in it runs for too long "
                              "(an endless loop?)",
                   "wrote-outside": "your notebook changed files outside its own folder (below): a notebook must "
                                    "only write beside itself"},
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
        "interrupted": "code cell {cell} of {cells} (`{first_line}`) was still running at its time limit ({seconds:g} s):"
                       " it was interrupted, and the cells after it did not run",
        "changed": "outside its own folder, it {path}",
        "created": "created",
        "deleted": "deleted",
        "modified": "modified",
        "ended": "it ended before its checks could run (exit code {code})",
    },
    "fr": {
        "title": "Retour sur votre notebook d'exercice — {name}",
        "status": {"ok": "votre notebook s'est exécuté jusqu'au bout",
                   "error": "votre notebook s'est exécuté, mais quelque chose y a échoué (voir plus bas)",
                   "timeout": "votre notebook a été arrêté à sa limite de temps : quelque chose y tourne trop "
                              "longtemps (une boucle sans fin ?)",
                   "wrote-outside": "votre notebook a modifié des fichiers hors de son propre dossier (voir plus "
                                    "bas) : un notebook ne doit écrire qu'à côté de lui-même"},
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
                       "({seconds:g} s) : elle a été interrompue, et les cellules suivantes n'ont pas été exécutées",
        "changed": "hors de son propre dossier, il a {path}",
        "ended": "il s'est terminé avant que ses vérifications puissent s'exécuter (code de sortie {code})",
        "created": "créé",
        "deleted": "supprimé",
        "modified": "modifié",
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
    return {"not_done": "not-done", "error": "crashed", "out_of_time": "timeout"}.get(mistake, mistake)


def stopped(g) -> bool:
    """The hand-in stopped before its end (killed, interrupted at its limit, or ended early)."""
    return g.timed_out or bool(g.interrupted) or not g.finished


def columns(check_names) -> list[str]:
    return ["student", "status", *check_names, "passed", "seconds", "note"]


def csv_text(graded, check_names) -> str:
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(columns(check_names))
    for g in graded:
        cells = [cell(g.checks.get(n), stopped(g)) for n in check_names]
        w.writerow([g.name, g.status, *cells, cells.count("passed"), f"{g.seconds:.1f}", g.note])
    return out.getvalue()


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


def _change(change: str, t: dict) -> str:
    """'deleted /path' (runner.differences) in the feedback's language."""
    verb, _, path = change.partition(" ")
    return f"{t[verb]} {path}" if verb in ("created", "deleted", "modified") else change


def feedback_text(g, check_names) -> str:
    """The student's feedback (Markdown): the status, each mistake with its explanation and the slide to reread,
    what passed, what is not done, and what went wrong when the notebook ran."""
    t = texts(g.language)
    cells = {n: cell(g.checks.get(n), stopped(g)) for n in check_names}
    lines = [f"# {t['title'].format(name=g.name)}", "", f"**{g.status}**: {t['status'][g.status]}.", "",
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
        problems.append(t["interrupted"].format(**{"first_line": "", "cells": "?", "cell": "?", "seconds": 0,
                                                   **g.interrupted}))
    elif not g.finished:
        problems.append(t["ended"].format(code=g.returncode))
    problems += [t["changed"].format(path=_change(c, t)) for c in g.changed]
    if problems:
        lines += [f"## {t['notebook']}", ""] + [f"- {p}" for p in problems] + [""]
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


def write_all(graded, check_names, out, feedback, gradescope_path=None) -> list:
    """Write grades.csv, feedback/STUDENT.md for each, and results.json; returns the paths written."""
    paths = [write_text(out, csv_text(graded, check_names))]
    feedback.mkdir(parents=True, exist_ok=True)
    for g in graded:
        paths.append(write_text(feedback / f"{g.name}.md", feedback_text(g, check_names)))
    if gradescope_path is not None:
        paths.append(write_text(gradescope_path, gradescope(graded[0], check_names)))
    return paths
