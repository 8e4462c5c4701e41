# Shared by the Python tests: where the data is (CTest sets the variables;
# run by hand, the repository's data/ and ../shared/data beside it), and one
# solve of the shipped Ladybug problem reused by several tests.
import os
import pathlib

import pytest

import dba

ROOT = pathlib.Path(__file__).resolve().parents[2]
REPO_DATA = pathlib.Path(os.environ.get("DBA_REPO_DATA_DIR", ROOT / "data"))
SHARED_DATA = pathlib.Path(os.environ.get("DBA_SHARED_DATA_DIR", ROOT.parent / "shared" / "data"))

# problem-49-7776 (Ladybug), shipped in data/: its initial cost and the exact
# final cost from a direct sparse Schur factorization (as
# src/dba/lm/bal_problems_test.cc; reached within 1e-5 relative, the
# agreement rule).
LADYBUG = REPO_DATA / "problem-49-7776-pre.txt.bz2"
LADYBUG_INITIAL_COST = 8.509125e+05
LADYBUG_EXACT_COST = 1.334432e+04

# The report's time phases (summary.seconds), which add up to its total.
TIME_PHASES = ("startup", "read", "load", "distribution", "setup", "rcs_formation", "linear_solve",
               "back_substitution", "analysis", "write", "other")


@pytest.fixture(scope="session")
def ladybug_result():
    return dba.solve(LADYBUG, threads=2)


@pytest.fixture(scope="session")
def ladybug_problem():
    return dba.read_problem(LADYBUG)
