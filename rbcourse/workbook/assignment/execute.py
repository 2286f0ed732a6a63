"""Running the generated student notebook for its outputs (run: nbclient, this Python's kernel, RBCOURSE_QUICK=1;
the cells tagged meshcat keep none, a cell's consecutive prints joined) and building it (build: its path and
JSON text)."""
from __future__ import annotations

import copy
import json
import os
import re
import subprocess
import sys
from pathlib import Path

from .notebooks import AssignmentError, source, student_path, writes
from .student import generate

MESHCAT_TAG = "meshcat"
CELL_TIMEOUT = 600          # s, per cell, when the student version is run


def _this_python_kernel():
    """A kernel manager that starts this Python (as nbval's --nbval-current-env)."""
    from jupyter_client.kernelspec import KernelSpec, KernelSpecManager
    from jupyter_client.manager import KernelManager

    class ThisPython(KernelSpecManager):
        def get_kernel_spec(self, kernel_name):
            return KernelSpec(argv=[sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"],
                              display_name="Python 3", language="python")
    return KernelManager(kernel_spec_manager=ThisPython(), kernel_name="python3")


def _joined_streams(outputs: list) -> list:
    """Consecutive stdout (or stderr) outputs as one: how a cell's printing is cut into outputs depends on
    when the kernel flushes, not on what it printed."""
    joined = []
    for out in outputs:
        last = joined[-1] if joined else None
        if (out.get("output_type") == "stream" and last is not None and last.get("output_type") == "stream"
                and last.get("name") == out.get("name")):
            last["text"] = source({"source": last["text"]}) + source({"source": out["text"]})
        else:
            joined.append(copy.deepcopy(out))
    return joined


def run(nb: dict, folder, label: str) -> dict:
    """The notebook with its outputs, run top to bottom under RBCOURSE_QUICK=1 in `folder`; the cells
    tagged meshcat keep no output; cell and notebook metadata unchanged.  A cell that raises is an
    AssignmentError naming it (label: the notebook's name)."""
    import nbformat
    from nbclient import NotebookClient
    from nbclient.exceptions import CellExecutionError
    node = nbformat.from_dict(copy.deepcopy(nb))
    client = NotebookClient(node, km=_this_python_kernel(), timeout=CELL_TIMEOUT, record_timing=False,
                            resources={"metadata": {"path": str(folder)}})
    saved = {key: os.environ.get(key) for key in ("RBCOURSE_QUICK", "MPLBACKEND")}
    os.environ["RBCOURSE_QUICK"] = "1"
    os.environ.pop("MPLBACKEND", None)
    try:
        client.execute(stderr=subprocess.DEVNULL)     # the kernel's own log (a cell's stderr is an output)
    except CellExecutionError as err:
        failed = next((i for i, c in enumerate(node.cells) if any(o.get("output_type") == "error"
                                                                  for o in c.get("outputs", []))), "?")
        ename, evalue = getattr(err, "ename", ""), getattr(err, "evalue", "")
        last = re.sub(r"\x1b\[[0-9;]*m", "", f"{ename}: {evalue}" if ename else str(err).strip().splitlines()[-1])
        last = " ".join(last.split())[:300]
        raise AssignmentError(f"{label}, cell {failed}: the generated student version raised when run: {last}") \
            from None
    finally:
        for key, value in saved.items():
            if value is None:
                os.environ.pop(key, None)
            else:
                os.environ[key] = value
    done = json.loads(json.dumps(node))
    for ran, cell in zip(done["cells"], nb["cells"]):
        ran["metadata"] = copy.deepcopy(cell.get("metadata", {}))
        if ran["cell_type"] == "code":
            ran["outputs"] = _joined_streams(ran["outputs"])
        if cell["cell_type"] == "code" and MESHCAT_TAG in cell.get("metadata", {}).get("tags", []):
            ran["outputs"], ran["execution_count"] = [], None
    done["metadata"] = copy.deepcopy(nb["metadata"])
    return done


def build(solution, *, execute: bool = True) -> tuple[Path, str]:
    """(the student notebook's path, its JSON text) generated from `solution`; execute: with its outputs
    (run as `run` says), else with none."""
    solution = Path(solution)
    target = student_path(solution)
    nb = generate(solution)
    if execute:
        nb = run(nb, target.parent, str(target))
    return target, writes(nb)
