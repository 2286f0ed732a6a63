"""Every sentence the views, the plots, the demo and the grader say is in the active language (issue 29, item 2):
the linked view (its page's data, the words its script shows, the page around them), the explorer (its page, its
script's words, its summary), the matplotlib plots (every text of a figure), the demo's summary and what
`demo --lang fr` prints, and the grader's feedback on a French hand-in.  Under "fr" no English sentence; under
"en" no French one.  The scripts of the pages carry no sentence of their own: every word they show is one of
viz/words.py's, which they ask for by id."""
import json
import re
from pathlib import Path

import numpy as np
import pytest

import rbcourse as rb
from rbcourse.support import glossary, language
from rbcourse.viz import words as page_words

from helpers import ENGLISH as CORE_ENGLISH, FRENCH as CORE_FRENCH

ENGLISH = CORE_ENGLISH | {
    "click", "drag", "play", "wall", "error", "errors", "reference", "ghost", "exactly", "overflow", "plotted",
    "before", "link", "unknown", "showing", "default", "accuracy", "order", "chosen", "conserved", "drift", "about",
    "over", "when", "what", "which", "this", "that", "for", "was", "were", "has", "have", "your", "you", "step",
    "run", "runs", "kinetic", "potential", "wrote", "grader", "graded", "still", "time", "rotation error",
    "problem", "least", "largest", "mistake", "passed", "checks", "fix", "feedback"}
"""English words that no French sentence of rbcourse holds (besides the names of JupyterLab's own menus)."""
FRENCH = CORE_FRENCH | {
    "erreur", "dérive", "temps", "fantôme", "référence", "lecture", "cliquez", "glissez", "méthode", "méthodes",
    "choisie", "ordre", "tracé", "lien", "inconnue", "montré", "précision", "calcul", "pour", "dans", "avec", "cette",
    "autour", "écart", "conservée", "conservé", "écrit", "votre", "vérifications", "noté", "correcteur"}
"""French words that no English sentence of rbcourse holds."""

ENGLISH_NOTEBOOK_UI = re.compile(r"View ▸ Activate Command Palette|Trust Notebook")
"""JupyterLab's own menu names: English in every language (frame.TRUST)."""


def words(text: str) -> set:
    """The words of a sentence, lower case, without what is code: HTML tags, <code>…</code>, dotted names
    (time.perf_counter, rb.simulate), calls of a name (Steps(…), save(path)), identifiers with an underscore or a
    digit (t_end, rk4, quaternion_euler_body), and JupyterLab's own menu names."""
    text = re.sub(r"\{\w+(?::[^}]*)?\}", " ", text)                       # a word's {placeholder}
    text = re.sub(r"<code>.*?</code>", " ", text, flags=re.S)
    text = re.sub(r"<[^>]+>", " ", text)
    text = re.sub(r"(?:/[\w.-]+)+", " ", text)                              # a path
    text = re.sub(r"--[\w-]+", " ", text)                                    # a command-line flag
    text = ENGLISH_NOTEBOOK_UI.sub(" ", text)
    text = re.sub(r"\b\w+(?:\.\w+)+(?:\([^)]*\))?", " ", text)
    text = re.sub(r"\b[A-Za-z_]\w*\(", "(", text)
    tokens = re.findall(r"[A-Za-zÀ-ÖØ-öø-ÿ_0-9⁻¹]+", text.replace("'", " ").replace("’", " "))
    return {w.lower() for w in tokens if not re.search(r"[_0-9]", w)}


def english_in(text: str) -> set:
    return words(text) & ENGLISH


def french_in(text: str) -> set:
    found = words(text) & FRENCH
    return found | ({"« »"} if "«" in text or "»" in text else set())


def test_the_detectors_can_fail():
    """A deliberately English sentence is found English, a French one French; code and method names are neither."""
    assert english_in("the energy drift of the run, exactly 0") and not french_in("the energy drift of the run")
    assert french_in("dérive de l'énergie, exactement 0") and not english_in("dérive de l'énergie, exactement 0")
    assert french_in("« boîte »")
    assert not english_in("rk4, euler, quaternion_euler_body, t_end, time.perf_counter(), save(path), 1e-3 rad kg m²/s, "
                          "--no-sandbox")
    assert not english_in("exécutez la cellule : View ▸ Activate Command Palette, « Trust Notebook »")


@pytest.fixture
def french():
    language.choose("fr")
    yield
    language.choose("en")


def check(where: str, text: str, code: str) -> None:
    """text holds no sentence of the other language; in French, the glossary's words."""
    if code == "fr":
        assert not english_in(text), f"{where} says English words {sorted(english_in(text))} under 'fr': {text!r}"
        assert not glossary.avoided_in(text), f"{where}: {glossary.avoided_in(text)}: {text!r}"
    else:
        assert not french_in(text), f"{where} says French words {sorted(french_in(text))} under 'en': {text!r}"


def page_text(html: str) -> str:
    """What a page shows besides its scripts' work: its text and its attributes' words, scripts and styles out."""
    html = re.sub(r"<script\b.*?</script>|<style\b.*?</style>|<code>.*?</code>", " ", html, flags=re.S)
    attributes = " ".join(re.findall(r'(?:title|aria-label)="([^"]*)"', html))
    return re.sub(r"<[^>]+>", " ", html) + " " + attributes


BOX = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
FAST = rb.State.from_velocities(BOX, np.zeros(3), np.eye(3), np.zeros(3), (0.1, 0.1, 50.0))


def linked_sentences():
    """(where, text) of a linked view: its data's titles, notes and labels, its script's words, the page around."""
    from rbcourse.viz import viewer
    from rbcourse import examples
    ex = examples.box_on_spring()
    run = rb.simulate(ex.scene, ex.X0, 0.5, 1e-2, "rk4")
    blew = rb.simulate(BOX, FAST, 60.0, 1e-2, "euler", on_divergence="stop")
    out = []
    for drawing in (viewer.draw_trajectory(run, ghost=run, plots=True), viewer.draw_trajectory(blew, plots=True)):
        data = drawing.plots
        out += [("panel title", p["title"]) for p in data["panels"]] + [("panel note", p["note"] or "") for p in
                                                                        data["panels"]]
        out += [("bar note", n) for n in data["notes"]] + [("series", s["label"]) for s in data["series"]]
        out += [("legend", t) for _, t in drawing.legend] + [("title", drawing.title), ("fallback", drawing._fallback())]
        html = drawing.html()
        assert f'<html lang="{language.current()}">' in html
        boot = re.search(r"rbTimeline\(viewer, [^,]+, [^,]+, [^,]+, (\{.*?\})\);", html).group(1)
        out += [(f"script word {k}", v) for k, v in json.loads(boot).items()]
        out.append(("page", page_text(html)))
    return out


@pytest.mark.parametrize("code", ["fr", "en"])
def test_the_linked_view_in_the_active_language(code):
    language.choose(code)
    try:
        said = linked_sentences()
    finally:
        language.choose("en")
    for where, text in said:
        check(where, text, code)
    if code == "fr":
        everything = "\n".join(t for _, t in said)
        for phrase in ("exactement 0", "fantôme : référence", "▶ lecture", "divergé à t = {t} s", "écart à SO(3)", "écart de rotation à « référence »"):
            assert phrase in everything, phrase


def test_the_pages_scripts_carry_no_sentence_of_their_own():
    """Every word the scripts show is asked for by id (rbSay) and is one of viz/words.py's; no string literal of
    theirs with a space holds an English word."""
    from rbcourse.viz.explorer.page import script as explorer_script
    from rbcourse.viz.viewer import assets
    scripts = {"runtime": assets.RUNTIME, "timeplots": assets.TIMEPLOTS, "explorer": explorer_script()}
    asked = set()
    for name, js in scripts.items():
        asked |= set(re.findall(r'rbSay\(\s*"(\w+)"', js))
        asked |= {k for pair in re.findall(r'rbSay\([^")]*\?\s*"(\w+)"\s*:\s*"(\w+)"', js) for k in pair}
        code = re.sub(r"//[^\n]*|/\*.*?\*/|throw new Error\(.*?\);", " ", js, flags=re.S)   # an API's error: code
        for literal in re.findall(r'"((?:[^"\\\n]|\\.)*)"', code):
            if " " in literal and not literal.startswith("<"):
                assert not english_in(literal), f"{name}: English literal {literal!r}"
    assert asked and asked <= set(page_words.WORDS), sorted(asked - set(page_words.WORDS))
    for key, texts in page_words.WORDS.items():
        fields = [set(re.findall(r"\{(\w+)\}", t)) for t in texts]
        assert all(f == fields[0] for f in fields), key
        check(f"WORDS[{key!r}] (fr)", texts[1], "fr")
        check(f"WORDS[{key!r}] (en)", texts[0], "en")


def test_a_js_literal_in_english_would_be_found():
    """The scan above fails on an English literal (what it is for)."""
    assert english_in("the run diverged at t = ") and english_in("▶ play")


@pytest.mark.parametrize("code", ["fr", "en"])
def test_the_explorer_in_the_active_language(code):
    from rbcourse.viz import explore
    from rbcourse.viz.explorer import page
    from rbcourse.examples import pushed_box
    from tests.viz.test_explorer import page_json
    language.choose(code)
    try:
        ex = explore(pushed_box(), methods=["euler", "rk4"], dts=[0.02, 0.01], t_end=1.0, frames=30)
        html = ex.html()
        data = page_json(html)
        said = [("page", page_text(html)), ("summary", ex.summary()), ("repr", repr(ex)),
                ("fallback", ex._repr_html_().split("<iframe")[0])]
        said += [(f"word {k}", v) for k, v in data["words"].items()]
        said += [(f"panel {p['key']}", p["title"] + " " + p["note"] + " " + p["unit"]) for p in data["panels"]]
        said += [("run reason", r["reason"]) for r in data["runs"]] + [("reference", data["reference"]["label"])]
        assert data["lang"] == code and f'<html lang="{code}">' in html
    finally:
        language.choose("en")
    for where, text in said:
        check(where, text, code)
    if code == "fr":
        assert "2 méthodes × 2 pas (4 simulations)" in said[0][1] and "a divergé" in said[1][1]


def figure_texts(fig) -> str:
    import matplotlib.text
    return "\n".join(t.get_text() for t in fig.findobj(matplotlib.text.Text) if t.get_text())


@pytest.mark.parametrize("code", ["fr", "en"])
def test_the_plots_labels_in_the_active_language(code):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from rbcourse.viz import plots
    from rbcourse import examples
    language.choose(code)
    try:
        ex = examples.box_on_spring()
        run = rb.simulate(ex.scene, ex.X0, 0.5, 1e-2, "rk4")
        blew = rb.simulate(BOX, FAST, 60.0, 1e-2, "euler", on_divergence="stop")
        free = rb.simulate(BOX, FAST, 0.5, 1e-3, "rk4")
        texts = []
        for trajs in ([run], [free, blew]):
            axes = plots.plot_drift(trajs)
            axes[0].figure.canvas.draw()
            texts.append(figure_texts(axes[0].figure))
            plt.close(axes[0].figure)
            axes = plots.plot_energy_momentum(trajs[-1])
            texts.append(figure_texts(axes[0].figure))
            plt.close(axes[0].figure)
    finally:
        language.choose("en")
    for text in texts:
        check("a plot's texts", text, code)
    if code == "fr":
        assert any("énergie" in t for t in texts) and any("divergé" in t for t in texts)


@pytest.mark.parametrize("code", ["fr", "en"])
def test_the_demo_summary_and_what_demo_prints(code, tmp_path, capsys):
    from rbcourse.__main__ import main
    try:
        assert main(["demo", "--t-end", "0.5", "--lang", code, "--out", str(tmp_path)]) == 0
    finally:
        language.choose("en")
    printed = capsys.readouterr().out
    summary = (tmp_path / "pushed_box_summary.txt").read_text(encoding="utf-8")
    check("demo --lang's output", printed, code)
    check("the demo's summary", summary, code)
    check("the demo's linked view", page_text((tmp_path / "pushed_box.html").read_text(encoding="utf-8")), code)
    if code == "fr":
        assert summary.startswith("Scène 'boîte poussée' : ") and "Intégrateur : rk4." in summary, summary
        assert "écrit : " in printed


FRENCH_HANDIN = json.dumps({"cells": [{"cell_type": "code", "metadata": {}, "execution_count": None, "outputs": [],
                                       "source": ["from rbcourse.workbook import exercises as ex\n", 'ex.langue("fr")']}],
                            "metadata": {}, "nbformat": 4, "nbformat_minor": 5})


def test_the_graders_feedback_on_a_french_hand_in(monkeypatch):
    """A French hand-in's feedback, the grader's remark on it included, is in French (the grader's failure on it:
    no sandbox needed to get there); an English hand-in's in English."""
    from rbcourse.workbook.grading import plan, report, runner, sandbox, submissions
    from rbcourse.workbook.grading.checker import checks

    def no_room(*args, **kwargs):
        raise OSError(28, "No space left on device")
    monkeypatch.setattr(sandbox, "start", no_room)
    names = [name for name, _ in checks()]
    for code, text in (("fr", FRENCH_HANDIN), ("en", FRENCH_HANDIN.replace('langue(\\"fr\\")', 'langue(\\"en\\")'))):
        g = runner.grade_task((submissions.Handin("ann", "ann.ipynb", text), runner.Settings(plan.MIN_TIMEOUT)))
        assert g.language == code and g.status == "error"
        feedback = report.feedback_text(g, names)
        check("the grader's remark", g.note.split("(OSError")[0], code)
        check("the grader's feedback", feedback.replace("No space left on device", ""), code)
        if code == "fr":
            assert "le correcteur a échoué sur ce rendu (OSError" in g.note and "Retour sur votre notebook" in feedback


def test_the_exercises_run_of_the_students_code_is_labelled_in_french(french):
    from rbcourse.workbook.exercises.texts import tr
    assert tr("your_code").format(method="euler") == "euler (votre code)"


def test_the_grade_summary_in_french(french):
    """What `grade --lang fr` prints at the end, in French; in English under "en"."""
    from types import SimpleNamespace
    from rbcourse.workbook.grading import plan as grading
    graded = [SimpleNamespace(status="ok"), SimpleNamespace(status="error")]
    settings = SimpleNamespace(gradescope=None, feedback=Path("retours"))
    said = grading.summary(graded, [Path("grades.csv"), Path("a.md"), Path("b.md")], settings)
    check("grade's summary", said, "fr")
    assert said.startswith("2 rendus notés : 1 ok, 1 erreur") and "écrit : grades.csv et 2 fichiers de retour" in said
    language.choose("en")
    said = grading.summary(graded, [Path("grades.csv"), Path("a.md"), Path("b.md")], settings)
    check("grade's summary", said, "en")
    assert said.startswith("graded 2 hand-ins: 1 ok, 1 error")


@pytest.mark.parametrize("code", ["fr", "en"])
def test_the_csv_note_in_the_language_of_grade_lang(code):
    """How a hand-in's notebook ran (the CSV's note) in the language grade --lang gave (Settings.language)."""
    from rbcourse.workbook.grading import runner
    expected = {"fr": "1 cellule(s) ont levé une exception ; la première : cellule de code 3 (x = 1 / 0) : ZeroDivisionError",
                "en": "1 cell(s) raised; first: code cell 3 (x = 1 / 0): ZeroDivisionError"}
    ran = {"errors": [{"cell": 3, "first_line": "x = 1 / 0", "error": "ZeroDivisionError"}], "interrupted": None,
           "language": "fr"}
    g = runner.Graded("ann", "ok", timeout=30.0)
    runner._notebook(g, ran, "", 0.0, lambda: 0.0, code)
    assert g.status == "error" and g.note == expected[code]
    check("the CSV's note", g.note.replace("ZeroDivisionError", ""), code)
    g = runner.Graded("bob", "ok", timeout=30.0)
    runner._notebook(g, None, "Killed", 0.0, lambda: 0.0, code)
    check("the CSV's note (ended)", g.note, code)


def test_a_progress_bar_in_french(french, capsys):
    from rbcourse.support import outputs
    with outputs.progress(3, "step", "simulate", True) as bar:
        bar.update(3)
    err = capsys.readouterr().err
    assert "simulation: 100%" in err and "pas/s" in err, err
    language.choose("en")
    with outputs.progress(3, "run", "explore", True) as bar:
        bar.update(3)
    err = capsys.readouterr().err
    assert "explore: 100%" in err and "run/s" in err, err


def test_grade_lang_fr_on_a_wrong_french_hand_in_without_the_sandbox(tmp_path, capsys):
    """`grade --no-sandbox --lang fr` on the French solution with v = P · M: what it prints, the CSV's note and the
    feedback (the mistake, the slide to reread, the grader's remark) in French, no English sentence."""
    from rbcourse.__main__ import main
    solution = Path(__file__).resolve().parents[1] / "notebooks" / "fr" / "solutions" / "01_exercice_euler.ipynb"
    nb = json.loads(solution.read_text(encoding="utf-8"))
    cells = [c for c in nb["cells"] if c["cell_type"] == "code" and "return P / M" in "".join(c["source"])]
    assert len(cells) == 1
    cells[0]["source"] = "".join(cells[0]["source"]).replace("return P / M", "return P * M")
    (tmp_path / "subs").mkdir()
    (tmp_path / "subs" / "bob.ipynb").write_text(json.dumps(nb, ensure_ascii=False), encoding="utf-8")
    try:
        assert main(["grade", str(tmp_path / "subs"), "--seed", "0", "--out", str(tmp_path / "grades.csv"), "--no-sandbox",
                     "--workers", "1", "--lang", "fr"]) == 0
    finally:
        language.choose("en")
    printed = capsys.readouterr()
    feedback = (tmp_path / "feedback" / "bob.md").read_text(encoding="utf-8")
    note = (tmp_path / "grades.csv").read_text(encoding="utf-8").splitlines()[1].split(",")[-1]
    check("grade --lang fr's output", printed.out + printed.err, "fr")
    check("the CSV's note", note, "fr")
    check("the feedback", re.sub(r"^#+ \w+ — erreur `\w+`$|^- ✓ \w+ ", "", feedback, flags=re.M), "fr")
    assert "1 rendu noté : 1 ok" in printed.out and "non protégé : noté sans bac à sable" in note
    assert "vous avez multiplié P par M" in feedback and "À relire : la slide" in feedback


@pytest.mark.parametrize("code", ["fr", "en"])
def test_why_a_hand_in_cannot_be_graded_in_the_active_language(code, tmp_path):
    from rbcourse.workbook.grading import submissions
    (tmp_path / "ann.ipynb").write_text("{ not json", encoding="utf-8")
    (tmp_path / "bob.txt").write_text("hello", encoding="utf-8")
    (tmp_path / "cat.ipynb").write_text('{"cells": 3}', encoding="utf-8")
    (tmp_path / "dan").mkdir()
    language.choose(code)
    try:
        problems = {h.name: h.problem for h in submissions.read(tmp_path)}
    finally:
        language.choose("en")
    assert len(problems) == 4 and all(problems.values()), problems
    for name, problem in problems.items():
        check(f"why {name} cannot be graded", problem.replace("STUDENT", ""), code)
