"""Plots of a `dba solve --report` (or Result.summary.report): cost and RMS
against time and against LM iteration, the linear solver's iterations per LM
iteration (why each stopped), and the time per phase; for a generated
problem solved with --truth, also a top view of the camera-centre errors
over the survey (after the similarity alignment); with the --covariance
file, the camera map with each centre's horizontal error ellipse (95%,
magnified, coloured by sigma_z) as photogrammetric quality reports draw it,
and the sigmas' distribution.

    python3 -m dba.plot REPORT.json -o FILE.png [--covariance FILE.csv]
    dba.plot.plot_report("report.json", "run.png", covariance="cov.csv")

Needs matplotlib (Debian: python3-matplotlib); drawn off screen (Agg).
"""

import argparse
import csv
import json
import math
import sys

# The 95% ellipse of a 2D normal: sqrt of chi-square(2)'s 0.95 quantile.
_ELLIPSE_95 = math.sqrt(5.991464547107979)


def _load(report):
    if isinstance(report, dict):
        return report
    with open(report) as f:
        return json.load(f)


def read_covariance(path):
    """The --covariance file's images with figures: x, y, the horizontal
    2x2 (c_xx, c_xy, c_yy) and sigma_z per image; held and undetermined
    images left out (counted in `skipped`)."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows or "c_xx" not in rows[0] or "x" not in rows[0]:
        raise ValueError(f"{path}: not a dba solve --covariance file (no c_xx, x columns)")
    out = {"x": [], "y": [], "c_xx": [], "c_xy": [], "c_yy": [], "sigma_z": [], "skipped": 0,
           "datum": rows[0]["datum"]}
    for row in rows:
        if row["c_xx"] == "":
            out["skipped"] += 1
            continue
        out["datum"] = row["datum"]
        for key in ("x", "y", "c_xx", "c_xy", "c_yy", "sigma_z"):
            out[key].append(float(row[key]))
    if not out["x"]:
        raise ValueError(f"{path}: no image with a covariance")
    return out


def _ellipses(cov):
    """Each image's 95% ellipse: full widths, heights and angles (degrees)."""
    widths, heights, angles = [], [], []
    for a, b, d in zip(cov["c_xx"], cov["c_xy"], cov["c_yy"]):
        mean, half = (a + d) / 2, math.hypot((a - d) / 2, b)
        major, minor = math.sqrt(max(mean + half, 0.0)), math.sqrt(max(mean - half, 0.0))
        widths.append(2 * _ELLIPSE_95 * major)
        heights.append(2 * _ELLIPSE_95 * minor)
        angles.append(math.degrees(0.5 * math.atan2(2 * b, a - d)))
    return widths, heights, angles


def _magnification(cov, widths):
    """A round factor (1, 2 or 5 times a power of ten) that makes the median
    ellipse at most about the images' spacing."""
    n = len(cov["x"])
    area = (max(cov["x"]) - min(cov["x"])) * (max(cov["y"]) - min(cov["y"]))
    spacing = math.sqrt(area / n) if area > 0 else 1.0
    median = sorted(widths)[n // 2]
    if median <= 0:
        return 1.0
    want = 0.9 * spacing / median
    power = 10 ** math.floor(math.log10(want))
    return max(f * power for f in (1, 2, 5) if f * power <= want)


def _plot_covariance(fig, top, bottom, cov):
    from matplotlib.collections import EllipseCollection
    widths, heights, angles = _ellipses(cov)
    k = _magnification(cov, widths)
    offsets = list(zip(cov["x"], cov["y"]))
    ellipses = EllipseCollection([k * w for w in widths], [k * h for h in heights], angles, units="xy",
                                 offsets=offsets, offset_transform=top.transData, cmap="plasma")
    ellipses.set_array(cov["sigma_z"])
    top.add_collection(ellipses)
    if len(offsets) <= 200:
        top.scatter(cov["x"], cov["y"], s=1, color="k")
    top.autoscale_view()
    top.set_aspect("equal", adjustable="datalim")
    fig.colorbar(ellipses, ax=top, label="sigma_z")
    top.set_xlabel("x")
    top.set_ylabel("y")
    skipped = f', {cov["skipped"]} held or undetermined' if cov["skipped"] else ""
    top.set_title(f'camera centres ({cov["datum"]}): 95% error ellipses x{k:g}{skipped}')
    sigma_x = [math.sqrt(v) for v in cov["c_xx"]]
    sigma_y = [math.sqrt(v) for v in cov["c_yy"]]
    bottom.hist([sigma_x, sigma_y, cov["sigma_z"]], bins=40, label=["sigma_x", "sigma_y", "sigma_z"])
    bottom.legend()
    bottom.set_xlabel("camera-centre sigma")
    bottom.set_ylabel("images")
    bottom.set_title(f'{len(sigma_x)} images: median sigma x {sorted(sigma_x)[len(sigma_x) // 2]:.3g}, '
                     f'z {sorted(cov["sigma_z"])[len(sigma_x) // 2]:.3g}')


def plot_report(report, output, title=None, covariance=None):
    """Draws `report` (a path to the JSON or its dict) into `output` (PNG);
    `covariance`: the path of its --covariance file, for the ellipse map."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    r = _load(report)
    history = r.get("history", [])
    if not history:
        raise ValueError("the report has no per-iteration history")
    seconds = r["seconds"]
    # Time at the end of each LM iteration, from the start of the program
    # (reports before the start-up and the read were counted begin later).
    start = sum(seconds.get(k, 0.0) for k in ("startup", "read", "load", "distribution", "setup"))
    times, t = [], start
    for it in history:
        t += it["seconds"]
        times.append(t)
    # Cost after each iteration: the candidate's when accepted, else unchanged.
    costs = [it["candidate_cost"] if it.get("accepted") else it["cost"] for it in history]
    iterations = [it["iteration"] for it in history]
    rms = [it["rms_px"] for it in history]

    cameras = r.get("ground_truth", {}).get("cameras")
    cov = read_covariance(covariance) if covariance is not None else None
    columns = 2 + (1 if cameras else 0) + (1 if cov else 0)
    fig, axes = plt.subplots(2, columns, figsize=(6 * columns, 8))
    fig.suptitle(title or f'{r.get("input", "")}: {r.get("num_images", r.get("num_cameras"))} images, '
                 f'{r.get("num_points")} points, {r.get("num_observations")} observations, '
                 f'{r.get("threads")} threads x {r.get("ranks")} ranks')

    ax = axes[0][0]
    ax.semilogy([start] + times, [r["initial_cost"]] + costs, "o-", color="C0", ms=3)
    ax.set_xlabel("time since start (s)")
    ax.set_ylabel("cost", color="C0")
    ax.set_title(f'cost against time: {r["final_cost"]:.6e} after {seconds["total"]:.2f} s')
    ax2 = ax.twinx()
    ax2.plot([start] + times[:-1], rms, "s--", color="C1", ms=3)
    ax2.set_ylabel("RMS at the start of the iteration (px)", color="C1")

    # How far above the final cost each iteration ended (relative): the
    # convergence the cost axis cannot show.
    ax = axes[0][1]
    final = r["final_cost"]
    gap = [max((c - final) / final, 1e-16) for c in [r["initial_cost"]] + costs]
    ax.semilogy([0] + iterations, gap, "o-", color="C0", ms=3)
    rejected = [i for i, it in zip(iterations, history) if not it.get("accepted")]
    if rejected:
        ax.semilogy(rejected, [gap[i] for i in rejected], "x", color="C3", label="rejected step")
        ax.legend()
    ax.axhline(1e-3, color="C7", lw=0.8, ls=":")
    ax.set_xlabel("LM iteration")
    ax.set_ylabel("(cost - final cost) / final cost")
    ax.set_title(f'convergence ({r.get("termination")}; dotted: 0.1%)')

    ax = axes[1][0]
    linear = [it.get("linear_iterations", 0) for it in history]
    stops = [it.get("linear_stop", "") for it in history]
    colours = ["C3" if s == "iteration_limit" else "C2" if s == "quadratic_model" else "C7"
               for s in stops]
    ax.bar(iterations, linear, color=colours)
    solver = r.get("linear_solver", {}).get("type", "?")
    ax.set_xlabel("LM iteration")
    ax.set_ylabel("linear solver iterations")
    ax.set_title(f'{solver}: {sum(linear)} linear iterations\n'
                 f'(green: model test, red: cap, grey: factorized or other)')

    ax = axes[1][1]
    phases = [("startup", "start-up"), ("read", "read"), ("load", "checks"), ("setup", "setup"),
              ("rcs_formation", "RCS formation"), ("linear_solve", "linear solve"),
              ("back_substitution", "back-substitution"), ("analysis", "analysis"), ("write", "write"),
              ("other", "other")]
    values = [seconds.get(k, 0.0) for k, _ in phases]
    ax.barh([name for _, name in phases], values, color="C4")
    for y, v in enumerate(values):
        ax.text(v, y, f" {v:.2f} s ({100 * v / max(seconds['total'], 1e-12):.0f}%)", va="center")
    ax.set_xlabel("seconds")
    ax.set_title(f'time per phase ({seconds["total"]:.2f} s in all)')
    ax.set_xlim(0, max(values) * 1.35 if max(values) > 0 else 1)

    if cameras:
        gt = r["ground_truth"]
        ax = axes[0][2]
        errors = sorted(cameras["centre_error"])
        vmax = errors[int(0.98 * (len(errors) - 1))] if errors else 1.0  # a few far ones aside
        points = ax.scatter(cameras["true_x"], cameras["true_y"], c=cameras["centre_error"],
                            s=max(0.2, min(12.0, 4000.0 / max(len(cameras["true_x"]), 1))),
                            cmap="viridis", vmin=0.0, vmax=vmax)
        fig.colorbar(points, ax=ax, label="camera-centre error after alignment (98th percentile up)")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("x (true)")
        ax.set_ylabel("y (true)")
        ax.set_title(f'camera centres: RMS {gt["camera_centre_rms"]:.4g}, scale '
                     f'{gt["similarity_scale"]:.6f}')
        ax = axes[1][2]
        ax.hist(cameras["centre_error"], bins=50, color="C5")
        ax.set_xlabel("camera-centre error")
        ax.set_ylabel("cameras")
        ax.set_title(f'RMS to noise-free observations {gt["rms_to_noise_free_px"]:.4f} px, '
                     f'points {gt["point_rms"]:.4g}')

    if cov:
        _plot_covariance(fig, axes[0][columns - 1], axes[1][columns - 1], cov)

    fig.tight_layout()
    fig.savefig(output, dpi=100)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m dba.plot",
                                     description="Plots a dba solve --report JSON.")
    parser.add_argument("report", help="the JSON written by dba solve --report")
    parser.add_argument("-o", "--output", required=True, help="the PNG to write")
    parser.add_argument("--covariance", help="the solve's --covariance file: the error-ellipse map")
    args = parser.parse_args(argv)
    try:
        plot_report(args.report, args.output, covariance=args.covariance)
    except (OSError, ValueError, KeyError) as e:
        print(f"dba.plot: {args.report}: {e}", file=sys.stderr)
        return 1
    print(args.output)
    return 0


if __name__ == "__main__":
    sys.exit(main())
