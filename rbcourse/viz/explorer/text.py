"""How the explorer writes a time step, a count and a wall time, the same on the page, in its links and in
Explorer.summary(); and its page's words (PAGE), in every language."""
from __future__ import annotations

from ...support.language import LANGUAGES, current, say

NOUNS = {"method": ("method", "méthode"), "step": ("step", "pas"), "run": ("run", "simulation")}
"""A counted noun in each language (count)."""

PLURALS = {"pas": "pas"}
"""French nouns whose plural is not the noun and an s."""

PAGE = {
    "title": ("{name}: accuracy explorer", "{name} : explorateur de précision"),
    "subtitle": ("— accuracy explorer: what each method and step cost, and what they keep",
                 "— explorateur de précision : ce que coûte chaque méthode et chaque pas de temps, et ce qu'ils "
                 "conservent"),
    "method": ("method", "méthode"),
    "method_aria": ("method (the integrator)", "méthode (l'intégrateur)"),
    "step": ("step dt", "pas dt"),
    "step_aria": ("time step dt", "pas de temps dt"),
    "play_aria": ("play or pause the animation", "lancer ou mettre en pause l'animation"),
    "time_aria": ("time t (s)", "temps t (s)"),
    "speed_aria": ("playback speed", "vitesse de lecture"),
    "real_time": ("real time", "temps réel"),
    "ghost_title": ("the reference motion, drawn semi-transparent", "le mouvement de référence, dessiné en transparence"),
    "ghost": ("ghost", "fantôme"),
    "view_aria": ("the body in 3-D", "le corps en 3-D"),
    "pane_aria": ("3-D view of the chosen run (meshcat), with the reference as a ghost",
                  "vue 3-D de la simulation choisie (meshcat), la référence en fantôme"),
    "plots_aria": ("the chosen run's drift and error over time (click a plot to jump there)",
                   "dérive et erreur de la simulation choisie au cours du temps (cliquez sur un graphique pour y aller)"),
    "wp_aria": ("work-precision: wall time against the error at the end",
                "travail-précision : temps de calcul contre l'erreur à la fin"),
    "wp_head": ("What accuracy costs: wall time vs error at t_end", "Ce que coûte la précision : temps de calcul "
                "contre erreur à t_end"),
    "wp_click": ("(click a point to pick that run)", "(cliquez sur un point pour choisir cette simulation)"),
    "notes_head": ("What is plotted, and why", "Ce qui est tracé, et pourquoi"),
    "resampling": ("Each plotted point is the largest value over the steps since the previous point, so no spike\n"
                   "    is lost in the resampling (the rotation error: over every step, or every k-th step in runs of "
                   "more than\n    {evals} body-steps); log scales. Link to one run with the page's address followed "
                   "by\n    ",
                   "Chaque point tracé est la plus grande valeur sur les pas depuis le point précédent : aucun pic "
                   "n'est perdu\n    au rééchantillonnage (l'erreur de rotation : à chaque pas, ou tous les k pas "
                   "pour les simulations de plus de\n    {evals} pas-corps) ; échelles logarithmiques. Lien vers une "
                   "simulation : l'adresse de la page suivie de\n    "),
    "scene_head": ("The scene, and every run", "La scène, et chaque simulation"),
    "th": ("<th>method</th><th>dt (s)</th><th>steps</th><th>wall time</th><th>rotation error at t_end (rad)</th>"
           "<th>position error at t_end (m)</th><th>outcome</th>",
           "<th>méthode</th><th>dt (s)</th><th>pas</th><th>temps de calcul</th><th>erreur de rotation à t_end "
           "(rad)</th><th>erreur de position à t_end (m)</th><th>issue</th>"),
    "ran_to": ("ran to t = {t:g} s", "a tourné jusqu'à t = {t:g} s"),
    "beyond_accuracy": (" Errors below its own accuracy (the dashed line in the work-precision panel) are not "
                        "resolved by this reference.",
                        " Les erreurs sous sa propre précision (la ligne en tirets du panneau travail-précision) ne "
                        "sont pas résolues par cette référence."),
    "reference": ("Reference (the ghost, and what the errors are measured against): {detail}.",
                  "Référence (le fantôme, ce à quoi les erreurs sont mesurées) : {detail}."),
    "timing": ("Wall time: time.perf_counter() around each rb.simulate call when this page was made, {warmup}; one "
               "measurement each, on the machine that made the page (the whole grid took {seconds:.3g} s, warm-ups "
               "and reference included). Error at the end: the rotation angle between R(t_end) and the reference's "
               "(rad); a run that diverged has none and sits in the top band.",
               "Temps de calcul : time.perf_counter() autour de chaque appel de rb.simulate quand cette page a été "
               "faite, {warmup} ; une mesure chacune, sur la machine qui a fait la page (toute la grille a pris "
               "{seconds:.3g} s, échauffements et référence compris). Erreur à la fin : l'angle de rotation entre "
               "R(t_end) et celle de la référence (rad) ; une simulation qui a divergé n'en a pas et se place dans la "
               "bande du haut."),
    "warmup": ("one untimed warm-up run per method before the timed runs (numba compiles a method's step at its "
               "first run: compile time excluded)",
               "une simulation d'échauffement non chronométrée par méthode avant les simulations chronométrées "
               "(numba compile le pas d'une méthode à sa première simulation : compilation exclue)"),
    "explorer_title": ("rbcourse accuracy explorer: {name}, {grid}", "explorateur de précision rbcourse : {name}, {grid}"),
    "fallback": ("<b>{title}</b>: an interactive page (pick a method and a step, watch the body and its drift "
                 "together). It needs a <i>trusted</i> notebook: {trust}. Or save it, <code>explorer.save("
                 "\"explorer.html\")</code>, and open the file in a browser.",
                 "<b>{title}</b> : une page interactive (choisissez une méthode et un pas de temps, regardez le corps "
                 "et sa dérive ensemble). Elle demande un notebook <i>de confiance</i> : {trust}. Ou enregistrez-la, "
                 "<code>explorer.save(\"explorer.html\")</code>, et ouvrez le fichier dans un navigateur."),
    "summary_head": ("{title} (reference: {label})", "{title} (référence : {label})"),
    "summary_row": ("{steps:>7} steps  {seconds:>9}  error {err:>12}  {end}",
                    "{steps:>7} pas  {seconds:>9}  erreur {err:>12}  {end}"),
    "repr": ("<Explorer: {title}; .save(path) writes the page>", "<Explorer : {title} ; .save(path) écrit la page>"),
    "drawn_note": ("drawn up to t = {t:.4g} s: after it the body is too far (|x| ≥ 1e6 m) or R too large (entries "
                   "≥ 1e15) to draw",
                   "dessinée jusqu'à t = {t:.4g} s : après, le corps est trop loin (|x| ≥ 1e6 m) ou R trop grande "
                   "(coefficients ≥ 1e15) pour être dessinés"),
    "exact_label": ("the exact torque-free motion", "le mouvement exact sans moment"),
    "exact_detail": ("the exact torque-free motion of the free body (closed form with Jacobi's elliptic functions, "
                     "rb.exact_free_body): no time step, exact to rounding",
                     "le mouvement exact sans moment du corps libre (forme close avec les fonctions elliptiques de "
                     "Jacobi, rb.exact_free_body) : sans pas de temps, exact aux arrondis près"),
    "fine_label": ("{method} at dt = {h:.3g} s", "{method} à dt = {h:.3g} s"),
    "fine_detail": ("{method} with steps {refine}× finer than the finest step of the grid (dt = {h:.3g} s or finer: "
                    "each run is compared with {method} at its step / m, at exactly its step times); its own "
                    "accuracy: {accuracy:.1e} rad at t = {t_end:g} s (the difference with {method} at twice its step)",
                    "{method} avec des pas {refine}× plus fins que le plus fin de la grille (dt = {h:.3g} s ou moins : "
                    "chaque simulation est comparée à {method} à son pas / m, exactement à ses instants) ; sa propre "
                    "précision : {accuracy:.1e} rad à t = {t_end:g} s (l'écart avec {method} au double de son pas)"),
}
"""id -> (English, French): every sentence of the explorer's page and of the Explorer's text, with the same
{placeholders} in each language."""


def page_text(key: str, **values) -> str:
    """PAGE[key] in the active language (rbcourse.support.language), its {placeholders} filled from values."""
    return PAGE[key][LANGUAGES.index(current())].format(**values)


def dt_text(dt: float) -> str:
    """dt as the page and its links write it: the shortest text that reads back as the same float."""
    return repr(float(dt))


def count(n: int, word: str) -> str:
    """n and the noun `word` (a key of NOUNS) in the active language, plural unless n is 1."""
    noun = say(*NOUNS[word])
    return f"{n} {noun if n == 1 else PLURALS.get(noun, noun + 's')}"


def fmt_seconds(x: float) -> str:
    return f"{x * 1e3:.3g} ms" if x < 1 else f"{x:.3g} s"
