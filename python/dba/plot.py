"""Plots of a `dba solve --report` (or Result.summary.report): cost and RMS
against time and against LM iteration, the linear solver's iterations per LM
iteration (why each stopped), and the time per phase; for a generated
problem solved with --truth, also a top view of the camera-centre errors
over the survey (after the similarity alignment).

    python3 -m dba.plot REPORT.json -o FILE.png
    dba.plot.plot_report("report.json", "run.png")

Needs matplotlib (Debian: python3-matplotlib); drawn off screen (Agg).
"""

import argparse
import json
import sys


def _load(report):
    if isinstance(report, dict):
        return report
    with open(report) as f:
        return json.load(f)


def plot_report(report, output, title=None):
    """Draws `report` (a path to the JSON or its dict) into `output` (PNG)."""
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
    columns = 3 if cameras else 2
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

    fig.tight_layout()
    fig.savefig(output, dpi=100)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m dba.plot",
                                     description="Plots a dba solve --report JSON.")
    parser.add_argument("report", help="the JSON written by dba solve --report")
    parser.add_argument("-o", "--output", required=True, help="the PNG to write")
    args = parser.parse_args(argv)
    try:
        plot_report(args.report, args.output)
    except (OSError, ValueError, KeyError) as e:
        print(f"dba.plot: {args.report}: {e}", file=sys.stderr)
        return 1
    print(args.output)
    return 0


if __name__ == "__main__":
    sys.exit(main())
