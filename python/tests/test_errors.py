# Errors become Python exceptions with the command line's messages: malformed
# input is a dba.InputError (a ValueError) naming the file and the line.
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
