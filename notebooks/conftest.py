"""The notebooks under test (nbval, see pyproject.toml): long runs are shortened.

tests/conftest.py sets the same flag for the whole suite (`python -m pytest`); this file sets it when
only the notebooks run (`python -m pytest notebooks/`).  The nbval kernels inherit the environment,
and rbcourse.config.quick_mode() reads it.
"""
import os

os.environ.setdefault("RBCOURSE_QUICK", "1")
