"""What grading a class costs: the hostile class (test_grade_hostile.py: hostile_class, every kind of entry the tests
know) graded with `python -m rbcourse grade --workers 2`, and printed: its wall time, the processor time per hand-in
(its sandboxes', counted by their control groups — Graded.cpu_seconds, in the progress lines — and the grader's own
processes'), and the peak memory of the grader's own processes (those outside any sandbox), sampled every 0.1 s.

    .venv/bin/python tests/workbook/grade_figures.py          (as root, with bubblewrap: as the grader runs)
"""
import os, re, resource, shutil, subprocess, sys, tempfile, time, uuid
from pathlib import Path
HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE), str(HERE.parent)]
import test_grade_hostile as H

root = Path(tempfile.mkdtemp(prefix="class-figures-"))
subs, out, scratch = root / "SUBMISSIONS", root / "grades", root / "scratch"
subs.mkdir(); scratch.mkdir()
listener = H.Listener()
H.hostile_class(subs, out, "secret-x", listener.port, f"rbcourse-survivor-{uuid.uuid4().hex}", root / "flag")
n = len(os.listdir(subs))
ours = os.readlink("/proc/self/ns/pid")

def tree(pid):
    kids = {}
    for e in os.scandir("/proc"):
        if e.name.isdigit():
            try:
                ppid = int(open(f"/proc/{e.name}/stat", "rb").read().rpartition(b")")[2].split()[1])
            except (OSError, IndexError):
                continue
            kids.setdefault(ppid, []).append(int(e.name))
    todo, found = [pid], []
    while todo:
        p = todo.pop(); found.append(p); todo += kids.get(p, [])
    return found

def rss(pid):
    try:
        for line in open(f"/proc/{pid}/status"):
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 0

t0 = time.monotonic()
before = resource.getrusage(resource.RUSAGE_CHILDREN)
p = subprocess.Popen([sys.executable, "-m", "rbcourse", "grade", str(subs), "--out", str(out / "grades.csv"),
                      "--workers", "2"], cwd=str(HERE.parents[1]), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                     env={**os.environ, "TMPDIR": str(scratch)})
peak_one, peak_sum = 0, 0
while p.poll() is None:
    grader = [q for q in tree(p.pid) if os.path.exists(f"/proc/{q}/ns/pid") and os.readlink(f"/proc/{q}/ns/pid") == ours
              and b"bwrap" not in open(f"/proc/{q}/cmdline", "rb").read()[:5] and b"sh\0" != open(f"/proc/{q}/cmdline", "rb").read()[:3]]
    sizes = [rss(q) for q in grader]
    peak_one, peak_sum = max(peak_one, max(sizes, default=0)), max(peak_sum, sum(sizes))
    time.sleep(0.1)
output = p.stdout.read()
wall = time.monotonic() - t0
after = resource.getrusage(resource.RUSAGE_CHILDREN)
cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
listener.close()
sandbox_cpu = sum(float(m) for m in re.findall(r", ([0-9.]+) s of CPU\)", output))
print(output[-600:])
print(f"{n} entries graded in {wall:.0f} s (--workers 2); processor time {sandbox_cpu + cpu:.0f} s in all = "
      f"{(sandbox_cpu + cpu) / n:.2f} s per hand-in (its sandboxes' {sandbox_cpu:.0f} s, the grader's own processes' "
      f"{cpu:.0f} s); the grader's peak memory: {peak_one / 2**20:.0f} MB in one process, {peak_sum / 2**20:.0f} MB "
      f"for all its processes together")
shutil.rmtree(root, ignore_errors=True)
