# dba.plot draws a solve's report: a PNG of the expected size from the
# Ladybug solve's report (given as a dict and as a JSON file), and a clear
# error for a report without history.
import json
import struct

import pytest

from dba import plot


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    return struct.unpack(">II", head[16:24])


def test_plots_a_report_dict_and_file(ladybug_result, tmp_path):
    report = ladybug_result.summary.report
    plot.plot_report(report, tmp_path / "dict.png")
    assert png_size(tmp_path / "dict.png") == (1200, 800)
    path = tmp_path / "report.json"
    path.write_text(json.dumps(report))
    assert plot.main([str(path), "-o", str(tmp_path / "file.png")]) == 0
    assert png_size(tmp_path / "file.png") == (1200, 800)


def test_a_report_without_history_is_refused(ladybug_result, tmp_path):
    report = dict(ladybug_result.summary.report)
    report["history"] = []
    with pytest.raises(ValueError, match="no per-iteration history"):
        plot.plot_report(report, tmp_path / "x.png")
    path = tmp_path / "empty.json"
    path.write_text(json.dumps(report))
    assert plot.main([str(path), "-o", str(tmp_path / "y.png")]) == 1
    assert not (tmp_path / "y.png").exists()


def test_a_report_with_truth_gets_the_top_view(ladybug_result, tmp_path):
    report = dict(ladybug_result.summary.report)
    report["ground_truth"] = {"rms_to_noise_free_px": 0.5, "similarity_scale": 1.0,
                              "camera_centre_rms": 0.1, "point_rms": 0.2,
                              "cameras": {"true_x": [0, 1, 2], "true_y": [0, 1, 0],
                                          "centre_error": [0.1, 0.2, 0.05]}}
    plot.plot_report(report, tmp_path / "truth.png")
    assert png_size(tmp_path / "truth.png") == (1800, 800)


def test_a_covariance_file_gets_the_ellipse_map(tmp_path):
    from conftest import SHARED_DATA
    import dba
    result = dba.solve(SHARED_DATA / "bal" / "problem-16-22106-pre.txt.bz2", covariance=tmp_path / "c.csv",
                       fix_images=[3])
    cov = plot.read_covariance(tmp_path / "c.csv")
    assert len(cov["x"]) == 15 and cov["skipped"] == 1 and cov["datum"] == "inner"
    widths, heights, _ = plot._ellipses(cov)
    # The 95% ellipse's axes: 2 sqrt(5.99) times the horizontal block's
    # eigenvalues' roots, the larger first.
    i = 0
    w = 2 * 2.4477 * (max(__import__("numpy").linalg.eigvalsh(
        [[cov["c_xx"][i], cov["c_xy"][i]], [cov["c_xy"][i], cov["c_yy"][i]]]))) ** 0.5
    assert abs(widths[i] - w) < 1e-4 * w and heights[i] <= widths[i]
    plot.plot_report(result.summary.report, tmp_path / "cov.png", covariance=tmp_path / "c.csv")
    assert png_size(tmp_path / "cov.png") == (1800, 800)
    path = tmp_path / "report.json"
    path.write_text(json.dumps(result.summary.report))
    (tmp_path / "bad.csv").write_text("a,b\n1,2\n")
    assert plot.main([str(path), "-o", str(tmp_path / "bad.png"), "--covariance", str(tmp_path / "bad.csv")]) == 1
    assert not (tmp_path / "bad.png").exists()
