"""What every layer of the package uses, at its bottom (beside the kernel): the input checks (checks.py),
the run-length flag (config.py), whole-file writes (outputs.py), the language of every text and its glossary
(language.py, glossary.py), the runner of independent tasks on every core or a Dask cluster (parallel.py), and
Ctrl-C for the command line (interrupts.py).
It imports nothing of rbcourse outside support/."""
