"""The best any outlier rejection can do on a generated survey: the true
mismatches dropped and nothing else (the oracle), solved with dba's default
options, its camera centres' RMS after a similarity against the truth, beside
the outlier-free survey's and --reject-outliers' (bench/README.md,
"Rejection against the oracle"). The surveys are bench/rejection.sh's (the
same files: run it first with --out DIR).

  PYTHONPATH=build/python python3 bench/rejection_oracle.py DIR IMAGES SEED FRACTION [OPTION=VALUE...]

OPTION=VALUE: solve options for the oracle, as given to rejection.sh after
"--" (e.g. linear_solver=sparse function_tolerance=1e-10 for the exact optima).

Prints one Markdown row: seed, fraction, mismatches, oracle RMS, oracle /
outlier-free, rejection / outlier-free, rejection / oracle.
"""
import json
import os
import sys

import numpy as np

import dba

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "lib"))
from gauge_check import centres, onto  # noqa: E402


def rms_after_similarity(a, b):
    """RMS of |s R a + t - b| for the similarity that best maps a onto b
    (Umeyama), as dba's --truth reports camera_centre_rms."""
    return float(np.sqrt(((onto(a, b) - b) ** 2).sum(1).mean()))


def main(work, images, seed, fraction, options):
    prefix = f"{work}/s{images}.{seed}"
    p = dba.read_problem(f"{prefix}.{fraction}.dba")
    truth = dba.read_problem(f"{prefix}.{fraction}.truth.dba")
    assert len(p.observations) == len(truth.observations)
    # The generator's mismatches: over 25 px from their noise-free pixel
    # (synthetic/uav_generator.h, IsTrueOutlier).
    far = np.linalg.norm(p.observations - truth.observations, axis=1) > 25.0
    keep = ~far
    # Points left with fewer than two observations go, as rejection drops them.
    seen = np.bincount(p.point_indices[keep], minlength=len(p.points))
    kept_point = seen >= 2
    keep &= kept_point[p.point_indices]
    renumber = np.cumsum(kept_point) - 1
    r = dba.solve_arrays(p.cameras, p.points[kept_point], p.observations[keep], p.camera_indices[keep],
                         renumber[p.point_indices[keep]], camera_model=p.camera_model,
                         intrinsics=p.intrinsics, camera_intrinsics=p.camera_intrinsics,
                         fixed_cameras=p.fixed_cameras, fixed_intrinsics=p.fixed_intrinsics,
                         lens_models=p.lens_models, threads=2, **options)
    oracle = rms_after_similarity(centres(r.cameras), centres(truth.cameras))
    clean = json.load(open(f"{prefix}.0.json"))["ground_truth"]["camera_centre_rms"]
    rejected = json.load(open(f"{prefix}.{fraction}.json"))["ground_truth"]["camera_centre_rms"]
    print(f"| {seed} | {float(fraction):.0%} | {far.sum():,} | {oracle:.4f} | {oracle / clean:.3f}x | "
          f"{rejected / clean:.3f}x | {rejected / oracle:.3f}x |")


def option(text):
    name, value = text.split("=", 1)
    try:
        return name, float(value) if any(c in value for c in ".e") else int(value)
    except ValueError:
        return name, value


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], dict(map(option, sys.argv[5:])))
