"""Command line:  python -m rbcourse demo [scene] [--method M] [--t-end T] [--dt DT] [--out DIR]"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m rbcourse", description="rigid-body simulation workbook")
    sub = parser.add_subparsers(dest="command", required=True)
    demo = sub.add_parser("demo", help="simulate a named scene and write plots and data")
    from .scenes import SCENES
    demo.add_argument("scene", nargs="?", default="pushed_box", choices=sorted(SCENES))
    demo.add_argument("--method", default=None, help="integrator (default: the scene's)")
    demo.add_argument("--t-end", type=float, default=None, help="duration (s)")
    demo.add_argument("--dt", type=float, default=None, help="time step (s)")
    demo.add_argument("--out", default="demo_output", help="output folder (default: demo_output)")
    args = parser.parse_args(argv)
    if args.command == "demo":
        from .demo import run_demo
        try:
            written = run_demo(args.scene, method=args.method, t_end=args.t_end, dt=args.dt, out=Path(args.out))
        except ValueError as err:
            parser.error(str(err))
        for path in written:
            print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
