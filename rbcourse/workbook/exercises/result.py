"""What a check finds: a verdict (CheckResult: passed, the mistake's id, the message), printed once in a
notebook — shown as the value of the cell that printed it, it shows nothing more."""
from __future__ import annotations


class CheckResult:
    """What a check found: passed (bool), mistake (an id of MISTAKES, or "not_done", "error", … ;
    None when passed), message (the line(s) printed).

    The check prints the message; shown as the value of the cell that printed it, the result shows
    nothing more (no second copy); shown in a later cell, it shows the message.
    """

    def __init__(self, name: str, passed: bool, mistake: str | None, message: str):
        self.name = name
        self.passed = passed
        self.mistake = mistake
        self.message = message
        self._printed_in = None       # the IPython cell (execution count) that printed the message

    def __repr__(self) -> str:
        return f"CheckResult(name={self.name!r}, passed={self.passed}, mistake={self.mistake!r})"

    def __str__(self) -> str:
        return self.message

    def printed(self, verbose: bool = True) -> "CheckResult":
        """Print the message (when verbose) and remember the cell that printed it; return the result."""
        if verbose:
            print(self.message)
            self._printed_in = execution_count()
        return self

    def _ipython_display_(self):
        if self._printed_in is None or self._printed_in != execution_count():
            print(self.message)


def execution_count():
    """The number of the IPython cell running now (None outside IPython)."""
    try:
        from IPython import get_ipython
    except ImportError:
        return None
    shell = get_ipython()
    return None if shell is None else shell.execution_count
