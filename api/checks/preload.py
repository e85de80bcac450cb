"""Imported once by the check forkserver, so every check process starts with the library loaded.

Numerical libraries are held to one thread each: the service runs several checks side by
side, one process each, and CPU-time limits count every thread.
"""

from __future__ import annotations

import importlib
import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

WARM_MODULES = (
    "numpy",
    "scipy.spatial",
    "lxml.etree",
    "trimesh",
    "xacro",
    "uvicorn.main",  # the main module of `uvicorn ...`, which each check process re-imports
    "geomcheck.cli",  # the main module of `geomcheck serve`, which each check process re-imports
    "geomcheck.load.loader",
    "api.checks.sandbox",
    "api.checks.job",
)


def warm() -> None:
    """Import the library and every rule and check family; a failure here is left for the check to report."""
    for name in WARM_MODULES:
        try:
            importlib.import_module(name)
        except Exception:
            continue
    try:
        from geomcheck.checks import family_runners
        from geomcheck.rules import all_rules

        all_rules()
        family_runners()
    except Exception:
        return


warm()
