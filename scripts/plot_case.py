"""The case quantities of a kiln run over time: plot_case.py DIR writes DIR/plots.png, one figure of
panels, from DIR/summary.json and DIR/result.h5 (kiln plot DIR runs it with Debian's python3).

Generic, so that a case that reports something new appears without a change here:
- every object of summary.json (at any depth) holding a `time` array: one panel per other array of
  the same length (mixing_history: lacey_index, temperature_std; energy.history: balance_error;
  the histories of cases to come);
- every object within it holding two or more arrays of one length but no time: a profile, the
  others against the first of eta, height, y, x, radius, position, depth (else the first in order);
- from result.h5 (h5py): the temperatures per frame (mean, spread, extremes) in thermal runs, and
  each wall's torque and power per frame in runs with walls;
- the energy ledger at the end (summary.json `energy`; result.h5 does not hold it per frame).
"""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ABSCISSAE = ("eta", "height", "y", "x", "radius", "position", "depth")


def numbers(value):
    """A list of real numbers (None for a value a case could not measure), or None."""
    if not isinstance(value, list) or not value:
        return None
    if all(v is None or (isinstance(v, (int, float)) and not isinstance(v, bool)) for v in value):
        return [math.nan if v is None else float(v) for v in value]
    return None


def series_of_summary(summary):
    """Panels from the arrays of summary.json: (title, x label, x, [(label, y)])."""
    panels = []

    def walk(obj, path):
        if isinstance(obj, dict):
            arrays = {k: numbers(v) for k, v in obj.items()}
            arrays = {k: v for k, v in arrays.items() if v is not None}
            if "time" in arrays:
                t = arrays["time"]
                for key, values in arrays.items():
                    if key != "time" and len(values) == len(t):
                        panels.append((f"{path}: {key}", "time (s)", t, [(key, values)]))
            elif path:  # not the summary's own arrays (bounce_heights beside contact_durations)
                lengths = {}
                for key, values in arrays.items():
                    lengths.setdefault(len(values), []).append(key)
                for keys in lengths.values():
                    if len(keys) >= 2 and len(arrays[keys[0]]) >= 2:
                        x = next((k for k in ABSCISSAE if k in keys), keys[0])
                        for key in keys:
                            if key != x:
                                panels.append((f"{path}: {key} against {x}", x, arrays[x],
                                               [(key, arrays[key])]))
            for key, value in obj.items():
                walk(value, f"{path}.{key}" if path else key)

    walk(summary, "")
    return panels


def series_of_result(path):
    """Panels from result.h5: temperatures, wall torques and powers per frame."""
    try:
        import h5py
    except ImportError:
        print(f"warning: {path} not plotted: needs python3-h5py (apt-get install python3-h5py)", file=sys.stderr)
        return []
    panels = []
    with h5py.File(path, "r") as f:
        t = f["time"][:]
        if "temperature" in f and len(t) > 0:
            temp = f["temperature"][:]
            mean, spread = temp.mean(axis=1), temp.std(axis=1)
            panels.append(("temperatures (result.h5)", "time (s)", t,
                           [("mean", mean), ("mean - spread", mean - spread), ("mean + spread", mean + spread),
                            ("min", temp.min(axis=1)), ("max", temp.max(axis=1))], "temperature (C)"))
        names = [n.decode() if isinstance(n, bytes) else str(n) for n in f.attrs.get("wall_names", [])]
        for dataset in ("wall_torque", "wall_power"):
            if dataset in f and len(t) > 0:
                values = f[dataset][:]
                units = f[dataset].attrs.get("units", b"")
                units = units.decode() if isinstance(units, bytes) else str(units)
                walls = [(names[w] if w < len(names) else f"wall {w}", values[:, w]) for w in range(values.shape[1])]
                panels.append((f"{dataset} per frame (result.h5)", "time (s)", t, walls, f"{dataset} ({units})"))
    return panels


def energy_ledger(summary):
    """The final energy ledger: its named terms in J (not the history, which has panels of its own)."""
    energy = summary.get("energy", {})
    return [(k, float(v)) for k, v in energy.items()
            if isinstance(v, (int, float)) and not isinstance(v, bool)]


def draw(panels, ledger, summary, target):
    count = len(panels) + (1 if ledger else 0)
    columns = 2 if count > 1 else 1
    rows = max(1, math.ceil(count / columns))
    fig, axes = plt.subplots(rows, columns, figsize=(7 * columns, 3.4 * rows), squeeze=False)
    flat = [ax for row in axes for ax in row]
    for ax, panel in zip(flat, panels):
        title, xlabel, x, lines = panel[:4]
        for label, y in lines:
            style = "--" if label.startswith("mean ") else "-"
            ax.plot(x, y, style, marker="o" if len(x) < 30 else None, ms=3, label=label)
        ax.set_title(title, fontsize=10)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(panel[4] if len(panel) > 4 else lines[0][0])
        if len(lines) > 1:
            ax.legend(fontsize=8)
        ax.grid(True, alpha=0.3)
    if ledger:
        ax = flat[len(panels)]
        names, values = zip(*ledger)
        ax.barh(names, values, color=["tab:red" if v < 0 else "tab:blue" for v in values])
        # Each bar's value written beside it: mechanical terms next to a heat content are too short
        # to read off the axis (a log axis would hide the signs).
        for k, v in enumerate(values):
            ax.annotate(f"{v:.3g}", (v, k), fontsize=7, va="center")
        ax.set_title("energy ledger at the end (summary.json; J)", fontsize=10)
        ax.grid(True, axis="x", alpha=0.3)
    for ax in flat[count:]:
        ax.axis("off")
    fig.suptitle(f"{summary.get('scene', '?')}: {summary.get('integrator', '?')}, t = 0 to "
                 f"{summary.get('t_end', math.nan):g} s", fontsize=12)
    fig.tight_layout(rect=(0, 0, 1, 0.97))  # room for the title above the panels
    titles = [panel[0] for panel in panels] + (["energy ledger"] if ledger else [])
    tmp = target + ".tmp"
    # The panels' titles in the PNG's text (what a reader or a test can find without looking).
    try:
        fig.savefig(tmp, dpi=100, format="png", metadata={"Description": "panels: " + "; ".join(titles)})
        os.replace(tmp, target)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise


def main(directory):
    summary_path = os.path.join(directory, "summary.json")
    if not os.path.exists(summary_path):
        print(f"error: {summary_path} not found: give the output directory of a run", file=sys.stderr)
        return 2
    with open(summary_path) as f:
        summary = json.load(f)
    panels = series_of_summary(summary)
    result = os.path.join(directory, "result.h5")
    if os.path.exists(result):
        panels += series_of_result(result)
    draw(panels, energy_ledger(summary), summary, os.path.join(directory, "plots.png"))
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print("usage: plot_case.py DIR", file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
