"""A PNG still of a page, for slides: headless Chromium renders the standalone page (at a URL fragment such
as ``#t=1.5&controls=hidden``) and takes its screenshot.  A GIF clip: the page draws N frames on one
contact sheet (``#sheet=N&w=..&h=..&cols=..``), one screenshot, cut into the frames (Pillow).

WebGL without a GPU: --disable-gpu with --enable-unsafe-swiftshader (software WebGL; a page this size is
drawn in well under a second).  Chromium runs with a fresh profile in a temporary folder, removed after,
and is waited for (a timeout kills it): no process is left behind.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

CANDIDATES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
INSTALL = ("a still needs Chromium to draw the page: install it (Debian/Ubuntu: sudo apt-get install chromium; "
           "macOS: brew install --cask chromium), or pass chromium= the path of a Chromium or Chrome executable")


def chromium_executable(given: str | os.PathLike | None = None) -> str:
    """Chromium's path: given, else the first of CANDIDATES on PATH; a RuntimeError saying how to install it."""
    if given is not None:
        if not isinstance(given, (str, os.PathLike)):
            raise ValueError(f"chromium must be None or the path of a Chromium executable, got {given!r}")
        if os.path.isfile(given) and os.access(given, os.X_OK):
            return os.fspath(given)
        raise RuntimeError(f"chromium = {os.fspath(given)!r} is not an executable file; {INSTALL}")
    for name in CANDIDATES:
        found = shutil.which(name)
        if found:
            return found
    raise RuntimeError(f"Chromium was not found (looked for {', '.join(CANDIDATES)} on PATH); {INSTALL}")


def flags(size: tuple[int, int], profile: str) -> list[str]:
    """Headless, software WebGL, no network chatter, a fresh profile; no sandbox when run as root (it refuses to)."""
    out = ["--headless", "--disable-gpu", "--enable-unsafe-swiftshader", "--no-first-run", "--no-default-browser-check",
           "--disable-background-networking", "--disable-component-update", "--disable-sync", "--disable-extensions",
           "--hide-scrollbars", "--mute-audio", "--force-device-scale-factor=1",
           f"--user-data-dir={profile}", f"--window-size={size[0]},{size[1]}"]
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        out.append("--no-sandbox")
    return out


def render_png(page: str, path: Path, *, fragment: str, size: tuple[int, int], chromium=None,
               timeout: float = 120.0) -> Path:
    """Screenshot of the page (HTML text) at #fragment, size (width, height) px, written to path; returns path.
    chromium: the executable (default: found on PATH)."""
    exe = chromium_executable(chromium)
    path = Path(path)
    with tempfile.TemporaryDirectory(prefix="rbcourse-still-") as tmp:
        html = Path(tmp) / "page.html"
        html.write_text(page, encoding="utf-8")
        shot = Path(tmp) / "still.png"
        cmd = [exe, *flags(size, os.path.join(tmp, "profile")), f"--screenshot={shot}",
               "--virtual-time-budget=10000", f"{html.as_uri()}#{fragment}"]
        with open(os.path.join(tmp, "chromium.log"), "w+b") as log:
            proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=log, stderr=log, start_new_session=True)
            try:
                code = proc.wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                raise RuntimeError(f"Chromium did not draw the still within {timeout:g} s") from None
            finally:                                 # also on Ctrl-C: Chromium and any helper left go
                _kill_group(proc)
            if code != 0 or not shot.exists():
                log.seek(0)
                err = log.read().decode("utf-8", "replace")[-1500:]
                raise RuntimeError(f"Chromium did not draw the still (exit code {code}): {err}")
        shutil.copyfile(shot, path)
    return path


def _kill_group(proc: subprocess.Popen):
    """Kill what is left of Chromium's process group (it was started in a session of its own) and reap it."""
    try:
        os.killpg(proc.pid, 9)
    except (ProcessLookupError, PermissionError):
        pass
    if proc.poll() is None:
        proc.wait()
    deadline = time.monotonic() + 10.0        # SIGKILL is asynchronous: wait until the group's helpers are gone
    while _group_alive(proc.pid) and time.monotonic() < deadline:
        time.sleep(0.02)


def _group_alive(pgid: int) -> bool:
    """Is a process of group pgid still running (not a zombie)?  Linux's /proc; elsewhere, no way to tell: False."""
    try:
        entries = os.listdir("/proc")
    except OSError:
        return False
    for pid in entries:
        if not pid.isdigit():
            continue
        try:
            with open(f"/proc/{pid}/stat", "rb") as f:
                fields = f.read().rsplit(b")", 1)[1].split()
        except OSError:
            continue
        if int(fields[2]) == pgid and fields[0] != b"Z":      # fields after "(comm)": state, ppid, pgrp, ...
            return True
    return False


def sheet_frames(page: str, *, frames: int, size: tuple[int, int], chromium=None) -> list:
    """The page's animation as `frames` PIL images of size (width, height), evenly over its duration."""
    from PIL import Image
    cols = int(np.ceil(np.sqrt(frames)))
    rows = int(np.ceil(frames / cols))
    w, h = size
    with tempfile.TemporaryDirectory(prefix="rbcourse-sheet-") as tmp:
        shot = render_png(page, Path(tmp) / "sheet.png", size=(cols * w, rows * h), chromium=chromium,
                          fragment=f"controls=hidden&sheet={frames}&w={w}&h={h}&cols={cols}")
        with Image.open(shot) as sheet:
            sheet = sheet.convert("RGB")
            return [sheet.crop(((i % cols) * w, (i // cols) * h, (i % cols + 1) * w, (i // cols + 1) * h))
                    for i in range(frames)]
