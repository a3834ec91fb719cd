"""The plot of a kiln study, from its JSON: plot_study.py order|sweep|wp|recommend study.json study.png
- order: log-log error against dt, one line per integrator, dashed nominal slopes;
- sweep: each quantity against dt (log x), unstable steps marked, the estimated limit dashed;
- wp: work-precision, error (x) against minimum wall time (y), log-log, one line per integrator.
What a figure leaves out (an integrator without a fitted order, levels whose error is 0, NaN or
failed) is said in notes under it, which the PNG's Description also holds. Any value of the JSON
may be null (a figure a run could not measure): none is formatted without a look."""
import json
import math
import os
import sys

import kiln_figure  # how a figure is written and how the script ends, shared with plot_case.py


def number(value, spec):
    """`value` formatted by `spec`, or "none" for a null (NaN is written null in the JSON)."""
    return "none" if value is None else format(value, spec)


def plot_order(study, ax):
    if "ensemble" in study:
        return plot_order_ensemble(study, ax)
    notes = []
    for entry in study["integrators"]:
        levels = list(zip(entry.get("dt") or [], entry.get("error") or []))
        points = [(d, e) for d, e in levels if d and e is not None and e > 0]  # log axes: 0 and NaN (null) are off them
        fitted = entry.get("fitted_order")
        if fitted is None:
            # An error of 0, NaN or a failed level leaves no order to fit: the verdict says why.
            notes.append(f"{entry['name']}: no fitted order: {entry.get('verdict') or 'no verdict'}")
        left_out = [d for d, e in levels if (d, e) not in points]
        if left_out and points:
            notes.append(f"{entry['name']}: not drawn at dt = " + ", ".join(number(d, ".3g") for d in left_out) +
                         " (error 0, NaN or failed)")
        if not points:
            notes.append(f"{entry['name']}: nothing to draw (every level's error is 0, NaN or failed)")
            continue
        xs, ys = zip(*points)
        label = f"{entry['name']} " + (f"(fitted {fitted:.2f})" if fitted is not None else "(no fitted order)")
        line, = ax.loglog(xs, ys, "o-", label=label)
        p = entry.get("nominal_order")
        if p is not None:
            ax.loglog(xs, [ys[-1] * (x / xs[-1]) ** p for x in xs], "--", color=line.get_color(), alpha=0.5, lw=1)
    ax.set_xlabel("dt (s)")
    ax.set_ylabel(("difference of successive levels" if study["reference"] == "richardson" else "error")
                  + f" of {study['quantity']} (max abs)")
    ax.set_title(f"{study['scene']}: {study['quantity']} at t = {number(study['t_end'], 'g')} s, reference "
                 f"{study['reference']}\n(dashed: nominal slopes)", fontsize=10)
    return notes


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
    ax.set_title(f"{study['scene']}: {study['quantity']} at t = {number(study['t_end'], 'g')} s, reference ensemble",
                 fontsize=10)
    return []


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
    return []


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
    return []


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
    if r and r.get("error") is not None and r.get("seconds_per_run"):
        ax.loglog([max(r["error"], 1e-300)], [r["seconds_per_run"]], "o", ms=14, mfc="none", color="red",
                  label=f"recommended: {r['integrator']} at {number(r.get('dt'), '.3g')} s")
    ax.set_xlabel(f"error of {study['quantity']} (reference {study['reference']})")
    ax.set_ylabel("wall seconds per run")
    ax.set_title(f"{study['scene']}: kiln recommend", fontsize=10)
    return []


PLOTS = {"order": plot_order, "sweep": plot_sweep, "wp": plot_wp, "recommend": plot_recommend}


def main(kind, source, target):
    try:
        with open(source) as f:
            study = json.load(f)
    except (OSError, ValueError) as e:
        kiln_figure.fail(kiln_figure.BAD_INPUT, f"cannot read {source}: {e}")
    plt = kiln_figure.pyplot(target)
    fig, ax = plt.subplots(figsize=(7, 5))
    notes = PLOTS[kind](study, ax) or []
    ax.grid(True, which="both", alpha=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8)
    # What the axes leave out, under them.
    below = 0.025 * len(notes) + (0.01 if notes else 0)
    for k, note in enumerate(notes):
        fig.text(0.01, 0.01 + 0.025 * (len(notes) - 1 - k), note if len(note) <= 150 else note[:147] + "...",
                 fontsize=7, va="bottom")
    fig.tight_layout(rect=(0, below, 1, 1))
    return kiln_figure.save(fig, target, dpi=110, metadata={"Description": "notes: " + "; ".join(notes)})


if __name__ == "__main__":
    if len(sys.argv) != 4 or sys.argv[1] not in PLOTS:
        kiln_figure.fail(kiln_figure.BAD_INPUT, "usage: plot_study.py order|sweep|wp|recommend study.json study.png")
    kiln_figure.run(lambda: main(*sys.argv[1:]), sys.argv[3])
