"""The case quantities of a kiln run over time: plot_case.py DIR [--keys JSON] writes DIR/plots.png,
one figure of panels, from DIR/summary.json and DIR/result.h5 (kiln plot DIR runs it with Debian's
python3, giving it the observer catalogue's keys, src/scene/observer_catalogue.h).

Generic, so that a case that reports something new appears without a change here:
- the keys the catalogue describes (path, kind, unit, meaning, against): each list with an
  abscissa (`against`: the time of a history, the eta of a profile) is a panel against it, labelled
  with its meaning and units; the numbers are listed, with their units, in a panel of the case's
  figures at the end;
- arrays no key describes: every object of summary.json (at any depth) holding a `time` array
  gives one panel per other array of the same length (energy.history: balance_error; the histories
  of cases to come); every object within it holding two or more arrays of one length but no time
  is a profile, the others against the first of eta, height, y, x, radius, position, depth (else
  the first in order);
- from result.h5 (h5py): the temperatures per frame (mean, spread, extremes) in thermal runs, and
  each wall's torque and power per frame in runs with walls;
- the energy ledger at the end (summary.json `energy`; result.h5 does not hold it per frame).
"""
import json
import math
import os
import sys

import kiln_figure  # how a figure is written and how the script ends, shared with plot_study.py

ABSCISSAE = ("eta", "height", "y", "x", "radius", "position", "depth")


def numbers(value):
    """A list of real numbers (None for a value a case could not measure), or None."""
    if not isinstance(value, list) or not value:
        return None
    if all(v is None or (isinstance(v, (int, float)) and not isinstance(v, bool)) for v in value):
        return [math.nan if v is None else float(v) for v in value]
    return None


def label(key, name):
    """An axis label: the key's name, with its units when the catalogue gives them."""
    return f"{name} ({key['unit']})" if key else name


def series_of_summary(summary, described):
    """Panels from the arrays of summary.json: (title, x label, x, [(label, y)], y label)."""
    panels = []

    def full(path, key):
        return f"{path}.{key}" if path else key

    def panel(path, key, x_name, arrays):
        where = full(path, key)
        title = f"{path}: {key}" if x_name == "time" else f"{path}: {key} against {x_name}"
        if where in described:
            title += "\n" + described[where]["meaning"]
        x_key = described.get(full(path, x_name))
        xlabel = label(x_key, x_name) if x_key else "time (s)" if x_name == "time" else x_name
        panels.append((title, xlabel, arrays[x_name], [(key, arrays[key])], label(described.get(where), key)))

    def walk(obj, path):
        if isinstance(obj, dict):
            arrays = {k: numbers(v) for k, v in obj.items()}
            arrays = {k: v for k, v in arrays.items() if v is not None}
            # Lists the catalogue describes, against their abscissa; the others found as below.
            undescribed = [k for k in arrays if full(path, k) not in described]
            for key, values in arrays.items():
                against = described.get(full(path, key), {}).get("against", "")
                x_name = against.rsplit(".", 1)[-1]
                if against and x_name in arrays and len(arrays[x_name]) == len(values):
                    panel(path, key, x_name, arrays)
            if "time" in arrays:
                t = arrays["time"]
                for key in undescribed:
                    if key != "time" and len(arrays[key]) == len(t):
                        panel(path, key, "time", arrays)
            elif path:  # not the summary's own arrays (bounce_heights beside contact_durations)
                lengths = {}
                for key, values in arrays.items():
                    lengths.setdefault(len(values), []).append(key)
                for keys in lengths.values():
                    if len(keys) >= 2 and len(arrays[keys[0]]) >= 2:
                        x = next((k for k in ABSCISSAE if k in keys), keys[0])
                        for key in keys:
                            if key != x and key in undescribed:
                                panel(path, key, x, arrays)
            for key, value in obj.items():
                walk(value, full(path, key))

    walk(summary, "")
    return panels


def figures_of_summary(summary, described):
    """The numbers the catalogue describes, as they stand at the end: (path, value or None, unit)."""
    figures = []
    for path, key in described.items():
        if key["kind"] != "number":
            continue
        value = summary
        for part in path.split("."):
            value = value.get(part) if isinstance(value, dict) else None
        if value is None and not has_path(summary, path):
            continue
        figures.append((path, value, key["unit"]))
    return figures


def has_path(summary, path):
    """Whether summary.json holds `path`, or a null object above it (a figure not measured)."""
    value = summary
    for part in path.split("."):
        if value is None:
            return True
        if not isinstance(value, dict) or part not in value:
            return False
        value = value[part]
    return True


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


def draw(panels, ledger, figures, summary, target):
    count = len(panels) + (1 if ledger else 0) + (1 if figures else 0)
    columns = 2 if count > 1 else 1
    rows = max(1, math.ceil(count / columns))
    plt = kiln_figure.pyplot(target)
    fig, axes = plt.subplots(rows, columns, figsize=(7 * columns, 3.4 * rows), squeeze=False)
    flat = [ax for row in axes for ax in row]
    for ax, panel in zip(flat, panels):
        title, xlabel, x, lines = panel[:4]
        for label, y in lines:
            style = "--" if label.startswith("mean ") else "-"
            ax.plot(x, y, style, marker="o" if len(x) < 30 else None, ms=3, label=label)
        ax.set_title(title, fontsize=9)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(panel[4])
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
    if figures:
        ax = flat[len(panels) + (1 if ledger else 0)]
        ax.axis("off")
        text = "\n".join(f"{path} = {'not measured' if v is None else f'{v:.6g}'} {'' if unit == '1' else unit}"
                         for path, v, unit in figures)
        ax.text(0, 1, text, va="top", family="monospace", fontsize=7, transform=ax.transAxes)
        ax.set_title("case figures at the end (summary.json)", fontsize=10)
    for ax in flat[count:]:
        ax.axis("off")
    fig.suptitle(f"{summary.get('scene', '?')}: {summary.get('integrator', '?')}, t = 0 to "
                 f"{summary.get('t_end', math.nan):g} s", fontsize=12)
    fig.tight_layout(rect=(0, 0, 1, 0.97))  # room for the title above the panels
    titles = ([panel[0].replace("\n", ": ") for panel in panels] + (["energy ledger"] if ledger else [])
              + (["case figures: " + ", ".join(path for path, _, _ in figures)] if figures else []))
    # The panels' titles in the PNG's text (what a reader or a test can find without looking).
    return kiln_figure.save(fig, target, dpi=100, metadata={"Description": "panels: " + "; ".join(titles)})


def main(directory, keys):
    summary_path = os.path.join(directory, "summary.json")
    if not os.path.exists(summary_path):
        print(f"error: {summary_path} not found: give the output directory of a run", file=sys.stderr)
        return kiln_figure.BAD_INPUT
    with open(summary_path) as f:
        summary = json.load(f)
    described = {key["path"]: key for key in keys}
    panels = series_of_summary(summary, described)
    result = os.path.join(directory, "result.h5")
    if os.path.exists(result):
        panels += series_of_result(result)
    return draw(panels, energy_ledger(summary), figures_of_summary(summary, described), summary,
                os.path.join(directory, "plots.png"))


if __name__ == "__main__":
    if not (len(sys.argv) == 2 or (len(sys.argv) == 4 and sys.argv[2] == "--keys")):
        kiln_figure.fail(kiln_figure.BAD_INPUT, "usage: plot_case.py DIR [--keys JSON]")
    kiln_figure.run(lambda: main(sys.argv[1], json.loads(sys.argv[3]) if len(sys.argv) == 4 else []),
                    os.path.join(sys.argv[1], "plots.png"))
