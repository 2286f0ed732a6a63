"""The checks of one hand-in, run here, in the grader's process — which never imports the student's code — on
the student's functions as they answer from their sandbox, over the channel (wire.py: plain data only).

    checks()                                      -> [(the student's function name, check_*)]
    check_all(channel, functions, budget, …)      -> ({check name: outcome}, what stopped the checks or "")

Each check of the exercise runs unchanged (exercises/*.py), on a Remote in place of the student's function:
calling it sends the arguments to the sandbox and waits for the answer, converted back here (arrays of the
allowed dtypes, tuples, numbers: the checks then read them as float64 arrays of the expected shape).  The
expected values never leave this process, and the verdicts are the checks' own.  The functions the checks
pass (simulate's forces_at and step) stay here too: the student's code calls them back over the channel.

Time: the student's functions get `budget` seconds in all, each check an n-th of it (what a check leaves unused
goes to the next ones), counted while the checker waits for them — not while the checks compute their cases and
verdicts here, so that a busy grader gives the same grades.  A call still unanswered when its check's time is
spent is "out_of_time" (the CSV's "timed-out"); one that the sandbox does not even report as stopped within
GRACE more seconds leaves the hand-in unusable: the checks after it are not run.
"""
from __future__ import annotations

import builtins
import inspect
import threading
import time
import traceback

import numpy as np

from . import outcome, wire

GRACE = 2.0              # s after a call's limit: the sandbox must have said that it stopped it
MAX_CALLBACKS = 10_000   # calls of the check's own functions (forces_at, step) within one call: then they raise
MAX_PASSED = 64 << 20    # bytes of arguments passed to them within one call (the check keeps them): then they raise
LAST = ("simulate",)
"""Checked after the others: check_simulate lends the student's loop a reference step (Euler's, or Euler's then
the projection), which the loop may call on inputs of its choosing — no check may follow that one."""
_LANGUAGE = threading.Lock()    # the checks' language is the process's: one hand-in's checks at a time


def checks():
    """The exercise's checks, [(the student's function name, check_*)], in the order of exercises.__all__."""
    from .. import exercises as ex
    return [(name[len("check_"):], getattr(ex, name)) for name in ex.__all__ if name.startswith("check_")]


class CallTimedOut(BaseException):
    """The student's function did not answer within its check's time (a BaseException: the checks' own
    `except Exception` lets it through, and the checker gives the verdict)."""


class Unusable(BaseException):
    """The hand-in's process no longer answers, or answered something that is not a reply: no more checks."""


class Link:
    """The checker's end of the channel: one call at a time, with its deadline."""

    def __init__(self, channel: wire.Channel):
        self.channel = channel
        self.remaining = 0.0            # s the student's functions may still take in this check
        self.broken = ""
        self.deadline = 0.0             # when the call under way must have been answered
        self.callbacks = 0              # the check's own functions called back in the call under way
        self.passed_from = 0            # the channel's bytes received when that call began
        self._next = 0

    def call(self, name: str, args: tuple, kwargs: dict):
        """The student's function `name` called with args, kwargs in the sandbox: its result (args changed in place
        as it changed them), or the exception it raised, rebuilt here."""
        if self.broken:
            raise Unusable(self.broken)
        self._next += 1
        call_id, callables = self._next, []

        def register(fn):
            callables.append(fn)
            return {"id": len(callables) - 1, "name": str(getattr(fn, "__name__", "function")),
                    "params": _parameters(fn)}
        seconds, began, self.callbacks, self.passed_from = self.remaining, time.monotonic(), 0, self.channel.received
        if seconds <= 0:
            raise CallTimedOut()
        self.deadline = began + seconds
        try:
            self.channel.send({"op": "call", "id": call_id, "name": name, "seconds": seconds,
                               "args": [wire.encode(a, register) for a in args],
                               "kwargs": {k: wire.encode(v, register) for k, v in kwargs.items()}},
                              time.monotonic() + GRACE)
            while True:
                message = self.channel.receive(self.deadline + GRACE)
                if message.get("id") != call_id:
                    raise wire.Broken("a reply to another call")
                op = message.get("op")
                if op == "callback":
                    self._callback(message, callables)
                elif op == "result":
                    value = wire.decode(message.get("value"), state=_state_tuple())
                    after = message.get("args")
                    if isinstance(after, list) and len(after) == len(args):
                        for original, item in zip(args, after):
                            mirror(original, wire.decode(item, state=_state_tuple()))
                    return value
                elif op == "raised":
                    error = _rebuilt(message)
                    break
                elif op == "timed_out":
                    raise CallTimedOut()
                else:
                    raise wire.Broken(f"an unknown reply {str(op)[:20]!r}")
        except wire.Broken as err:
            self.broken = "its process did not stop its function at its time limit" if err.timed_out \
                else f"its process stopped answering ({err})"
            raise (CallTimedOut() if err.timed_out else Unusable(self.broken)) from None
        except (ValueError, TypeError, KeyError) as err:
            self.broken = f"its process answered something unreadable ({type(err).__name__})"
            raise Unusable(self.broken) from None
        finally:
            self.remaining = max(0.0, self.remaining - (time.monotonic() - began))
        raise error                     # what the student's function raised (outside the try: not the channel's)

    def _callback(self, message: dict, callables: list) -> None:
        """The student's code called one of the check's functions (forces_at, step): run it here, send back its
        result (or what it raised)."""
        index = message.get("fn")
        if not isinstance(index, int) or not 0 <= index < len(callables):
            raise wire.Broken("a callback to no function")
        self.callbacks += 1
        passed = self.channel.received - self.passed_from
        if self.callbacks > MAX_CALLBACKS or passed > MAX_PASSED:    # (the check's functions keep what they are given)
            too_much = f"more than {MAX_CALLBACKS} calls of {callables[index].__name__}" if passed <= MAX_PASSED \
                else f"more than {MAX_PASSED >> 20} MB of arguments passed to {callables[index].__name__}"
            self.channel.send({"op": "raise", "id": message["id"], "type": "RuntimeError",
                               "message": f"{too_much} in one run"}, self.deadline + GRACE)
            return
        args = [wire.decode(a, state=_state_tuple()) for a in message.get("args", [])]
        kwargs = {str(k): wire.decode(v, state=_state_tuple()) for k, v in (message.get("kwargs") or {}).items()}
        try:
            reply = {"op": "return", "id": message["id"], "value": wire.encode(callables[index](*args, **kwargs))}
        except Exception as exc:        # noqa: BLE001 — raised in the student's code, as it would be in class
            reply = {"op": "raise", "id": message["id"], "type": type(exc).__name__, "message": str(exc)[:300]}
        self.channel.send(reply, self.deadline + GRACE)


def _state_tuple():
    from ..exercises.reference import StateTuple
    return StateTuple


def _parameters(fn) -> list[str]:
    try:
        return list(inspect.signature(fn).parameters)
    except (TypeError, ValueError):
        return []


def mirror(original, after) -> bool:
    """What the student's function did to an argument, done to the checker's copy of it (the checks compare it
    with the input, to name an input changed in place); False when `original` cannot hold it (immutable)."""
    if isinstance(original, np.ndarray):
        if isinstance(after, np.ndarray) and original.shape == after.shape:
            try:
                original[...] = after
                return True
            except (TypeError, ValueError):
                return False
        return False
    if isinstance(original, list) and isinstance(after, list):
        if len(original) != len(after):
            original[:] = after
        for i, (o, a) in enumerate(zip(original, after)):
            if not mirror(o, a):
                original[i] = a
        return True
    if isinstance(original, tuple) and isinstance(after, tuple) and len(original) == len(after):
        return all([mirror(o, a) for o, a in zip(original, after)])
    return False


def _rebuilt(message: dict) -> Exception:
    """The exception the student's function raised, as an exception here: of a class named as theirs, under the
    built-in class it derives from (NotImplementedError, TypeError, …: what the checks tell apart), with the
    frames of their code (where it was raised) and, for a name of rbcourse it called, .library."""
    base = getattr(builtins, str(message.get("builtin")), Exception)
    if not (isinstance(base, type) and issubclass(base, Exception)):
        base = Exception                # SystemExit, KeyboardInterrupt: stay exceptions here, never exits
    kind = type(wire.identifier(message.get("type")), (base,), {})
    error = kind(str(message.get("message", ""))[:300])
    frames = message.get("frames") if isinstance(message.get("frames"), list) else []
    error.frames = [traceback.FrameSummary("<notebook>", int(f[1]), str(f[0])[:60], line=str(f[2])[:120])
                    for f in frames[-10:] if isinstance(f, list) and len(f) == 3 and isinstance(f[1], int)]
    library = message.get("library")
    if isinstance(library, str) and library:
        error.library = library[:120]
    return error


class Remote:
    """A student's function, as the checks call it: by its name in the notebook, over the link.  It carries what
    the checks read of a function — its name, its declared parameters — and .library when its source takes its
    answer from rbcourse (library.py)."""

    def __init__(self, link: Link, name: str, params, library: str | None):
        self._link, self._name = link, name
        self.__name__ = name
        params = [p for p in (params if isinstance(params, list) else [])[:20]
                  if isinstance(p, str) and p.isidentifier() and len(p) <= 60]
        try:
            self.__signature__ = inspect.Signature([inspect.Parameter(p, inspect.Parameter.POSITIONAL_OR_KEYWORD)
                                                     for p in params])
        except ValueError:
            self.__signature__ = inspect.Signature()
        if library:
            self.library = library

    def __call__(self, *args, **kwargs):
        return self._link.call(self._name, args, kwargs)

    def __repr__(self):
        return f"<function {self._name}>"


def stand_in(link: Link, name: str, described: dict, library: str | None):
    """What the checks are given for the student's `name`: a Remote, or (not callable) an object showing theirs."""
    if described.get("callable"):
        return Remote(link, name, described.get("params"), library)
    return wire.foreign(described.get("type"), described.get("repr", ""))


def own_seed(check) -> int:
    """The seed a check draws its inputs from in the notebook (its `seed` parameter's default)."""
    import inspect
    return inspect.signature(check).parameters["seed"].default


def check_all(channel: wire.Channel, functions: dict, budget: float, language: str, interrupted: bool,
              library: dict, seed: int = 0) -> tuple[dict, str]:
    """Every check on the student's functions (functions: name -> what the sandbox said of it), in `language`;
    ({check name: outcome}, why the checks stopped early or "").  seed: each check draws its inputs from its own
    seed + `seed` (0: the notebook's own inputs; a grading's secret one, kept here, out of every sandbox)."""
    from ..exercises.texts import tr
    from ..language import current, langue
    table = checks()
    link, results = Link(channel), {}
    with _LANGUAGE:
        before = current()
        langue(language)
        try:
            for name, check in sorted(table, key=lambda item: item[0] in LAST):
                link.remaining += budget / len(table)
                described = functions.get(name)
                if not isinstance(described, dict):
                    if not interrupted:
                        results[name] = {"name": name, "passed": False, "mistake": "not_done", "slide": None,
                                         "message": tr("not_defined").format(name=name)}
                    continue
                if link.broken:
                    continue
                try:
                    results[name] = outcome(check(stand_in(link, name, described, library.get(name)), verbose=False,
                                                  seed=own_seed(check) + seed))
                except CallTimedOut:
                    results[name] = {"name": name, "passed": False, "mistake": "out_of_time", "slide": None,
                                     "message": tr("out_of_time").format(name=name)}
                except Unusable:
                    pass
        finally:
            langue(before)
    return results, link.broken
