"""A student's "Run All" and save in JupyterLab, for every notebook, driven by Playwright in Debian's chromium.

JupyterLab (the one of the Python running this script, or --python) is started on a free localhost port with a
token, on a temporary COPY of notebooks/ (the repository stays clean), its settings, data (the trust database) and
workspaces in temporary folders too.  For each notebook (00-05, the instructor's demo, the solutions, every
notebooks/fr one): open it, Run All (full length: no RBCOURSE_QUICK), wait for the kernel to be idle, save, then
check the saved file: at most 1 MB (issue 28), no stderr stream and no error in any cell; and every 3-D view
rendered in the page (each inline view's frame, scrolled into sight, shows meshcat's canvas and no message that
meshcat's script is missing: viewer/sharing.py).  Once, the trust instruction as the views' fallback writes it
(rbcourse/viz/frame.py): an untrusted notebook shows the fallback; open the command palette (Ctrl+Shift+C),
choose "Trust Notebook", and the 3-D view renders.

Prints a table (notebook, size, seconds, stderr cells, views) and exits 1 on any failure.

    python .ci/jupyterlab_check.py [--python PY] [--shots DIR] [NOTEBOOK ...]   (default: every notebook)

Needs `pip install -r .ci/requirements-jupyterlab.txt` (playwright, which drives the system's chromium: no
`playwright install`) and Debian's chromium (/usr/bin/chromium).
"""
from __future__ import annotations

import argparse
import json
import os
import secrets
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

from playwright.sync_api import sync_playwright

ROOT = Path(__file__).resolve().parents[1]
MAX_BYTES = 1_000_000
CHROMIUM = "/usr/bin/chromium"
# the flags of the brief; --enable-unsafe-swiftshader: WebGL in software (meshcat's canvas) with --disable-gpu
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run", "--enable-unsafe-swiftshader"]
RUN_TIMEOUT = 1800          # s: one notebook's whole Run All
VIEW_TIMEOUT = 60           # s: one 3-D view, scrolled into sight, to show meshcat's canvas


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Lab:
    """JupyterLab on a copy of the notebooks; its REST API (kernels, sessions) with the token."""

    def __init__(self, python: str, work: Path):
        self.root = work / "notebooks"
        shutil.copytree(ROOT / "notebooks", self.root,
                        ignore=shutil.ignore_patterns(".ipynb_checkpoints", "pages", "__pycache__"))
        settings = work / "settings" / "@jupyterlab" / "apputils-extension"
        settings.mkdir(parents=True)
        (settings / "notification.jupyterlab-settings").write_text(
            json.dumps({"fetchNews": "false", "checkForUpdates": False}))
        self.token, self.port = secrets.token_hex(16), free_port()
        self.url = f"http://127.0.0.1:{self.port}"
        env = {k: v for k, v in os.environ.items() if k != "RBCOURSE_QUICK"}        # a student's full-length run
        env.pop("MPLBACKEND", None)                                                  # the kernel's inline figures
        env.update(JUPYTER_CONFIG_DIR=str(work / "config"), JUPYTER_DATA_DIR=str(work / "data"),
                   JUPYTER_RUNTIME_DIR=str(work / "runtime"))
        self.log = open(work / "jupyterlab.log", "wb")
        self.proc = subprocess.Popen(
            [python, "-m", "jupyterlab", "--no-browser", "--allow-root", "--ip=127.0.0.1", f"--port={self.port}",
             "--LabApp.extension_manager=readonly",                  # no query of PyPI
             f"--IdentityProvider.token={self.token}", f"--ServerApp.root_dir={self.root}",
             f"--LabApp.user_settings_dir={work / 'settings'}", f"--LabApp.workspaces_dir={work / 'workspaces'}"],
            env=env, stdout=self.log, stderr=subprocess.STDOUT, start_new_session=True)
        deadline = time.monotonic() + 120
        while True:
            try:
                self.api("GET", "/api/status")
                return
            except OSError:
                if self.proc.poll() is not None or time.monotonic() > deadline:
                    raise SystemExit(f"JupyterLab did not start: see {work / 'jupyterlab.log'}")
                time.sleep(0.5)

    def api(self, method: str, path: str):
        req = urllib.request.Request(self.url + path, method=method,
                                     headers={"Authorization": f"token {self.token}"})
        with urllib.request.urlopen(req, timeout=30) as r:
            body = r.read()
        return json.loads(body) if body else None

    def busy(self) -> bool:
        return any(k["execution_state"] != "idle" for k in self.api("GET", "/api/kernels"))

    def stop_kernels(self):
        for s in self.api("GET", "/api/sessions"):
            self.api("DELETE", f"/api/sessions/{s['id']}")

    def close(self):
        self.proc.terminate()
        try:
            self.proc.wait(20)
        except subprocess.TimeoutExpired:
            self.proc.kill()
        self.log.close()


def palette(page, command: str):
    """The command palette (Ctrl+Shift+C, as the views' fallback says), then `command`."""
    page.keyboard.press("Control+Shift+C")
    box = page.locator(".lm-CommandPalette-input")
    box.wait_for(state="visible", timeout=10_000)
    box.fill(command)
    page.locator(".lm-CommandPalette-item.lm-mod-active").wait_for(timeout=10_000)
    page.keyboard.press("Enter")


def open_notebook(page, lab: Lab, rel: str):
    page.goto(f"{lab.url}/lab/tree/{rel}?reset&token={lab.token}")
    page.locator(".jp-NotebookPanel .jp-Notebook").first.wait_for(timeout=120_000)
    deadline = time.monotonic() + 120
    while not lab.api("GET", "/api/kernels") or lab.busy():                  # the kernel started, idle
        if time.monotonic() > deadline:
            raise RuntimeError("the kernel did not start")
        time.sleep(0.5)
    page.locator(".jp-NotebookPanel .jp-Notebook").first.click(position={"x": 5, "y": 5})


def wait_idle(lab: Lab, timeout: float, quiet: float = 4.0):
    """The kernel idle for `quiet` seconds in a row (Run All sends the cells one after another)."""
    deadline, since = time.monotonic() + timeout, None
    while time.monotonic() < deadline:
        if lab.busy():
            since = None
        elif since is None:
            since = time.monotonic()
        elif time.monotonic() - since >= quiet:
            return
        time.sleep(0.5)
    raise RuntimeError(f"Run All did not finish in {timeout:.0f} s")


def views(page, shots: Path | None, name: str) -> tuple[int, list[str]]:
    """Each 3-D view of the notebook scrolled into sight: meshcat's canvas drawn in its frame, no missing-script
    message.  (number of views, problems)."""
    found, problems = page.locator(".rbcourse-view"), []
    n = found.count()
    for i in range(n):
        view = found.nth(i)
        view.scroll_into_view_if_needed(timeout=30_000)
        handle = view.locator("iframe").element_handle(timeout=30_000)
        frame = handle.content_frame() if handle else None
        if frame is None:
            problems.append(f"view {i + 1}: no frame (untrusted output?)")
            continue
        deadline, state = time.monotonic() + VIEW_TIMEOUT, None
        while time.monotonic() < deadline:
            try:
                state = frame.evaluate("[!!document.querySelector('#meshcat-pane canvas, canvas'), "
                                       "(document.getElementById('rb-missing') || {}).textContent || '']")
            except Exception:               # the frame still loading
                state = None
            if state and (state[0] or state[1]):
                break
            time.sleep(0.5)
        if not state or not state[0]:
            problems.append(f"view {i + 1}: blank" + (f" ({state[1][:80]}...)" if state and state[1] else ""))
        if shots is not None and i == 1:                   # the second view: it borrows meshcat's script
            time.sleep(2)
            page.screenshot(path=str(shots / f"{name.replace('/', '_')}_view2.png"))
    return n, problems


def check_saved(path: Path) -> tuple[int, list[int], list[int]]:
    """(size in bytes, cells writing to stderr, cells with an error) of the saved notebook."""
    nb = json.loads(path.read_text(encoding="utf-8"))
    stderr, errors = [], []
    for i, cell in enumerate(nb["cells"]):
        for out in cell.get("outputs", []):
            if out.get("output_type") == "stream" and out.get("name") == "stderr":
                stderr.append(i)
            if out.get("output_type") == "error":
                errors.append(i)
    return path.stat().st_size, sorted(set(stderr)), sorted(set(errors))


def run_all(page, lab: Lab, rel: str, shots: Path | None) -> dict:
    path = lab.root / rel
    before = path.stat().st_mtime_ns
    start = time.monotonic()
    open_notebook(page, lab, rel)
    palette(page, "Run All Cells")
    time.sleep(2)
    wait_idle(lab, RUN_TIMEOUT)
    seconds = time.monotonic() - start
    n_views, problems = views(page, shots, rel)
    page.keyboard.press("Control+s")
    deadline = time.monotonic() + 60
    while path.stat().st_mtime_ns == before or page.locator(".jp-mod-dirty").count():
        if time.monotonic() > deadline:
            raise RuntimeError("the notebook was not saved")
        time.sleep(0.3)
    time.sleep(1)
    size, stderr, errors = check_saved(path)
    lab.stop_kernels()
    return {"name": rel, "size": size, "seconds": seconds, "stderr": stderr, "errors": errors, "views": n_views,
            "problems": problems}


def trust_check(page, lab: Lab, rel: str, shots: Path | None) -> list[str]:
    """The trust instruction as written: an untrusted copy of a run notebook shows the fallback; the command
    palette's "Trust Notebook" makes its 3-D view render."""
    nb = json.loads((lab.root / rel).read_text(encoding="utf-8"))
    nb["metadata"]["rbcourse_trust_check"] = True                   # not the signed content: untrusted
    target = (lab.root / rel).with_name("trust_check.ipynb")
    target.write_text(json.dumps(nb, indent=1, ensure_ascii=False), encoding="utf-8")
    open_notebook(page, lab, target.relative_to(lab.root).as_posix())
    problems = []
    hint = page.locator(".rbcourse-view", has_text="Trust Notebook").first
    try:
        hint.wait_for(timeout=30_000)
        if "Ctrl+Shift+C" not in hint.text_content() and "Ctrl+Maj+C" not in hint.text_content():
            problems.append(f"the fallback does not name the command palette's shortcut: {hint.text_content()[:300]!r}")
        if page.locator(".rbcourse-view iframe").count():
            problems.append("an untrusted notebook shows the frame")
    except Exception:
        problems.append("the untrusted notebook shows no fallback naming “Trust Notebook”")
    palette(page, "Trust Notebook")
    page.locator(".jp-Dialog .jp-mod-accept").click(timeout=10_000)
    time.sleep(2)
    n, bad = views(page, None, "trust")
    if n == 0:
        problems.append("after “Trust Notebook” no 3-D view is shown")
    problems += [f"after “Trust Notebook”: {b}" for b in bad]
    if shots is not None:
        page.locator(".rbcourse-view").first.scroll_into_view_if_needed()
        time.sleep(2)
        page.screenshot(path=str(shots / "trusted.png"))
    lab.stop_kernels()
    target.unlink()
    return problems


def notebooks(args) -> list[str]:
    base = ROOT / "notebooks"
    if args:
        return [Path(a).resolve().relative_to(base).as_posix() for a in args]
    return sorted(p.relative_to(base).as_posix() for p in base.rglob("*.ipynb")
                  if ".ipynb_checkpoints" not in p.parts)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("notebooks", nargs="*")
    parser.add_argument("--python", default=sys.executable, help="the Python whose JupyterLab and kernel run")
    parser.add_argument("--shots", default=None, help="a folder for screenshots (a shared-script view, the trust check)")
    args = parser.parse_args(argv)
    shots = Path(args.shots) if args.shots else None
    if shots:
        shots.mkdir(parents=True, exist_ok=True)
    names = notebooks(args.notebooks)
    work = Path(tempfile.mkdtemp(prefix="rbcourse-lab-"))
    lab = Lab(args.python, work)
    rows, failed, trust = [], 0, []
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, args=FLAGS, headless=True)
            page = browser.new_page(viewport={"width": 1280, "height": 900})
            for rel in names:
                try:
                    row = run_all(page, lab, rel, shots)
                except Exception as err:                        # a time-out, a dead kernel: this notebook fails
                    row = {"name": rel, "size": 0, "seconds": 0.0, "stderr": [], "errors": [], "views": 0,
                           "problems": [f"{type(err).__name__}: {str(err).splitlines()[0][:200]}"]}
                    try:
                        lab.stop_kernels()
                    except OSError:
                        pass
                ok = (0 < row["size"] <= MAX_BYTES and not row["stderr"] and not row["errors"]
                      and not row["problems"])
                failed += not ok
                rows.append(row)
                print(f"{'ok  ' if ok else 'FAIL'} {row['name']:<42} {row['size'] / 1e6:6.3f} MB {row['seconds']:7.1f} s "
                      f"stderr cells {row['stderr'] or '-'}  errors {row['errors'] or '-'}  views {row['views']}"
                      + (f"  — {'; '.join(row['problems'])}" if row["problems"] else ""), flush=True)
            with_views = [r["name"] for r in rows if r["views"] and not r["problems"]]
            if with_views:
                trust = trust_check(page, lab, with_views[0], shots)
                print(f"{'ok  ' if not trust else 'FAIL'} trust instruction on {with_views[0]}"
                      + (f": {'; '.join(trust)}" if trust else ": fallback shown, “Trust Notebook” from the palette, "
                                                              "3-D view rendered"), flush=True)
            else:
                trust = ["no notebook with a 3-D view ran: the trust instruction was not checked"]
                print("FAIL " + trust[0])
            browser.close()
    finally:
        lab.close()
        shutil.rmtree(work, ignore_errors=True)
    total = sum(r["seconds"] for r in rows)
    print(f"JupyterLab Run All: {failed} of {len(rows)} notebooks failed, {total:.0f} s of runs; largest "
          f"{max((r['size'] for r in rows), default=0) / 1e6:.3f} MB (limit {MAX_BYTES / 1e6:g} MB)", flush=True)
    return 1 if failed or trust else 0


if __name__ == "__main__":
    sys.exit(main())
