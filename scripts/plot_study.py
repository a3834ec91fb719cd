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
    if "ensemble" in study:
        return plot_order_ensemble(study, ax)
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


def plot_order_ensemble(study, ax):
    # |bias| of each level's ensemble mean with its interval where detected; an open v at the
    # interval's far end (an upper bound) where not.
    for entry in study["integrators"]:
        if "statistics" not in entry:
            continue
        fitted = entry.get("fitted_order")
        label = entry["name"] + (f" (fitted {fitted:.2f})" if fitted is not None else " (not resolved)")
        color = None
        for dt, st in zip(entry["dt"], entry["statistics"]):
            lo, hi = st["bias"]["interval"]
            if lo is None:
                continue
            if lo > 0 or hi < 0:
                x = abs(st["bias"]["estimate"])
                near, far = min(abs(lo), abs(hi)), max(abs(lo), abs(hi))
                art = ax.errorbar([dt], [x], yerr=[[x - near], [far - x]], fmt="o", color=color,
                                  label=None if color else label)
                color = art.lines[0].get_color()
            else:
                art, = ax.plot([dt], [max(abs(lo), abs(hi))], "v", mfc="none", color=color,
                               label=None if color else label)
                color = art.get_color()
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("dt (s)")
    ax.set_ylabel(f"|bias| of mean {study['quantity']} ({study['ensemble']['members']} members; v: undetected, bound)")
    ax.set_title(f"{study['scene']}: {study['quantity']} at t = {study['t_end']:g} s, reference ensemble", fontsize=10)


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
    ensemble = study.get("ensemble")
    for entry in study["integrators"]:
        if ensemble:
            # Ensembles: a bias the test detects at its |estimate| with its interval; one it cannot
            # detect as an open marker at the interval's far end, an upper bound of the error.
            color = None
            for s, st in zip(entry["wall_seconds"], entry["statistics"]):
                if not st or not s or st["bias"]["interval"][0] is None:
                    continue
                b = st["bias"]
                lo, hi = b["interval"]
                if b["verdict"] == "biased":
                    x = abs(b["estimate"])
                    near, far = min(abs(lo), abs(hi)), max(abs(lo), abs(hi))
                    line = ax.errorbar([x], [s], xerr=[[x - near], [far - x]], fmt="o", color=color,
                                       label=None if color else entry["name"])
                else:
                    line = ax.plot([max(abs(lo), abs(hi))], [s], "<", mfc="none", color=color,
                                   label=None if color else entry["name"])
                color = (line[0] if isinstance(line, list) else line.lines[0]).get_color()
            ax.set_xscale("log")
            ax.set_yscale("log")
            continue
        pts = [(e, s) for e, s in zip(entry["error"], entry["wall_seconds"]) if e and s]
        if pts:
            xs, ys = zip(*sorted(pts))
            ax.loglog(xs, ys, "o-", label=entry["name"])
    label = f"error of {study['quantity']} (max abs, reference {study['reference']})"
    if ensemble:
        label = (f"|bias| of mean {study['quantity']} ({ensemble['members']} members, "
                 f"{100 * ensemble['level']:g} % CI; <: undetected, bound)")
    ax.set_xlabel(label)
    ax.set_ylabel(f"wall time (s, minimum of {study['repeats']} runs)")
    ax.set_title(f"{study['scene']}: work-precision ({study['setting']} varied)", fontsize=10)


def plot_recommend(study, ax):
    # Cost against error of every probed step, the tolerance as a vertical line, the choice ringed.
    by = {}
    for p in study["probes"]:
        if p.get("error") is not None and p["seconds"] > 0:
            by.setdefault(p["integrator"], []).append((max(p["error"], 1e-300), p["seconds"]))
    for name, pts in by.items():
        xs, ys = zip(*pts)
        ax.loglog(xs, ys, "o-", label=name)
    ax.axvline(study["tolerance"], color="black", ls="--", label="tolerance")
    r = study.get("recommendation")
    if r:
        ax.loglog([max(r["error"], 1e-300)], [r["seconds_per_run"]], "o", ms=14, mfc="none", color="red",
                  label=f"recommended: {r['integrator']} at {r['dt']:.3g} s")
    ax.set_xlabel(f"error of {study['quantity']} (reference {study['reference']})")
    ax.set_ylabel("wall seconds per run")
    ax.set_title(f"{study['scene']}: kiln recommend", fontsize=10)


def main(kind, source, target):
    with open(source) as f:
        study = json.load(f)
    fig, ax = plt.subplots(figsize=(7, 5))
    {"order": plot_order, "sweep": plot_sweep, "wp": plot_wp, "recommend": plot_recommend}[kind](study, ax)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    tmp = target + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, target)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3])
