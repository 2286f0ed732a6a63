import subprocess
import sys

import pytest

from rbcourse.__main__ import main


def test_demo_writes_its_files(tmp_path, capsys):
    assert main(["demo", "--t-end", "0.3", "--dt", "0.01", "--out", str(tmp_path)]) == 0
    printed = capsys.readouterr().out
    for name in ["trajectory.csv", "drift.png", "energy.png", "summary.txt"]:
        assert (tmp_path / name).stat().st_size > 100
        assert f"wrote {tmp_path / name}" in printed
    summary = (tmp_path / "summary.txt").read_text()
    assert "pushed box" in summary and "rk4" in summary and "euler" in summary
    rows = (tmp_path / "trajectory.csv").read_text().splitlines()
    assert rows[0].startswith("t,x,y,z") and len(rows) == 32


def test_demo_rejects_bad_arguments(tmp_path):
    for bad in (["demo", "--dt", "-1", "--out", str(tmp_path)], ["demo", "--method", "nope", "--out", str(tmp_path)],
                ["demo", "no_such_scene"]):
        with pytest.raises(SystemExit) as info:
            main(bad)
        assert info.value.code == 2


def test_module_entry_point(tmp_path):
    out = subprocess.run([sys.executable, "-m", "rbcourse", "demo", "--t-end", "0.05", "--dt", "0.01",
                          "--out", str(tmp_path)], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert "summary.txt" in out.stdout
