"""order.png from order.json: log-log error against dt, one line per integrator, with dashed
reference slopes of each nominal order. Usage: plot_order.py order.json order.png"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(source, target):
    with open(source) as f:
        study = json.load(f)
    fig, ax = plt.subplots(figsize=(7, 5))
    for entry in study["integrators"]:
        if "error" not in entry:
            continue
        dt, err = entry["dt"], entry["error"]
        points = [(d, e) for d, e in zip(dt, err) if e > 0]
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
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    tmp = target + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, target)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
