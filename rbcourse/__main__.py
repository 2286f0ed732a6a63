"""Command line:
    python -m rbcourse demo [scene] [--method M] [--t-end T] [--dt DT] [--out DIR] [--open] [--lang fr]
    python -m rbcourse explore [scene] [--methods ...] [--dts ...] [--t-end T] [--out DIR] [--lang fr]
    python -m rbcourse bench [--problems A B C] [--methods ...] [--quick] [--no-peers] [--repeats R] [--out DIR] [--lang fr]
                             [--errors-only [--workers N] [--scheduler ADDRESS]]
    python -m rbcourse throughput [--bodies N] [--quick] [--no-peers] [--out DIR]
    python -m rbcourse throughput --compile [--methods a,b] [--out DIR]
    python -m rbcourse stability [--quick] [--cases ...] [--methods ...] [--out DIR] [--workers N] [--scheduler ADDRESS] [--lang fr]
    python -m rbcourse grade SUBMISSIONS/ --out grades.csv [--timeout S] [--feedback DIR] [--gradescope results.json]
                             [--workers N] [--scheduler ADDRESS] [--no-sandbox] [--lang fr]
    python -m rbcourse assignment build [--check] [SOLUTION ...]
    python -m rbcourse compile [--methods a,b]
    python -m rbcourse notebooks [--to DIR] [--solutions]

A bad argument (an unknown scene, method, problem, case or flag, a number that is not finite or
out of range, an --out that cannot take files) exits with code 2 and one line on stderr,
``python -m rbcourse COMMAND: error: …``, before anything is computed or written: every argument
is checked first, then --out is created and probed with a temporary file.

Ctrl-C (SIGINT) exits with code 130 and one line on stderr, `python -m rbcourse COMMAND: interrupted`, at any
moment: while Python imports the package, while numba compiles (LLVM's callbacks into Python are left to return
first), as the process ends (support/interrupts.py).  `bench` and `stability` keep the
runs finished so far: their CSV grows one row per run as it finishes, and on Ctrl-C the CSV and
the report are written whole, the report beginning "# partial: interrupted after N of M … runs".

`assignment build --check` writes nothing and exits 1 when a stored student notebook differs from what
its solution notebook generates (naming each).
"""
from __future__ import annotations

import argparse
import math
import signal
import sys
import time

from .support import interrupts
if __name__ == "__main__":
    interrupts.install()      # Ctrl-C is the command line's before the commands' modules load (support/interrupts.py)
from .support import language
from .bench import commands as reports
from .bench.commands import checked as _checked

PROG = "python -m rbcourse"


class _Parser(argparse.ArgumentParser):
    """argparse, whose errors are one line, `python -m rbcourse demo: error: …`, exit code 2 (no usage)."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {' '.join(str(message).split())}\n")


def _positive(text: str) -> float:
    """A finite number > 0 (not nan, not inf)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number > 0, got {text!r}") from None
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be a finite number > 0, got {text!r}")
    return value


def _integer(low: int, high: int):
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            value = None
        if value is None or not low <= value <= high:
            raise argparse.ArgumentTypeError(f"must be an integer from {low:,} to {high:,}, got {text!r}")
        return value
    return parse


def _parser():
    """The parser, and its sub-parsers by command."""
    from .bench.work_precision import MAX_REPEATS
    from .bench.hardcases import names as hard_cases
    from .methods import METHODS
    from .bench.problems import PROBLEMS
    from .examples import SCENES
    from .bench.box_scenes import MAX_BODIES       # not throughput.py: the parser stays light (the demo's start)
    methods = sorted(METHODS)
    names = ", ".join(methods)
    parser = _Parser(prog=PROG, description="rigid-body simulation workbook")
    sub = parser.add_subparsers(dest="command", required=True)
    demo = sub.add_parser("demo", help="simulate a named scene and write plots, data and a 3-D page")
    demo.add_argument("scene", nargs="?", default="pushed_box", choices=sorted(SCENES))
    demo.add_argument("--method", default=None, choices=methods, metavar="METHOD",
                      help=f"integrator: {names} (default: the scene's)")
    demo.add_argument("--t-end", type=_positive, default=None, help="duration (s, > 0)")
    demo.add_argument("--dt", type=_positive, default=None, help="time step (s, > 0, <= the duration)")
    demo.add_argument("--out", default="demo_output",
                      help="output folder (default: demo_output); files named after the scene, SCENE_summary.txt, …")
    demo.add_argument("--open", action="store_true",
                      help="also serve the animation live (meshcat, on 127.0.0.1) until Ctrl-C; prints its URL")
    from .viz.explorer.runs import DEFAULT_METHODS, MAX_DTS, MAX_METHODS
    explore = sub.add_parser("explore", help="every method × step on a named scene, on one interactive page "
                                             "(offline: SCENE_explorer.html)")
    explore.add_argument("scene", nargs="?", default="pushed_box", choices=sorted(SCENES))
    explore.add_argument("--methods", nargs="+", default=None, choices=methods, metavar="METHOD",
                         help=f"at most {MAX_METHODS} integrators among {names} "
                              f"(default: {' '.join(DEFAULT_METHODS)})")
    explore.add_argument("--dts", nargs="+", type=_positive, default=None, metavar="DT",
                         help=f"at most {MAX_DTS} time steps (s, > 0, <= the duration; default: the scene's dt "
                              "× 20, 10, 5, 2.5)")
    explore.add_argument("--t-end", type=_positive, default=None, help="duration (s, > 0; default: the scene's)")
    explore.add_argument("--out", default="demo_output",
                         help="output folder (default: demo_output, beside the demo's files); writes "
                              "SCENE_explorer.html")
    bench = sub.add_parser("bench", help="work-precision benchmark on problems A, B, C, beside scipy and MuJoCo")
    bench.add_argument("--problems", nargs="+", default=["A", "B", "C"], choices=sorted(PROBLEMS), metavar="P",
                       help="among A B C (default: all)")
    bench.add_argument("--methods", nargs="+", default=None, choices=methods, metavar="METHOD",
                       help=f"integrators among {names} (default: all)")
    bench.add_argument("--quick", action="store_true", help="a short sweep (seconds, for CI)")
    bench.add_argument("--no-peers", action="store_true", help="skip scipy and MuJoCo")
    bench.add_argument("--repeats", type=_integer(1, MAX_REPEATS), default=None,
                       help=f"timed repeats per run (median; default 5, quick 1; at most {MAX_REPEATS})")
    bench.add_argument("--out", default="bench_output", help="output folder (default: bench_output)")
    bench.add_argument("--errors-only", action="store_true",
                       help="the same sweep untimed, for the errors and observed orders alone (results.csv, results.md)")
    bench.add_argument("--workers", default=None, metavar="N",
                       help="with --errors-only: runs at once on N processes (an integer >= 1; default: every core); "
                            "timed runs stay serial")
    bench.add_argument("--scheduler", default=None, metavar="ADDRESS",
                       help="with --errors-only: run on the Dask cluster at ADDRESS (e.g. tcp://host:8786) instead")
    thr = sub.add_parser("throughput", help="what each effect costs; bodies per second, beside MuJoCo")
    thr.add_argument("--bodies", type=_integer(2, MAX_BODIES), default=10000,
                     help="N for the many-body runs (default 10000, at most 10⁶)")
    thr.add_argument("--quick", action="store_true", help="few steps (for CI)")
    thr.add_argument("--no-peers", action="store_true", help="skip MuJoCo")
    thr.add_argument("--compile", action="store_true",
                     help="the compile-cost report alone: each family's first simulate() and the demo, cold (empty "
                          "numba cache) and warm, each in a fresh process, one at a time (many minutes)")
    thr.add_argument("--methods", default=None, metavar="A,B",
                     help="with --compile: the families measured, one method each, comma-separated (default: euler, "
                          "rk4, symplectic_euler, implicit_midpoint, adaptive, exact_splitting)")
    thr.add_argument("--out", default="throughput_output",
                     help="output folder for throughput.md, or compile_cost.md with --compile (default: "
                          "throughput_output)")
    stab = sub.add_parser("stability", help="the stability matrix: every hard case × every method")
    stab.add_argument("--quick", action="store_true", help="short runs (as under test, RBCOURSE_QUICK=1)")
    stab.add_argument("--cases", nargs="+", default=None, choices=hard_cases(), metavar="CASE",
                      help=f"hard cases among {', '.join(hard_cases())} (default: all)")
    stab.add_argument("--methods", nargs="+", default=None, choices=methods, metavar="METHOD",
                      help=f"integrators among {names} (default: all)")
    stab.add_argument("--out", default="stability_output", help="output folder (default: stability_output)")
    stab.add_argument("--workers", default=None, metavar="N",
                      help="cells run at once on N processes (an integer >= 1; default: every core, os.cpu_count())")
    stab.add_argument("--scheduler", default=None, metavar="ADDRESS",
                      help="run the cells on the Dask cluster at ADDRESS (e.g. tcp://host:8786) instead")
    for reported in (demo, explore, bench, stab):
        reported.add_argument("--lang", default="en", choices=language.LANGUAGES, help="the language of what it "
                              "writes and prints: en (default) or fr")
    from .workbook.grading.plan import DEFAULT_TIMEOUT, MAX_TIMEOUT, MIN_TIMEOUT
    grade = sub.add_parser("grade", help="run each student's exercise notebook alone and write grades.csv and "
                                         "feedback per student")
    grade.add_argument("submissions", metavar="SUBMISSIONS",
                       help="a folder of hand-ins: STUDENT.ipynb, or STUDENT/ holding one notebook")
    grade.add_argument("--out", required=True, help="the CSV to write (one row per student), e.g. grades.csv")
    grade.add_argument("--timeout", type=_positive, default=DEFAULT_TIMEOUT,
                       help=f"each hand-in's wall-time limit (s, {MIN_TIMEOUT:g} to {MAX_TIMEOUT:g}; "
                            f"default {DEFAULT_TIMEOUT:g})")
    grade.add_argument("--feedback", default=None,
                       help="folder for the feedback files STUDENT.md (default: feedback/ beside --out)")
    grade.add_argument("--gradescope", default=None, metavar="RESULTS_JSON",
                       help="also write Gradescope's results.json (one hand-in only)")
    grade.add_argument("--workers", default=None, metavar="N",
                       help="hand-ins graded at once on N processes (an integer >= 1; default: every core)")
    grade.add_argument("--scheduler", default=None, metavar="ADDRESS",
                       help="grade on the Dask cluster at ADDRESS (e.g. tcp://host:8786; its machines need bwrap)")
    grade.add_argument("--no-sandbox", action="store_true",
                       help="run the notebooks without the bubblewrap sandbox: the grades are NOT protected")
    grade.add_argument("--seed", type=_integer(0, (1 << 48) - 1), default=None, metavar="S",
                       help="the check inputs' seed, to grade again on the same inputs (default: a new secret one, "
                            "printed; 0: the notebook's own inputs)")
    grade.add_argument("--lang", default="en", choices=language.LANGUAGES,
                       help="the language of what it prints: en (default) or fr (each feedback is in its hand-in's)")
    assignment = sub.add_parser("assignment", help="instructors: each student notebook generated from its solution "
                                                   "notebook (a checkout tool: the wheel ships no notebooks)")
    build = assignment.add_subparsers(dest="action", required=True, metavar="{build}").add_parser(
        "build", help="write each student notebook from its solution notebook (### BEGIN/END SOLUTION → stub), "
                      "run under RBCOURSE_QUICK=1 to store its outputs")
    build.add_argument("solutions", nargs="*", metavar="SOLUTION",
                       help="solution notebooks, each in a solutions/ folder: solutions/X.ipynb writes X.ipynb in "
                            "the folder above (default: every notebooks/**/solutions/*.ipynb of this checkout)")
    build.add_argument("--check", action="store_true",
                       help="write nothing; exit 1 naming each stored student notebook that differs from what its "
                            "solution generates (outputs and execution counts aside)")
    warm = sub.add_parser("compile", help="instructors: compile every method's engine code once, ahead of time "
                                          "(a lab image, a JupyterHub): numba's disk cache, read by every later run")
    warm.add_argument("--methods", default=None, metavar="A,B",
                      help=f"comma-separated, among {names} (default: all)")
    books = sub.add_parser("notebooks", help="students: your own copies of the workbook to work in (my_notebooks/), "
                                             "never overwritten: a newer version goes beside yours as NAME.updated.ipynb")
    books.add_argument("--to", default="my_notebooks", metavar="DIR", help="the folder of the copies (default: "
                       "my_notebooks, in the current folder; created if missing)")
    books.add_argument("--solutions", action="store_true", help="copy the solution notebooks too")
    sub.metavar = "{" + ",".join(sub.choices) + "}"     # every command added above, named in the usage and the error
    return parser, {"demo": demo, "explore": explore, "bench": bench, "throughput": thr, "stability": stab,
                    "grade": grade, "assignment": build, "compile": warm, "notebooks": books}


def main(argv=None, *, wait=None) -> int:
    """Run the command line.  wait(url): how `demo --open` waits while serving (default: until Ctrl-C)."""
    parser, commands = _parser()
    args, extra = parser.parse_known_args(argv)
    command = commands[args.command]
    if extra:
        command.error(f"unrecognized arguments: {' '.join(extra)}")
    run = {"demo": _demo, "explore": _explore, "bench": reports.bench, "throughput": reports.throughput,
           "stability": reports.stability, "grade": _grade, "assignment": _assignment, "compile": _compile,
           "notebooks": _notebooks}[args.command]
    try:
        interrupts.running(command.prog)        # a Ctrl-C from here on: a KeyboardInterrupt, caught below
        return run(args, command, wait)
    except KeyboardInterrupt as stop:
        from .support.outputs import Interrupted
        if isinstance(stop, Interrupted):
            kept = ", ".join(str(p) for p in stop.paths)
            print(f"{command.prog}: interrupted after {stop.done} of {stop.total} planned runs; kept the "
                  f"{stop.done} finished in {kept} (marked partial)", file=sys.stderr)
        else:
            print(f"{command.prog}: interrupted", file=sys.stderr)
        interrupts.said()
        return 130
    finally:
        interrupts.closing()            # a Ctrl-C from here on: said after the exit handlers, code 130


def _demo(args, command, wait) -> int:
    from .support.outputs import writable_folder
    from .workbook.demo import check_arguments, output_names, run_demo
    language.choose(args.lang)
    ex, *_ = _checked(command, lambda: check_arguments(args.scene, method=args.method, t_end=args.t_end, dt=args.dt,
                                                       live=args.open))
    out = _checked(command, lambda: writable_folder(args.out, "--out", output_names(ex.name)))
    written = run_demo(args.scene, method=args.method, t_end=args.t_end, dt=args.dt, out=out, live=args.open)
    for path in written:
        print(language.say(f"wrote {path}", f"écrit : {path}"))
    if args.open:
        from .viz.viewer import close_live_server, live_server
        url = live_server().url
        print(language.say(f"live at {url}", f"en direct à {url}"), flush=True)
        try:
            (wait or _wait_until_interrupted)(url)
        finally:
            close_live_server()
    return 0


_EXPLORE_FLAGS = (("methods", "--methods"), ("dts", "--dts"), ("t_end", "--t-end"))


def _explore(args, command, wait) -> int:
    from .support.outputs import writable_folder
    from .viz.explorer import Explorer, check_arguments
    from .viz.explorer.runs import run_grid
    from .examples import get_scene
    language.choose(args.lang)

    def flagged(check):
        """check(), a ValueError naming a parameter of explore() told by its flag (dts -> --dts)."""
        try:
            return check()
        except ValueError as err:
            msg = str(err)
            flag = next((f for name, f in _EXPLORE_FLAGS if msg.startswith(name)), None)
            command.error(f"{flag}: {msg}" if flag else msg)

    ex = flagged(lambda: get_scene(args.scene))
    settings = flagged(lambda: check_arguments(ex, methods=args.methods, dts=args.dts, t_end=args.t_end))
    name = f"{ex.name}_explorer.html"
    out = _checked(command, lambda: writable_folder(args.out, "--out", [name]))
    grid = flagged(lambda: run_grid(settings, progress=True))
    explorer = Explorer(grid)
    path = explorer.save(out / name)
    print(explorer.summary())
    size = f"{path.stat().st_size / 1e6:.2f}"
    print(language.say(f"wrote {path} ({size} MB)", f"écrit : {path} ({size} Mo)"))
    return 0


def _short_paths(*flags) -> None:
    """Each path given (flag, value; None when not given) within the file system's limits (checks.path_length)."""
    from pathlib import Path
    from .support import checks
    for flag, value in flags:
        if isinstance(value, str) and value and "\0" not in value:
            checks.path_length(flag, Path(value))


def _grade(args, command, wait) -> int:
    from .support import parallel
    from .workbook.grading.plan import check_arguments, grade, summary
    language.choose(args.lang)
    workers = parallel.default_workers() if args.workers is None else args.workers
    _checked(command, lambda: _short_paths(("SUBMISSIONS", args.submissions), ("--out", args.out),
                                           ("--feedback", args.feedback), ("--gradescope", args.gradescope)))
    plan = _checked(command, lambda: check_arguments(args.submissions, args.out, args.timeout, args.feedback,
                                                     args.gradescope, workers, sandboxed=not args.no_sandbox))
    plan.scheduler = None if args.scheduler is None else _checked(command, lambda: parallel.connect(args.scheduler))
    from .workbook.grading.plan import check_seed, draw_seed
    plan.seed = draw_seed() if args.seed is None else _checked(command, lambda: check_seed(args.seed))
    try:
        graded, paths = grade(plan, warn=lambda line: print(f"{command.prog}: {line}", file=sys.stderr))
    finally:
        if plan.scheduler is not None:
            plan.scheduler.close()
    print(summary(graded, paths, plan))
    return 0


def _assignment(args, command, wait) -> int:
    from pathlib import Path
    from .support.outputs import write_text
    from .workbook import assignment
    solutions = _checked(command, lambda: [Path(p) for p in args.solutions] or assignment.solution_notebooks())
    for solution in solutions:                      # every notebook checked before anything is run or written
        _checked(command, lambda: assignment.generate(solution))
    if args.check:
        stale = 0
        for solution in solutions:
            target, found = assignment.student_path(solution), assignment.check(solution)
            stale += bool(found)
            print(f"differs: {target} (from {solution}): {'; '.join(found)}" if found else f"up to date: {target}")
        if stale:
            print(f"{stale} of {len(solutions)} student notebooks differ from their solution notebook: "
                  f"run {PROG} assignment build")
        return 1 if stale else 0
    for solution in solutions:
        try:
            target, text = assignment.build(solution)
        except assignment.AssignmentError as err:
            print(f"{command.prog}: {' '.join(str(err).split())}", file=sys.stderr)
            return 1
        print(f"wrote {write_text(target, text)} (from {solution})")
    return 0


def _notebooks(args, command, wait) -> int:
    from .workbook import copies
    done = _checked(command, lambda: copies.copy_workbook(args.to, solutions=args.solutions))
    print(copies.report(done, args.to))
    return 0


def _compile(args, command, wait) -> int:
    from .workbook import warmup
    from .engine import jit
    methods = _checked(command, lambda: warmup.check_methods(args.methods))
    if not jit.COMPILED:
        print(f"nothing to compile: the engine is {jit.describe()}")
        return 0
    seconds, refused = warmup.timed(methods)
    for line in refused:
        print(f"not run: {line}")
    print(f"compiled {len(methods)} method{'s' * (len(methods) > 1)} and the helpers in {seconds:.1f} s; "
          f"the cache: {warmup.cache_folder()} (numba's, read by every later run of this installation)")
    return 0


def _wait_until_interrupted(url: str):
    """Serve until Ctrl-C (or SIGTERM): the live server stops with this process."""
    print(language.say("open it in a browser on this machine; Ctrl-C stops the server",
                       "ouvrez-la dans un navigateur sur cette machine ; Ctrl-C arrête le serveur"), flush=True)

    def stop(signum, frame):
        raise KeyboardInterrupt
    previous = {sig: signal.signal(sig, stop) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        while True:
            time.sleep(3600)
    except KeyboardInterrupt:
        pass
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


if __name__ == "__main__":
    interrupts.leave(main())
