"""The command line's report commands: `bench` (work-precision), `stability` (the stability matrix) and
`throughput` (what each effect costs; with --compile, what compiling costs: compile_cost), each checking its
arguments (checked: a ValueError becomes the command's one-line error, exit code 2), running, printing its report
and the files it wrote, in the language asked for (--lang; throughput's report is English)."""
from __future__ import annotations

from ..support import language


def checked(command, check):
    """check(): the arguments' checks; a ValueError becomes the one-line error (exit code 2)."""
    try:
        return check()
    except ValueError as err:
        command.error(str(err))


def bench(args, command, wait) -> int:
    """`python -m rbcourse bench`: the work-precision sweep (or --errors-only), its report printed."""
    from . import work_precision as sweep
    from ..support import parallel
    from ..support.outputs import writable_folder
    language.choose(args.lang)
    checked(command, lambda: sweep.check_arguments(args.problems, args.methods, args.repeats))
    default = parallel.default_workers() if args.errors_only else 1
    workers = checked(command, lambda: sweep.check_parallel(
        args.errors_only, default if args.workers is None else args.workers, args.scheduler))
    out = checked(command, lambda: writable_folder(args.out, "--out", sweep.OUTPUTS))
    client = None if args.scheduler is None else checked(command, lambda: parallel.connect(args.scheduler))
    try:
        _, paths = sweep.main(args.problems, args.methods, quick=args.quick, out=out, peers=not args.no_peers,
                              repeats=args.repeats, errors_only=args.errors_only, workers=workers, scheduler=client)
    finally:
        if client is not None:
            client.close()
    print(paths[1].read_text(encoding="utf-8"))
    for path in paths:
        print(language.say(f"wrote {path}", f"écrit : {path}"))
    return 0


def stability(args, command, wait) -> int:
    """`python -m rbcourse stability`: every hard case × every method, its report printed."""
    from . import stability as matrix
    from ..support.config import quick_mode
    from ..support.outputs import writable_folder
    language.choose(args.lang)
    checked(command, lambda: matrix.check_arguments(args.cases, args.methods))
    workers = checked(command, lambda: matrix.check_workers(
        matrix.default_workers() if args.workers is None else args.workers))
    out = checked(command, lambda: writable_folder(args.out, "--out", matrix.OUTPUTS))
    client = None if args.scheduler is None else checked(command, lambda: matrix.connect(args.scheduler))
    quick = args.quick or quick_mode()
    try:
        cells, paths = matrix.main(args.cases, args.methods, quick=quick, out=out, workers=workers,
                                   scheduler=client)
    finally:
        if client is not None:
            client.close()
    print(matrix.markdown(cells, quick))
    for path in paths:
        print(language.say(f"wrote {path}", f"écrit : {path}"))
    return 0


def throughput(args, command, wait) -> int:
    """`python -m rbcourse throughput`: what each effect costs, many bodies per second, beside MuJoCo."""
    from ..support.outputs import writable_folder, write_text
    if args.compile:
        return compile_cost(args, command)
    if args.methods is not None:
        command.error("--methods: only with --compile (the compile-cost report's families)")
    from .throughput import main as throughput
    out = checked(command, lambda: writable_folder(args.out, "--out", ["throughput.md"]))
    text = throughput(args.bodies, quick=args.quick, peers=not args.no_peers)
    print(text)
    print(f"wrote {write_text(out / 'throughput.md', text)}")
    return 0


def compile_cost(args, command) -> int:
    """`python -m rbcourse throughput --compile [--methods a,b]`: the compile-cost report alone (bench/compile_cost.py),
    printed and written to compile_cost.md in --out."""
    from . import compile_cost as cost
    from ..support.outputs import writable_folder, write_text
    methods = checked(command, lambda: cost.check_methods(args.methods))
    if args.quick:
        command.error("--quick: not with --compile (a compile takes as long as it takes)")
    out = checked(command, lambda: writable_folder(args.out, "--out", ["compile_cost.md"]))
    text = cost.main(methods)
    print(text)
    print(f"wrote {write_text(out / 'compile_cost.md', text)}")
    return 0
