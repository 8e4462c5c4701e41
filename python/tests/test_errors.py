# Errors become Python exceptions with the command line's messages: malformed
# input is a dba.InputError (a ValueError) naming the file and the line.
import bz2

import pytest

import dba
from conftest import LADYBUG


def test_malformed_bal_names_file_and_line(tmp_path):
    bad = tmp_path / "bad.txt"
    bad.write_text("2 2 3\n0 0 1.0 2.0\n1 0 3.0 4.0\n1 1 5.0 oops\n")
    with pytest.raises(dba.InputError) as info:
        dba.solve(bad)
    e = info.value
    assert isinstance(e, ValueError)
    assert e.file == str(bad) and e.line == 4
    assert str(e).startswith(f"{bad}:4: ")


def test_read_problem_raises_the_same(tmp_path):
    bad = tmp_path / "bad.txt"
    bad.write_text("1 1 1\n0 3 1.0 2.0\n")
    with pytest.raises(dba.InputError, match=rf"{bad}:2: .*point index"):
        dba.read_problem(bad)


def test_missing_file(tmp_path):
    with pytest.raises(dba.InputError, match="No such file or directory") as info:
        dba.solve(tmp_path / "missing.txt")
    assert info.value.line == 0


def test_fixing_out_of_range_is_a_value_error():
    with pytest.raises(ValueError, match="--fix-images: camera 49 does not exist"):
        dba.solve(LADYBUG, fix_images=[49])


def test_outputs_that_would_replace_an_input_or_each_other(tmp_path):
    # The rule of the command line (tests/cli_outputs.sh): refused before the
    # solve, naming both, and nothing is written.
    problem = tmp_path / "p.txt"
    problem.write_bytes(bz2.decompress(LADYBUG.read_bytes()))
    before = problem.read_bytes()
    with pytest.raises(ValueError, match=f"--report {problem} names INPUT {problem}"):
        dba.solve(problem, report=problem)
    out = tmp_path / "out.txt"
    with pytest.raises(ValueError, match="name one file"):
        dba.solve(problem, output=out, ply=out)
    with pytest.raises(ValueError, match="is a directory"):
        dba.solve(problem, report=tmp_path)
    assert problem.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.txt"]
