"""The words the pages' scripts show (a view's time line, the linked view's plots and bar, the explorer's controls,
panels, notes and link notes), each id once with its text in every language: the scripts carry no sentence of
their own, they read these (script_words(), in the page's data) and fill in the {placeholders} (rbSay in
viewer/js/timeplots.js).  The French words are the glossary's (rbcourse.support.glossary)."""
from __future__ import annotations

from ..support.language import LANGUAGES, current

WORDS = {
    # a view's time line (viewer/assets.py, rbTimeline)
    "played_at": ("  (played at ×{speed})", "  (joué à ×{speed})"),
    "bad_t": ("#t={t}: t must be a time in [{t0}, {t1}] s; the animation plays instead",
              "#t={t} : t doit être un temps dans [{t0}, {t1}] s ; l'animation est jouée à la place"),
    # the plots over time (viewer/js/timeplots.js)
    "exactly_0": ("exactly 0", "exactement 0"),
    "overflow": ("∞ (overflow)", "∞ (dépassement)"),
    "plot_aria": ("{title} over time: click or drag to move the time cursor",
                  "{title} au cours du temps : cliquez ou glissez pour déplacer le curseur de temps"),
    "diverged": ("diverged", "divergé"),
    "diverged_at": ("diverged at t = {t} s", "divergé à t = {t} s"),
    "before_t0": ("not plotted before t₀ = {t0} s", "non tracé avant t₀ = {t0} s"),
    "colon": (": ", " : "),
    "semicolon": ("; ", " ; "),
    "play": ("▶ play", "▶ lecture"),
    "pause": ("❚❚ pause", "❚❚ pause"),
    "play_title": ("play or pause the animation", "lancer ou mettre en pause l'animation"),
    # the explorer (explorer/js)
    "method_title": ("{name} (order {order}): {summary}", "{name} (ordre {order}) : {summary}"),
    "run_diverged": ("{method}, dt = {dt} s: {reason}", "{method}, dt = {dt} s : {reason}"),
    "dt_title": ("{steps} steps; error at the end {error} rad", "{steps} pas ; erreur à la fin {error} rad"),
    "status": ("<b>{method}</b>, dt = {dt} s ({steps} steps of {h} s), wall time {seconds}: ",
               "<b>{method}</b>, dt = {dt} s ({steps} pas de {h} s), temps de calcul {seconds} : "),
    "status_diverged": ("<b>{reason}</b>: its curves stop at its last finite state, t = {t_last} s (×), and the "
                        "animation at t = {drawn} s{why}.",
                        "<b>{reason}</b> : ses courbes s'arrêtent à son dernier état fini, t = {t_last} s (×), et "
                        "l'animation à t = {drawn} s{why}."),
    "status_ran": ("ran to t = {t_last} s; rotation error at the end {error} rad, position error {position} m.",
                   "a tourné jusqu'à t = {t_last} s ; erreur de rotation à la fin {error} rad, erreur de position "
                   "{position} m."),
    "unknown_key": ("unknown key “{key}” ignored", "clé inconnue « {key} » ignorée"),
    "unknown_method": ("unknown method “{method}”: showing the default method {default} (this page has {all})",
                       "méthode inconnue « {method} » : la méthode par défaut {default} est montrée (cette page a "
                       "{all})"),
    "unknown_dt": ("no step dt = “{dt}” here: showing the default dt = {default} s (this page has dt = {all} s)",
                   "aucun pas dt = « {dt} » ici : le dt par défaut = {default} s est montré (cette page a "
                   "dt = {all} s)"),
    "bad_link_t": ("t = “{t}” is not a time in [0, {t_end}] s: the animation plays from the start",
                   "t = « {t} » n'est pas un temps dans [0, {t_end}] s : l'animation est jouée depuis le début"),
    "link": ("Link: {notes}.", "Lien : {notes}."),
    "shown_last_drawable": ("{method}, dt = {dt} s: {reason}; shown at its last drawable state, t = {t} s",
                            "{method}, dt = {dt} s : {reason} ; montré à son dernier état dessinable, t = {t} s"),
    "shown_last_finite": ("{method}, dt = {dt} s: {reason}; shown at its last finite state, t = {t} s",
                          "{method}, dt = {dt} s : {reason} ; montré à son dernier état fini, t = {t} s"),
    "ghost_reference": ("ghost: reference ({label})", "fantôme : référence ({label})"),
    "axes_xyz": ("axes x y z", "axes x y z"),
    "drag_hint": (" — drag to turn the view, scroll to zoom", " — glissez pour tourner la vue, molette pour zoomer"),
    "wp_x": ("wall time of the run (s, numba compile excluded)",
             "temps de calcul de la simulation (s, compilation numba exclue)"),
    "wp_y": ("rotation error at t_end (rad)", "erreur de rotation à t_end (rad)"),
    "reference_accuracy": ("the reference's own accuracy", "précision propre de la référence"),
    "wp_point": ("{method}, dt = {dt} s: {seconds}, error {error} rad", "{method}, dt = {dt} s : {seconds}, erreur {error} rad"),
    "wp_point_diverged": ("{method}, dt = {dt} s: {seconds}, diverged", "{method}, dt = {dt} s : {seconds}, divergé"),
    "order": ("{name} (order {order})", "{name} (ordre {order})"),
    "chosen_run": ("the chosen run", "la simulation choisie"),
}
"""id -> (English, French): every word a page's script shows, with the same {placeholders} in each language."""


def script_words(code: str | None = None) -> dict:
    """{id: text} of WORDS in the language `code` (default: the active one, rbcourse.support.language): what a page's data
    carries for its script."""
    i = LANGUAGES.index(code or current())
    return {key: texts[i] for key, texts in WORDS.items()}
