"""The live meshcat server's start: a start that hangs is stopped and tried once more, and says where it waited."""
import os

import pytest

pytest.importorskip("meshcat")

from rbcourse.viz.viewer import live  # noqa: E402

_HANG = "import time; time.sleep(300)   # a start that hangs\n"


def _hanging(first_only: bool) -> str:
    """The server's script, made to hang before its imports (the first start only, or every start)."""
    head, tail = live._SERVER_SCRIPT.split("import tornado.ioloop, tornado.web", 1)
    if first_only:   # a mark beside the static folder (argv[2]) says a start has hung already
        hang = ("_mark = os.path.join(os.path.dirname(sys.argv[2]), 'hung-once')\n"
                "if not os.path.exists(_mark):\n    open(_mark, 'w').close()\n    " + _HANG)
    else:
        hang = _HANG
    return head + hang + "import tornado.ioloop, tornado.web" + tail


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    with open(f"/proc/{pid}/stat") as f:           # a zombie is gone too
        return f.read().rsplit(")", 1)[1].split()[0] != "Z"


def test_a_start_that_hangs_once_is_tried_again(monkeypatch):
    monkeypatch.setattr(live, "_SERVER_SCRIPT", _hanging(first_only=True))
    pids = []
    popen = live.subprocess.Popen

    def recording_popen(*args, **kwargs):
        proc = popen(*args, **kwargs)
        pids.append(proc.pid)
        return proc

    monkeypatch.setattr(live.subprocess, "Popen", recording_popen)
    server = live.LiveServer(timeout=6)
    try:
        assert server.running and server.url.startswith("http://127.0.0.1:")
        assert len(pids) == 2 and not _alive(pids[0]) and pids[1] == server.proc.pid
        server.send(live.SetAnimation(live.Animation(), play=False).lower())     # it answers
    finally:
        server.close()
    assert not _alive(pids[1])


def test_a_start_that_always_hangs_stops_and_says_where(monkeypatch):
    monkeypatch.setattr(live, "_SERVER_SCRIPT", _hanging(first_only=False))
    with pytest.raises(RuntimeError, match=r"did not start: twice it printed no address within 4 s") as err:
        live.LiveServer(timeout=8)
    assert 'File "<string>"' in str(err.value)          # faulthandler's dump: where the script waited


def test_a_start_that_fails_is_not_tried_again(monkeypatch):
    monkeypatch.setattr(live, "_SERVER_SCRIPT", "import sys; sys.exit('no server here')")
    with pytest.raises(RuntimeError, match=r"did not start \(exit code 1\): no server here"):
        live.LiveServer(timeout=6)
