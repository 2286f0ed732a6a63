"""The command line: a bad argument is one line and exit code 2, before anything is computed or
written; Ctrl-C keeps the finished runs of bench and stability; demos of two scenes share a folder."""
import csv
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from rbcourse.bench import work_precision as bench
from rbcourse.workbook import demo
from rbcourse.bench import stability
from rbcourse.bench import throughput
from rbcourse.__main__ import main

PROG = "python -m rbcourse"

# (arguments, a word the one line must hold): {file} is an existing file, {tmp} an empty folder
BAD = [
    (["demo", "no_such_scene"], "scene"),
    (["demo", ""], "scene"),
    (["demo", "--method", "nope"], "--method"),
    (["demo", "--method", ""], "--method"),
    (["demo", "--dt", "-1"], "--dt"),
    (["demo", "--dt", "0"], "--dt"),
    (["demo", "--dt", "nan"], "--dt"),
    (["demo", "--dt", "one"], "--dt"),
    (["demo", "--t-end", "inf"], "--t-end"),
    (["demo", "--t-end", "-2"], "--t-end"),
    (["demo", "--dt", "1e-9"], "t_end / dt"),                      # 5e9 steps
    (["demo", "--t-end", "1e308"], "got inf steps"),                 # t_end / dt overflows: no OverflowError
    (["demo", "many_bodies", "--dt", "1e-5"], "200 bodies"),        # 5e5 steps × 200 bodies
    (["demo", "--dt", "10"], "dt must be <= t_end"),
    (["demo", "--out", "{file}"], "--out"),
    (["demo", "--out", "{file}/sub"], "--out"),
    (["demo", "--out", "/proc/x"], "--out"),
    (["demo", "--out", ""], "--out"),
    (["demo", "--out", "{tmp}/pushed_box_summary.txt/.."], "--out"),  # a path through a name that is a file
    (["demo", "--frobnicate"], "--frobnicate"),
    (["demo", "--out"], "--out"),
    (["bench", "--problems", "D"], "--problems"),
    (["bench", "--problems", ""], "--problems"),
    (["bench", "--methods", "verlet"], "--methods"),
    (["bench", "--methods", ""], "--methods"),
    (["bench", "--methods"], "--methods"),
    (["bench", "--repeats", "0"], "--repeats"),
    (["bench", "--repeats", "1.5"], "--repeats"),
    (["bench", "--repeats", "1000"], "--repeats"),
    (["bench", "--out", "{file}"], "--out"),
    (["bench", "--out", "/proc/x"], "--out"),
    (["bench", "--out", ""], "--out"),
    (["bench", "--out", "{tmp}/has_a_folder"], "is a folder"),      # results.csv there is a folder
    (["bench", "stray"], "stray"),
    (["bench", "--out", "x" * 300], "at most 255 bytes"),         # the file system's "File name too long" (Errno 36)
    (["bench", "--out", "{tmp}/" + "é" * 200], "400 bytes"),      # 200 characters, 400 bytes in UTF-8
    (["demo", "--out", "d" * 300], "at most 255 bytes"),
    (["demo", "--out", "{tmp}/" + "/".join(["a" * 200] * 21)], "at most 4095 bytes"),
    (["notebooks", "--to", "n" * 300], "at most 255 bytes"),
    (["grade", "{tmp}", "--out", "g" * 300 + ".csv"], "--out: a file or folder name must be at most 255 bytes"),
    (["grade", "{tmp}", "--out", "{tmp}/g.csv", "--feedback", "f" * 300], "--feedback"),
    (["stability", "--cases", "nope"], "--cases"),
    (["stability", "--methods", ""], "--methods"),
    (["stability", "--out", "{file}/sub"], "--out"),
    (["stability", "--out", ""], "--out"),
    (["stability", "--quick", "--quiet"], "--quiet"),
    (["throughput", "--bodies", "1"], "--bodies"),
    (["throughput", "--bodies", "1000000000"], "1,000,000"),
    (["throughput", "--bodies", "ten"], "--bodies"),
    (["throughput", "--out", "/proc/x"], "--out"),
    (["frobnicate"], "frobnicate"),
    ([], "required"),
]


@pytest.fixture
def nothing_runs(monkeypatch, tmp_path):
    """No command may start: each entry point fails the test if called.  The current folder is an
    empty one (where the default output folders would appear)."""
    def forbidden(*args, **kwargs):
        raise AssertionError("a bad argument must be refused before anything is computed")
    for module, name in ((demo, "run_demo"), (demo, "simulate"), (bench, "main"), (bench, "run_all"),
                         (stability, "main"), (stability, "matrix"), (throughput, "main")):
        monkeypatch.setattr(module, name, forbidden)
    cwd = tmp_path / "cwd"
    cwd.mkdir()
    monkeypatch.chdir(cwd)
    return cwd


@pytest.mark.parametrize("argv, word", BAD, ids=[" ".join(a) or "(none)" for a, _ in BAD])
def test_a_bad_argument_is_one_line_and_exit_code_2_before_anything_runs(argv, word, tmp_path, nothing_runs, capsys):
    if any(a == "/proc/x" for a in argv) and not Path("/proc").is_dir():
        pytest.skip("no /proc on this system")
    afile, folder = tmp_path / "a_file", tmp_path / "folder"
    afile.write_text("not a folder")
    folder.mkdir()
    (folder / "pushed_box_summary.txt").write_text("a file")
    (folder / "has_a_folder" / "results.csv").mkdir(parents=True)
    before = sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*"))
    argv = [a.format(file=afile, tmp=folder) for a in argv]
    with pytest.raises(SystemExit) as info:
        main(argv)
    assert info.value.code == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.count("\n") == 1 and err.endswith("\n"), err           # exactly one line
    assert err.startswith(f"{PROG}") and ": error: " in err and word in err, err
    # nothing written: no new file or folder (not even the default output folder), the file untouched
    assert sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*")) == before
    assert afile.read_text() == "not a folder" and not Path("/proc/x").exists()


def test_bad_arguments_from_a_fresh_process(tmp_path):
    afile = tmp_path / "a_file"
    afile.write_text("")
    for argv in (["demo", "--out", str(afile)], ["bench", "--quick", "--frob"], ["stability", "--methods", "nope"]):
        run = subprocess.run([sys.executable, "-m", "rbcourse", *argv], capture_output=True, text=True, timeout=120)
        assert run.returncode == 2 and run.stdout == ""
        assert len(run.stderr.splitlines()) == 1 and run.stderr.startswith(f"{PROG} {argv[0]}: error: "), run.stderr


def test_no_command_names_every_command(capsys):
    """`python -m rbcourse` alone says one line naming every command there is (it once left out `notebooks`): the
    list is the parser's own, in the usage and in the error, and --help lists each."""
    from rbcourse.__main__ import _parser
    parser, commands = _parser()
    assert {"demo", "explore", "notebooks", "bench", "throughput", "stability", "grade", "assignment",
            "compile"} <= set(commands)
    with pytest.raises(SystemExit) as info:
        main([])
    assert info.value.code == 2
    err = capsys.readouterr().err
    listed = err.rstrip("\n").rsplit("{", 1)[1].rstrip("}").split(",")
    assert sorted(listed) == sorted(commands), err
    usage, helped = parser.format_usage(), parser.format_help()
    for name in commands:
        assert name in usage.split("{", 1)[1] and f"\n    {name} " in helped, name


def test_two_demo_scenes_in_one_folder_keep_their_own_files(tmp_path, capsys):
    args = ["--t-end", "0.04", "--dt", "0.01", "--out", str(tmp_path)]
    assert main(["demo", "pushed_box", *args]) == 0
    first = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    assert sorted(first) == sorted(demo.output_names("pushed_box"))
    assert main(["demo", "tennis_racket", *args]) == 0
    after = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    assert sorted(after) == sorted(demo.output_names("pushed_box") + demo.output_names("tennis_racket"))
    assert all(after[name] == content for name, content in first.items())      # the first demo's files untouched
    assert b"pushed box" in after["pushed_box_summary.txt"] and b"tennis racket" in after["tennis_racket_summary.txt"]
    printed = capsys.readouterr().out
    assert all(f"wrote {tmp_path / name}" in printed for name in demo.output_names("tennis_racket"))


# --- Ctrl-C -------------------------------------------------------------------------------

def _interrupt(argv, out: Path, csv_name: str, rows: int = 1):
    """Run the command, send SIGINT once `rows` rows are in its CSV; (return code, stderr)."""
    proc = subprocess.Popen([sys.executable, "-m", "rbcourse", *argv, "--out", str(out)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, text=True,
                            # a shell may start background jobs with SIGINT ignored; the test means Ctrl-C
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        deadline = time.monotonic() + 180
        path = out / csv_name
        while time.monotonic() < deadline and proc.poll() is None:
            if path.exists() and path.read_text(encoding="utf-8").count("\n") >= 1 + rows:
                break
            time.sleep(0.05)
        assert proc.poll() is None, "the command ended before it could be interrupted"
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    return proc.returncode, err


def _check_partial(out: Path, csv_name: str, md_name: str, header: str, columns: int, code: int, err: str):
    assert code == 130, err
    text = (out / csv_name).read_text(encoding="utf-8")
    assert text.endswith("\n")                                    # no truncated last row
    table = list(csv.reader(text.splitlines()))
    assert table[0] == header.split(",") and len(table) >= 2
    assert all(len(row) == columns for row in table)
    for row in table[1:]:
        [float(v) for v in row[3:]]                               # every number whole
    n = len(table) - 1
    md = (out / md_name).read_text(encoding="utf-8")
    assert md.startswith(f"# partial: interrupted after {n} of ")
    last = err.strip().splitlines()[-1]
    assert f"interrupted after {n} of " in last and f"kept the {n} finished in" in last and str(out / csv_name) in last
    assert not [p.name for p in out.iterdir() if p.name.startswith(".")]   # no temporary file left


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT to a child process")
def test_ctrl_c_during_bench_keeps_the_finished_runs(tmp_path):
    out = tmp_path / "bench"
    out.mkdir()
    for name in bench.OUTPUTS:                                    # a previous run's files
        (out / name).write_text("OLD")
    (out / "notes.txt").write_text("mine")
    code, err = _interrupt(["bench", "--quick", "--no-peers"], out, "results.csv", rows=2)
    _check_partial(out, "results.csv", "results.md", bench.CSV_HEADER, 7, code, err)
    for name in bench.OUTPUTS:                                    # never a mix of the old run and the new one
        assert not (out / name).exists() or (out / name).read_bytes() != b"OLD"
    assert (out / "work_precision.png").read_bytes()[:4] == b"\x89PNG"
    assert (out / "notes.txt").read_text() == "mine"              # only its own files are replaced


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT to a child process")
def test_ctrl_c_during_stability_keeps_the_finished_runs(tmp_path):
    out = tmp_path / "stability"
    code, err = _interrupt(["stability", "--quick"], out, "stability.csv")
    _check_partial(out, "stability.csv", "stability.md", stability.CSV_HEADER, 12, code, err)


@pytest.mark.parametrize("at", [1, 3])
def test_an_interrupt_at_any_run_leaves_consistent_files(at, tmp_path, monkeypatch, capsys):
    """In process, Ctrl-C simulated at the first or the third run: what the command keeps, and says."""
    for name in bench.OUTPUTS:                                    # a previous run's files
        (tmp_path / name).write_text("OLD")
    calls = []

    def run(problem, method, setting, repeats, min_total=0.0):
        calls.append(setting)
        if len(calls) == at:
            raise KeyboardInterrupt
        return bench.Run(problem.name, "rbcourse", method, setting, 10, 1e-3, 1e-4 / len(calls))
    monkeypatch.setattr(bench, "run_rbcourse", run)
    argv = ["bench", "--problems", "A", "--methods", "rk4", "--quick", "--no-peers", "--out", str(tmp_path)]
    assert main(argv) == 130
    done = at - 1
    rows = (tmp_path / "results.csv").read_text().splitlines()
    assert rows[0] == bench.CSV_HEADER and len(rows) == 1 + done
    assert all(row.endswith(f",{1e-4 / (i + 1):.6g}") for i, row in enumerate(rows[1:]))
    assert (tmp_path / "results.md").read_text().startswith(f"# partial: interrupted after {done} of 6 planned runs")
    assert (tmp_path / "work_precision.png").exists() == (done > 0)     # no old plot beside the new results
    assert all((tmp_path / name).read_bytes() != b"OLD" for name in bench.OUTPUTS if (tmp_path / name).exists())
    last = capsys.readouterr().err.strip().splitlines()[-1]        # after the progress bar
    assert last.startswith(f"{PROG} bench: interrupted after {done} of 6 ") and str(tmp_path / "results.csv") in last
    # and a run to the end replaces every partial file
    monkeypatch.setattr(bench, "run_rbcourse", lambda p, m, s, r, mt=0.0: bench.Run(p.name, "rbcourse", m, s, 10,
                                                                                    1e-3, 1e-4))
    assert main(argv) == 0
    md = (tmp_path / "results.md").read_text()
    assert not md.startswith("# partial") and "## Problem A" in md
    assert len((tmp_path / "results.csv").read_text().splitlines()) == 1 + 6
    assert (tmp_path / "work_precision.png").read_bytes()[:4] == b"\x89PNG"


def test_a_file_is_written_whole_or_not_at_all(tmp_path):
    from rbcourse.support.outputs import write_text, write_with
    path = write_text(tmp_path / "report.md", "old\n")

    def fails(tmp):
        tmp.write_text("half")
        raise KeyboardInterrupt
    with pytest.raises(KeyboardInterrupt):
        write_with(path, fails)
    assert path.read_text() == "old\n" and [p.name for p in tmp_path.iterdir()] == ["report.md"]
    write_text(path, "new\n")
    assert path.read_text() == "new\n" and os.stat(path).st_mode & 0o044   # readable as any output (umask)


LEAVE = """
import atexit, sys, threading, time
from pathlib import Path
from rbcourse.support.interrupts import leave
out = Path(sys.argv[1])
atexit.register(lambda: (out / "atexit").write_text("ran"))
if sys.argv[2] == "thread":                 # a thread still at work: the normal exit waits for it
    threading.Thread(target=lambda: (time.sleep(0.3), (out / "thread").write_text("done"))).start()
threading.Thread(target=time.sleep, args=(60,), daemon=True).start()    # a daemon (tqdm's monitor): not waited for
print("no newline at the end", end="")
sys.stderr.write("said")
leave(3)
"""


@pytest.mark.parametrize("way", ["alone", "thread"])
def test_leaving_runs_the_exit_handlers_flushes_the_output_and_keeps_the_code(way, tmp_path):
    """interrupts.leave, the CLI's exit without the interpreter's teardown: the atexit handlers run, the output is
    all there, the exit code is kept; a thread still running is waited for (the normal exit)."""
    done = subprocess.run([sys.executable, "-c", LEAVE, str(tmp_path), way], capture_output=True, text=True,
                          timeout=120)
    assert (done.returncode, done.stdout, done.stderr) == (3, "no newline at the end", "said")
    assert (tmp_path / "atexit").read_text() == "ran"
    if way == "thread":
        assert (tmp_path / "thread").read_text() == "done"


def test_the_pool_starts_the_resource_tracker_with_its_warnings_ignored():
    """A Ctrl-C inside a semaphore's clean-up leaves multiprocessing's tracker a name already unlinked: its warning
    must not come after the command's last words (the tracker takes its -W flags from sys.warnoptions)."""
    import subprocess as sp
    from rbcourse.support import parallel
    script = ("import sys; from rbcourse.support import parallel; from multiprocessing import resource_tracker\n"
              "list(parallel._run_pool(abs, [-1, 2], 2)); resource_tracker.register('/mp-rbcourse-gone', 'semaphore')\n")
    done = sp.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert "resource_tracker" not in done.stderr, done.stderr
    assert parallel.QUIET_TRACKER.startswith("ignore::UserWarning:")
