"""The grading channel: what crosses between the checker and a hand-in's process, plain data only.

Both ends use this file: the checker (checker.py, outside the sandbox) and the hand-in's process (worker.py,
inside it, where this file is bound read-only at /grading/wire.py and imported as a plain module: it imports
nothing but the standard library and numpy).

A message is a frame: 4 bytes (big-endian length), then that many bytes of UTF-8 JSON (NaN and ±inf written as
Python's json writes them).  A value inside a message is tagged:

    {"t": "none"} {"t": "bool", "v": …} {"t": "int", "v": …} {"t": "float", "v": …} {"t": "complex", "re", "im"}
    {"t": "nd", "dtype": "<f8", "shape": [3], "b64": …}      an array (its bytes, little-endian), "matrix": np.matrix
    {"t": "tuple", "items": […], "fields": [...] or None}     a tuple (a named one: its fields), {"t": "list", …}
    {"t": "state", "type": name, "x": …, "R": …, "P": …, "L": …}   an object with x, R, P, L (an rbcourse State)
    {"t": "fn", "id": k, "name": …, "params": […]}           the checker's callable (forces_at, step): its number
    {"t": "other", "type": name, "repr": text}               anything else: its type and repr, cut (never rebuilt)

decode() rebuilds only these: arrays of the allowed dtypes (DTYPES), tuples, lists, numbers — never an object
of the sender's choosing (no pickle).  Limits: MAX_FRAME bytes a frame, MAX_DEPTH levels, MAX_ITEMS items a
list, MAX_ELEMENTS elements an array.
"""
from __future__ import annotations

import base64
import json
import os
import select
import struct
import time
from typing import NamedTuple

import numpy as np

MAX_FRAME = 16 << 20
MAX_NOTEBOOK = 64 << 20     # the first frame to a hand-in's process, its notebook's code (submissions.MAX_BYTES at most)
MAX_DEPTH = 8
MAX_ITEMS = 100_000
MAX_ELEMENTS = 2_000_000
DTYPES = {np.dtype(t).str for t in ("?", "i1", "i2", "i4", "i8", "u1", "u2", "u4", "u8", "f2", "f4", "f8",
                                      "c8", "c16")}
"""The array dtypes that cross as they are (little-endian); other floats cross as float64."""


class StateTuple(NamedTuple):
    """X = (x, R, P, L), as the checks pass it (the same fields as rbcourse.workbook.exercises.StateTuple)."""
    x: np.ndarray
    R: np.ndarray
    P: np.ndarray
    L: np.ndarray


class Broken(Exception):
    """The channel is closed, too slow (timed out), or carried something that is not a message."""

    def __init__(self, why: str, timed_out: bool = False):
        super().__init__(why)
        self.timed_out = timed_out


class Channel:
    """Frames over a pair of file descriptors (a pipe each way).  The checker's end is non-blocking: every
    send and receive has a deadline (time.monotonic()), so that a hand-in that stops reading or writing
    cannot hold it; the hand-in's end blocks (deadline None)."""

    def __init__(self, read_fd: int, write_fd: int, blocking: bool = True, receives: int = MAX_FRAME,
                 sends: int = MAX_FRAME):
        self.read_fd, self.write_fd = read_fd, write_fd
        self.receives, self.sends = receives, sends      # the largest frame this end reads, and sends
        self._buffer = b""
        self.received = 0               # bytes of the frames received so far
        if not blocking:
            os.set_blocking(read_fd, False)
            os.set_blocking(write_fd, False)

    def send(self, message: dict, deadline: float | None = None) -> None:
        data = json.dumps(message, ensure_ascii=False, separators=(",", ":")).encode("utf-8")
        if len(data) > self.sends:
            raise Broken(f"a message of {len(data)} bytes (at most {self.sends})")
        data = struct.pack(">I", len(data)) + data
        while data:
            self._wait(self.write_fd, deadline, write=True)
            try:
                n = os.write(self.write_fd, data)
            except BlockingIOError:
                continue
            except OSError as err:
                raise Broken(f"the other end is gone ({err.strerror or err})") from None
            data = data[n:]

    def receive(self, deadline: float | None = None) -> dict:
        head = self._read(4, deadline)
        (size,) = struct.unpack(">I", head)
        if size > self.receives:
            raise Broken(f"a frame of {size} bytes (at most {self.receives})")
        self.received += size
        try:
            message = json.loads(self._read(size, deadline).decode("utf-8"))
        except (ValueError, RecursionError) as err:
            raise Broken(f"a frame that is not JSON ({type(err).__name__})") from None
        if not isinstance(message, dict):
            raise Broken("a frame that is not a message")
        return message

    def _read(self, n: int, deadline) -> bytes:
        while len(self._buffer) < n:
            self._wait(self.read_fd, deadline)
            try:
                chunk = os.read(self.read_fd, max(65536, n - len(self._buffer)))
            except BlockingIOError:
                continue
            except OSError as err:
                raise Broken(f"cannot read ({err.strerror or err})") from None
            if not chunk:
                raise Broken("closed")
            self._buffer += chunk
        out, self._buffer = self._buffer[:n], self._buffer[n:]
        return out

    @staticmethod
    def _wait(fd: int, deadline, write: bool = False) -> None:
        if deadline is None:
            return
        left = deadline - time.monotonic()
        if left <= 0:
            raise Broken("timed out", timed_out=True)
        ready = select.select([], [fd], [], left) if write else select.select([fd], [], [], left)
        if not any(ready):
            raise Broken("timed out", timed_out=True)


def _cut(text: str, n: int) -> str:
    return text if len(text) <= n else text[: n - 1] + "…"


def type_name(obj) -> str:
    try:
        return _cut(str(type(obj).__name__), 60)
    except Exception:       # noqa: BLE001 — whatever the object is
        return "object"


def short_repr(obj) -> str:
    try:
        return _cut(repr(obj), 200)
    except BaseException:   # noqa: BLE001 — a repr that raises (or is interrupted) is not the checker's problem
        return f"<{type_name(obj)}>"


def _array(a: np.ndarray, tag: str = "nd") -> dict:
    if a.size > MAX_ELEMENTS:
        raise ValueError(f"an array of {a.size} elements (at most {MAX_ELEMENTS})")
    dtype = a.dtype.newbyteorder("<") if a.dtype.byteorder == ">" else a.dtype
    if dtype.str not in DTYPES:
        dtype = np.dtype("<f8")            # float128, object arrays of numbers, …: read as floats
    data = np.ascontiguousarray(a, dtype=dtype)
    return {"t": tag, "dtype": dtype.str, "shape": list(a.shape), "b64": base64.b64encode(data.tobytes()).decode()}


def encode(value, callables=None, depth: int = 0) -> dict:
    """A value as tagged plain data.  callables(fn) -> its number, for the checker's own functions (None: a
    callable is an "other")."""
    if depth > MAX_DEPTH:
        return {"t": "other", "type": "nested", "repr": "(nested too deeply)"}
    if value is None:
        return {"t": "none"}
    if isinstance(value, (bool, np.bool_)):
        return {"t": "bool", "v": bool(value)}
    if isinstance(value, int) and not isinstance(value, np.integer):
        return {"t": "int", "v": int(value)} if -2**63 <= value < 2**63 else _other(value)
    if isinstance(value, float):
        return {"t": "float", "v": float(value)}
    if isinstance(value, complex):
        return {"t": "complex", "re": value.real, "im": value.imag}
    if isinstance(value, (np.ndarray, np.generic)):
        try:
            if isinstance(value, np.matrix):
                return _array(np.asarray(value), "matrix")
            item = _array(np.asarray(value))
            if isinstance(value, np.generic):
                item["scalar"] = True
            return item
        except (ValueError, TypeError):
            return _other(value)
    if isinstance(value, (tuple, list)):
        if len(value) > MAX_ITEMS:
            return _other(value)
        items = [encode(v, callables, depth + 1) for v in value]
        if isinstance(value, list):
            return {"t": "list", "items": items}
        fields = getattr(type(value), "_fields", None)
        return {"t": "tuple", "items": items,
                "fields": [str(f) for f in fields] if isinstance(fields, tuple) and len(fields) == len(items) else None}
    if callables is not None and callable(value):
        return {"t": "fn", **callables(value)}
    try:
        if all(hasattr(value, k) for k in "xRPL"):
            return {"t": "state", "type": type_name(value),
                    **{k: encode(getattr(value, k), callables, depth + 1) for k in "xRPL"}}
    except Exception:       # noqa: BLE001 — an object whose attributes raise: shown as it is
        pass
    return _other(value)


def _other(value) -> dict:
    return {"t": "other", "type": type_name(value), "repr": short_repr(value)}


class Foreign:
    """What decode() makes of an "other": an object that is not numbers, showing the sender's type and repr."""

    def __init__(self, text: str):
        self._text = text

    def __repr__(self):
        return self._text


def identifier(name) -> str:
    name = "".join(c for c in str(name) if c.isalnum() or c == "_")[:60]
    return name if name and not name[0].isdigit() else "object"


def foreign(type_text, text) -> Foreign:
    """An object of a class named as the sender's (letters, digits, _ only) whose repr is the sender's."""
    return type(identifier(type_text), (Foreign,), {})(_cut(str(text), 200))


def decode(data, function=None, state=StateTuple, depth: int = 0):
    """The value a tagged item stands for.  function(item) -> a callable for an "fn" item (None: not accepted);
    state: the class a tuple named (x, R, P, L) is rebuilt as.  ValueError for anything else."""
    if depth > MAX_DEPTH or not isinstance(data, dict):
        raise ValueError("not a value")
    t = data.get("t")
    if t == "none":
        return None
    if t == "bool":
        return bool(data["v"])
    if t == "int":
        v = data["v"]
        if isinstance(v, bool) or not isinstance(v, int):
            raise ValueError("not an int")
        return v
    if t == "float":
        return float(data["v"])
    if t == "complex":
        return complex(float(data["re"]), float(data["im"]))
    if t in ("nd", "matrix"):
        return _decode_array(data, t)
    if t in ("tuple", "list"):
        items = data.get("items")
        if not isinstance(items, list) or len(items) > MAX_ITEMS:
            raise ValueError("not items")
        values = [decode(v, function, state, depth + 1) for v in items]
        if t == "list":
            return values
        if data.get("fields") == ["x", "R", "P", "L"] and len(values) == 4:
            return state(*values)
        return tuple(values)
    if t == "state":
        return _state_object(data.get("type"), {k: decode(data[k], function, state, depth + 1) for k in "xRPL"})
    if t == "fn" and function is not None:
        return function(data)
    if t == "other":
        return foreign(data.get("type"), data.get("repr", ""))
    raise ValueError(f"an item tagged {str(t)[:20]!r}")


def _state_object(type_text, parts: dict):
    """An object with the attributes x, R, P, L (what the sender's State-like object held)."""
    obj = foreign(type_text, f"<{identifier(type_text)} with x, R, P, L>")
    obj.__dict__.update(parts)
    return obj


def _decode_array(data: dict, tag: str):
    dtype, shape, b64 = data.get("dtype"), data.get("shape"), data.get("b64")
    if dtype not in DTYPES or not isinstance(shape, list) or not all(isinstance(s, int) and s >= 0 for s in shape) \
            or len(shape) > 32 or not isinstance(b64, str):
        raise ValueError("not an array")
    count = int(np.prod(shape, dtype=np.int64)) if shape else 1
    if count > MAX_ELEMENTS:
        raise ValueError("too large an array")
    raw = base64.b64decode(b64.encode("ascii"), validate=True)
    if len(raw) != count * np.dtype(dtype).itemsize:
        raise ValueError("an array whose bytes do not fill its shape")
    a = np.frombuffer(raw, dtype=np.dtype(dtype)).reshape(shape).astype(np.dtype(dtype).newbyteorder("="))
    if tag == "matrix":
        return np.asmatrix(a)
    return a[()] if data.get("scalar") and not shape else a
