"""The predicted pose covariances (dba solve --covariance) against the spread
of solutions over noise realizations (bench/README.md, "Covariance: the
spread of solutions"). A generated survey's truth is observed again and again
with fresh Gaussian pixel noise of sigma 1 px (the geometry fixed), each
realization solved from the truth with dba's defaults; the solved centres are
mapped onto the true ones by the least-squares similarity (Umeyama: to first
order the inner constraints over the centres, --covariance's datum), and each
camera's empirical 3x3 centre covariance over the realizations is compared
with the one --covariance predicts for a pixel sigma of 1. Also: sigma0 (the
a-posteriori pixel noise) against the true 1 px.

  PYTHONPATH=build/python python3 bench/covariance_calibration.py DBA WORKDIR [IMAGES [REALIZATIONS [SEED]]]

Prints the median and quartiles of the per-camera trace ratio
(empirical / predicted), the median of the largest eigenvalue's ratio, and
sigma0's median over the realizations.
"""
import csv
import json
import os
import subprocess
import sys

import numpy as np

import dba

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "lib"))
from gauge_check import centres, onto  # noqa: E402  (Umeyama)


def predicted(dba_bin, work, images, seed):
    survey, truth = f"{work}/cal{images}.{seed}.dba", f"{work}/cal{images}.{seed}.truth.dba"
    subprocess.run([dba_bin, "generate", "--model", "photo", "--images", str(images), "--seed", str(seed),
                    survey, "--truth", truth], check=True, stdout=subprocess.DEVNULL)
    csv_path, report = f"{work}/cal{images}.{seed}.csv", f"{work}/cal{images}.{seed}.json"
    subprocess.run([dba_bin, "solve", survey, "-q", "--covariance", csv_path, "--covariance-scale", "unit",
                    "--report", report], check=True, stdout=subprocess.DEVNULL)
    blocks = []
    with open(csv_path, newline="") as f:
        for row in list(csv.reader(f))[1:]:
            c = [float(v) for v in row[5:11]]
            blocks.append(np.array([[c[0], c[1], c[2]], [c[1], c[3], c[4]], [c[2], c[4], c[5]]]))
    return truth, blocks, json.load(open(report))["covariance"]["sigma0_px"]


def main(dba_bin, work, images=100, realizations=100, seed=7):
    images, realizations, seed = int(images), int(realizations), int(seed)
    truth_path, blocks, sigma0_file = predicted(dba_bin, work, images, seed)
    t = dba.read_problem(truth_path)
    true_centres = centres(t.cameras)
    rng = np.random.default_rng(seed)
    deviations, sigma0 = [], []
    for _ in range(realizations):
        obs = t.observations + rng.normal(0.0, 1.0, t.observations.shape)
        r = dba.solve_arrays(t.cameras, t.points, obs, t.camera_indices, t.point_indices,
                             camera_model=t.camera_model, intrinsics=t.intrinsics,
                             camera_intrinsics=t.camera_intrinsics, fixed_cameras=t.fixed_cameras,
                             fixed_intrinsics=t.fixed_intrinsics, lens_models=t.lens_models, threads=2)
        deviations.append(onto(centres(r.cameras), true_centres) - true_centres)
        free_intrinsics = int((~np.asarray(t.fixed_intrinsics, bool)).sum())
        redundancy = 2 * len(obs) - (6 * len(t.cameras) + free_intrinsics + 3 * len(t.points)) + 7
        sigma0.append(np.sqrt(2 * r.summary.final_cost / redundancy))
    d = np.array(deviations)  # realizations x images x 3
    trace, largest = [], []
    for i, P in enumerate(blocks):
        E = d[:, i, :].T @ d[:, i, :] / realizations  # the truth is the mean
        trace.append(np.trace(E) / np.trace(P))
        largest.append(np.linalg.eigvalsh(E)[-1] / np.linalg.eigvalsh(P)[-1])
    q = np.percentile(trace, [25, 50, 75])
    print(f"{images} images, {realizations} realizations (seed {seed}): trace ratio empirical/predicted "
          f"median {q[1]:.3f} (quartiles {q[0]:.3f}-{q[2]:.3f}, range {min(trace):.3f}-{max(trace):.3f}); "
          f"largest eigenvalue ratio median {np.median(largest):.3f}; sigma0 median "
          f"{np.median(sigma0):.4f} px over the realizations, {sigma0_file:.4f} px in the survey's file")


if __name__ == "__main__":
    main(*sys.argv[1:])
