"""One source, two versions: the student notebook is generated from the solution notebook.

The solution notebook is the single source.  A notebook in a ``solutions/`` folder generates the notebook
of the same name in the parent folder (``notebooks/solutions/01_exercise_euler.ipynb`` →
``notebooks/01_exercise_euler.ipynb``; ``notebooks/fr/solutions/X.ipynb`` → ``notebooks/fr/X.ipynb``),
by ``python -m rbcourse assignment build``.  The markers are nbgrader's, so an instructor can also use
nbgrader as is:

* **Code cells.**  A cell holding a solution has nbgrader's cell metadata
  ``{"nbgrader": {"solution": true, "grade": false, "locked": false, "grade_id": "<function name>",
  "schema_version": 3}}``, and its solution between the lines ``### BEGIN SOLUTION`` and
  ``### END SOLUTION``.  The student version has, instead of each region, at the region's indentation::

      # YOUR CODE HERE                (French, notebook metadata rbcourse.language == "fr": # VOTRE CODE ICI)
      raise NotImplementedError()

  Everything outside the regions stays: the signature, the docstring, a line such as ``x, R, P, L = X``,
  and the hint comments written just above ``### BEGIN SOLUTION``.  The checks say "not done yet" for
  a function that raises NotImplementedError, so the student version runs clean as shipped.
* **Markdown cells.**  Text between ``<!-- SOLUTION ONLY -->`` and ``<!-- /SOLUTION ONLY -->`` (inline or
  over several lines, the markers included) is removed from the student version: the title's
  "— solution", the sentence saying this is the solution notebook.  (nbgrader knows no such marker: a
  notebook released by nbgrader keeps these words.)
* **Everything else** — cells, cell ids, cell and notebook metadata — is copied unchanged.

Outputs.  The student notebook's stored outputs are made by running it (nbclient, this Python's kernel,
RBCOURSE_QUICK=1, its folder as the working directory), as nbval compares the cells tagged
``nbval-check-output`` with them; the outputs of cells tagged ``meshcat`` (a 3-D page, about 1 MB)
are not stored, and a cell's consecutive prints are one output (how they are cut depends on the kernel's
flushes).  The comparison with the stored student notebook (``--check``, and the tests) ignores outputs
and execution counts: it compares the cells' types, ids, sources and metadata, and the notebook's
metadata.  The JSON is written as nbformat writes it (sorted keys, indent 1): the same solution gives
the same bytes (two builds of notebook 01 gave identical files, figures included).

``solution_functions(path)`` runs the functions of a solution notebook without running the notebook: the
tests check the solution from the notebook itself, not from a copy.

The package, one concept a module (every name below importable from rbcourse.workbook.assignment):
    notebooks   AssignmentError; reading, writing and finding notebooks (student_path, solution_notebooks)
    student     generate: the student version (the markers BEGIN, END, ONLY, ONLY_END; STUBS)
    execute     run, build: the student version with its outputs
    compare     differences, check: the stored student notebook against the generated one
    functions   solution_functions
"""
from __future__ import annotations

from .compare import check, differences
from .execute import CELL_TIMEOUT, MESHCAT_TAG, build, run
from .functions import solution_functions
from .notebooks import (AssignmentError, is_solution_cell, notebooks_folders, read_notebook, solution_notebooks, source,
                        student_path, writes)
from .student import BEGIN, END, ONLY, ONLY_END, STUBS, clear_regions, clear_solution_only, generate, language

__all__ = ["AssignmentError", "BEGIN", "END", "ONLY", "ONLY_END", "STUBS", "MESHCAT_TAG", "CELL_TIMEOUT",
           "student_path", "read_notebook", "writes", "source", "language", "is_solution_cell", "clear_regions",
           "clear_solution_only", "generate", "run", "build", "differences", "check", "notebooks_folders",
           "solution_notebooks", "solution_functions"]
