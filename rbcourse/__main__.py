"""Command line:
    python -m rbcourse demo [scene] [--method M] [--t-end T] [--dt DT] [--out DIR] [--open]
    python -m rbcourse bench [--problems A B C] [--methods ...] [--quick] [--no-peers] [--out DIR]
    python -m rbcourse throughput [--bodies N] [--quick] [--no-peers]
    python -m rbcourse stability [--quick] [--cases ...] [--methods ...] [--out DIR]
"""
from __future__ import annotations

import argparse
import signal
import sys
import time
from pathlib import Path


def main(argv=None, *, wait=None) -> int:
    """Run the command line.  wait(url): how `demo --open` waits while serving (default: until Ctrl-C)."""
    parser = argparse.ArgumentParser(prog="python -m rbcourse", description="rigid-body simulation workbook")
    sub = parser.add_subparsers(dest="command", required=True)
    demo = sub.add_parser("demo", help="simulate a named scene and write plots, data and a 3-D page")
    from .scenes import SCENES
    demo.add_argument("scene", nargs="?", default="pushed_box", choices=sorted(SCENES))
    demo.add_argument("--method", default=None, help="integrator (default: the scene's)")
    demo.add_argument("--t-end", type=float, default=None, help="duration (s)")
    demo.add_argument("--dt", type=float, default=None, help="time step (s)")
    demo.add_argument("--out", default="demo_output", help="output folder (default: demo_output)")
    demo.add_argument("--open", action="store_true",
                      help="also serve the animation live (meshcat, on 127.0.0.1) until Ctrl-C; prints its URL")
    bench = sub.add_parser("bench", help="work-precision benchmark on problems A, B, C, beside scipy and MuJoCo")
    bench.add_argument("--problems", nargs="+", default=["A", "B", "C"], help="among A B C (default: all)")
    bench.add_argument("--methods", nargs="+", default=None, help="integrators (default: all of METHODS)")
    bench.add_argument("--quick", action="store_true", help="a short sweep (seconds, for CI)")
    bench.add_argument("--no-peers", action="store_true", help="skip scipy and MuJoCo")
    bench.add_argument("--repeats", type=int, default=None, help="timed repeats per run (median; default 5, quick 1)")
    bench.add_argument("--out", default="bench_output", help="output folder (default: bench_output)")
    thr = sub.add_parser("throughput", help="what each effect costs; bodies per second, beside MuJoCo")
    thr.add_argument("--bodies", type=int, default=10000, help="N for the many-body runs (default 10000)")
    thr.add_argument("--quick", action="store_true", help="few steps (for CI)")
    thr.add_argument("--no-peers", action="store_true", help="skip MuJoCo")
    stab = sub.add_parser("stability", help="the stability matrix: every hard case × every method")
    stab.add_argument("--quick", action="store_true", help="short runs (as under test, RBCOURSE_QUICK=1)")
    stab.add_argument("--cases", nargs="+", default=None, help="hard cases (default: all)")
    stab.add_argument("--methods", nargs="+", default=None, help="integrators (default: all)")
    stab.add_argument("--out", default="stability_output", help="output folder (default: stability_output)")
    args = parser.parse_args(argv)
    if args.command == "stability":
        from . import stability
        from .hardcases import catalogue, quick_mode
        from .integrators import METHODS
        bad = [c for c in args.cases or [] if c not in catalogue()] + [m for m in args.methods or [] if m not in METHODS]
        if bad:
            parser.error(f"unknown case or method {bad}: cases are {sorted(catalogue())}, methods {sorted(METHODS)}")
        quick = args.quick or quick_mode()
        cells = stability.matrix(args.cases, args.methods, quick=quick, progress=True)
        paths = stability.write(cells, Path(args.out), quick)
        print(stability.markdown(cells, quick))
        for path in paths:
            print(f"wrote {path}")
        return 0
    if args.command == "throughput":
        if args.bodies < 2:
            parser.error(f"--bodies must be an integer >= 2, got {args.bodies}")
        from .throughput import main as throughput
        print(throughput(args.bodies, quick=args.quick, peers=not args.no_peers))
        return 0
    if args.command == "bench":
        from . import bench as bench_module
        if args.repeats is not None and args.repeats < 1:
            parser.error(f"--repeats must be an integer >= 1, got {args.repeats}")
        try:
            _, paths = bench_module.main(args.problems, args.methods, quick=args.quick, out=args.out,
                                         peers=not args.no_peers, repeats=args.repeats)
        except ValueError as err:
            parser.error(str(err))
        print(paths[1].read_text(encoding="utf-8"))
        for path in paths:
            print(f"wrote {path}")
        return 0
    if args.command == "demo":
        from .demo import run_demo
        try:
            written = run_demo(args.scene, method=args.method, t_end=args.t_end, dt=args.dt, out=Path(args.out),
                               live=args.open)
        except ValueError as err:
            parser.error(str(err))
        for path in written:
            print(f"wrote {path}")
        if args.open:
            from .viewer import close_live_server, live_server
            url = live_server().url
            print(f"live at {url}", flush=True)
            try:
                (wait or _wait_until_interrupted)(url)
            finally:
                close_live_server()
    return 0


def _wait_until_interrupted(url: str):
    """Serve until Ctrl-C (or SIGTERM): the live server stops with this process."""
    print("open it in a browser on this machine; Ctrl-C stops the server", flush=True)

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
    sys.exit(main())
