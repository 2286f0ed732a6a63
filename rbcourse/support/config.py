"""The run-length flag: RBCOURSE_QUICK=1 shortens long runs (the tests, CI's shortened notebook run).

Read here only, by the notebooks, the tests and the command line, and passed down explicitly
(e.g. ``stability.matrix(quick=config.quick_mode())``): the library itself never reads the
environment.  The flag only shortens durations; it never changes which code runs.
"""
from __future__ import annotations

import os

FLAG = "RBCOURSE_QUICK"


def quick_mode() -> bool:
    """True when RBCOURSE_QUICK is set to anything but '', '0', 'false' or 'no'."""
    return os.environ.get(FLAG, "") not in ("", "0", "false", "no")
