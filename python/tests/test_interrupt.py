# Ctrl-C stops a solve: SIGINT while dba.solve or dba.solve_arrays runs
# raises KeyboardInterrupt from the solve itself (the solve polls Python's
# signal handlers between LM and PCG iterations), and nothing is written.
# The solve here would otherwise run for hours (no tolerance stops it).
import signal
import subprocess
import sys
import textwrap
import time

import pytest

from conftest import LADYBUG

CHILD = textwrap.dedent("""
    import signal, sys
    import dba
    # Python's own handler, even where the parent left SIGINT ignored.
    signal.signal(signal.SIGINT, signal.default_int_handler)
    mode, path, out, report = sys.argv[1:]
    endless = dict(threads=2, max_iterations=1000000, function_tolerance=0.0,
                   gradient_tolerance=0.0, parameter_tolerance=0.0, linear_solver="pcg",
                   eta=0.0, pcg_tolerance=0.0)
    if mode == "file":
        print("solving", flush=True)
        dba.solve(path, output=out, report=report, **endless)
    else:
        p = dba.read_problem(path)
        print("solving", flush=True)
        dba.solve_arrays(p.cameras, p.points, p.observations, p.camera_indices,
                         p.point_indices, **endless)
    print("finished", flush=True)
""")


@pytest.mark.parametrize("mode", ["file", "arrays"])
def test_sigint_stops_the_solve_and_nothing_is_written(tmp_path, mode):
    out, report = tmp_path / "out.txt", tmp_path / "report.json"
    child = subprocess.Popen([sys.executable, "-c", CHILD, mode, str(LADYBUG), str(out),
                              str(report)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True)
    try:
        assert child.stdout.readline() == "solving\n"
        time.sleep(2)  # inside the solve (the call follows the line at once)
        child.send_signal(signal.SIGINT)
        stdout, stderr = child.communicate(timeout=120)
    finally:
        child.kill()
    assert child.returncode != 0
    assert "finished" not in stdout
    assert stderr.rstrip().endswith("KeyboardInterrupt"), stderr
    assert f"_dba.solve{'' if mode == 'file' else '_arrays'}(" in stderr, stderr
    assert not out.exists() and not report.exists()
    assert list(tmp_path.iterdir()) == []  # no temporary either
