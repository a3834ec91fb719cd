"""The plot of a kiln study, from its JSON: plot_study.py order|sweep|wp study.json study.png
- order: log-log error against dt, one line per integrator, dashed nominal slopes;
- sweep: each quantity against dt (log x), unstable steps marked, the estimated limit dashed;
- wp: work-precision, error (x) against minimum wall time (y), log-log, one line per integrator."""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def plot_order(study, ax):
    for entry in study["integrators"]:
        points = [(d, e) for d, e in zip(entry.get("dt", []), entry.get("error", [])) if e and e > 0]
        if not points:
            continue
        xs, ys = zip(*points)
        line, = ax.loglog(xs, ys, "o-", label=f"{entry['name']} (fitted {entry['fitted_order']:.2f})")
        p = entry["nominal_order"]
        ax.loglog(xs, [ys[-1] * (x / xs[-1]) ** p for x in xs], "--", color=line.get_color(), alpha=0.5, lw=1)
    ax.set_xlabel("dt (s)")
    ax.set_ylabel(("difference of successive levels" if study["reference"] == "richardson" else "error")
                  + f" of {study['quantity']} (max abs)")
    ax.set_title(f"{study['scene']}: {study['quantity']} at t = {study['t_end']:g} s, reference {study['reference']}"
                 "\n(dashed: nominal slopes)", fontsize=10)


def plot_sweep(study, ax):
    dts = study["dt"]
    for q, values in study["values"].items():
        pts = [(d, v) for d, v in zip(dts, values) if v is not None]
        if pts:
            xs, ys = zip(*pts)
            ax.semilogx(xs, ys, "o-", label=q)
    bad = [d for d, ok in zip(dts, study["stable"]) if not ok]
    for d in bad:
        ax.axvline(d, color="red", alpha=0.3)
    limit = study["estimate"]["dt_limit"]
    if limit and math.isfinite(limit):
        ax.axvline(limit, color="black", ls="--", label="estimated stability limit")
    if study.get("largest_stable_dt"):
        ax.axvline(study["largest_stable_dt"], color="green", ls=":", label="largest stable dt found")
    ax.set_xlabel("dt (s)")
    ax.set_ylabel("value (fields: difference from the smallest dt)")
    ax.set_title(f"{study['scene']} with {study['integrator']}: time-step sweep (red: unstable)", fontsize=10)


def plot_wp(study, ax):
    for entry in study["integrators"]:
        noise = entry.get("noise", [0] * len(entry["error"]))
        pts = [(e, s, n) for e, s, n in zip(entry["error"], entry["wall_seconds"], noise) if e and s]
        if pts:
            xs, ys, ns = zip(*sorted(pts))
            line, = ax.loglog(xs, ys, "o-", label=entry["name"])
            if "noise" in entry:  # ensemble: the noise floor of each error as a horizontal bar
                ax.errorbar(xs, ys, xerr=[[min(n, 0.999 * x) for x, n in zip(xs, ns)], ns], fmt="none",
                            color=line.get_color(), alpha=0.5)
    ax.set_xlabel(f"error of {study['quantity']} (max abs, reference {study['reference']})"
                  + (f"; bars: noise of {study['seeds']} fills" if "seeds" in study else ""))
    ax.set_ylabel(f"wall time (s, minimum of {study['repeats']} runs)")
    ax.set_title(f"{study['scene']}: work-precision ({study['setting']} varied)", fontsize=10)


def main(kind, source, target):
    with open(source) as f:
        study = json.load(f)
    fig, ax = plt.subplots(figsize=(7, 5))
    {"order": plot_order, "sweep": plot_sweep, "wp": plot_wp}[kind](study, ax)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    tmp = target + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, target)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3])
