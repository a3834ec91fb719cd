#!/usr/bin/env python3
"""The table and the goal ratios of one bench/run.sh invocation, from its CSV of runs.

Every ratio comes from runs of that invocation: where two codes (or two variants) ran in the same
group, repeat by repeat, the ratio is the median of the ratios of each repeat's runs (the machine's
load drifts between repeats, less within one). The last line is
`ratio kiln/LAMMPS particle-steps/s: X.XX at N=10000`.
"""
import csv
import statistics
import sys

MODEL = {
    "kiln": "velocity Verlet",
    "LAMMPS": "gran/hooke/history",
    "LIGGGHTS": "hooke/stiffness, tangential history",
}


def load(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for key in ("n", "steps", "warmup", "threads", "rhs_evals", "repeat"):
            r[key] = int(r[key])
        for key in ("loop_s", "peak_rss_mb"):
            r[key] = float(r[key])
        # kiln's run alone, its stability estimate before it left out: empty for the peers, -1 where
        # kiln could not measure it (no /proc/self/clear_refs)
        run_rss = float(r["run_rss_mb"]) if r.get("run_rss_mb") else -1
        r["run_rss_mb"] = run_rss if run_rss > 0 else None
        r["contacts_per_disc"] = float(r["contacts_per_disc"]) if r["contacts_per_disc"] else None
        r["rebuild_ns_per_disc"] = float(r["rebuild_ns_per_disc"]) if r.get("rebuild_ns_per_disc") else None
        r["rate"] = r["n"] * r["steps"] / r["loop_s"]
    return rows


def select(rows, group=None, **match):
    return [r for r in rows if (group is None or r["group"] == group) and all(r[k] == v for k, v in match.items())]


def paired(rows, group, a, b, figure):
    """Median over the group's repeats of figure(run of a) / figure(run of b), with the range."""
    ratios = []
    for repeat in sorted({r["repeat"] for r in select(rows, group)}):
        ra, rb = select(rows, group, repeat=repeat, **a), select(rows, group, repeat=repeat, **b)
        if ra and rb:
            ratios.append(figure(ra[0]) / figure(rb[0]))
    if not ratios:
        return None
    return statistics.median(ratios), min(ratios), max(ratios), len(ratios)


def show(label, result, goal=""):
    if result is None:
        print(f"{label}: n/a (not run)")
        return
    median, lo, hi, count = result
    spread = f" (pairs {lo:.2f}-{hi:.2f}, {count})" if count > 1 else " (one pair)"
    print(f"{label}: {median:.2f}{spread}{goal}")


def rate(r):
    return r["rate"]


def step_seconds(r):
    return r["loop_s"] / r["steps"]


def rhs_seconds(r):
    return r["loop_s"] / r["rhs_evals"]


def table(rows):
    keys = []
    for r in rows:
        key = (r["code"], r["model"], r["integrator"], r["n"], r["steps"], r["threads"])
        if key not in keys:
            keys.append(key)
    head = (f"{'code':<10} {'model':<44} {'N':>7} {'steps':>6} {'loop time median (min-max) s':>29} "
            f"{'particle-steps/s':>16} {'peak RSS MB':>11} {'RSS kB/particle':>15}")
    print(head)
    print("-" * len(head))
    for code, model, integrator, n, steps, threads in keys:
        runs = select(rows, code=code, model=model, integrator=integrator, n=n, steps=steps, threads=threads)
        loops = [r["loop_s"] for r in runs]
        loop = statistics.median(loops)
        rss = statistics.median(r["peak_rss_mb"] for r in runs)
        name = MODEL[code] if integrator == "velocity-verlet" or code != "kiln" else f"ARKODE {integrator}"
        description = f"{name}, {model}" + (f", {threads} threads" if threads > 1 else "")
        spread = f"{loop:.3f} ({min(loops):.3f}-{max(loops):.3f}) x{len(loops)}"
        print(f"{code:<10} {description:<44} {n:>7} {steps:>6} {spread:>29} {n * steps / loop:>16.3g} "
              f"{rss:>11.1f} {rss * 1024 / n:>15.2f}")


def median_of(rows, figure, **match):
    runs = select(rows, **match)
    return statistics.median(figure(r) for r in runs) if runs else None


def main(path):
    rows = load(path)
    table(rows)
    print()
    print("Goals (each ratio from runs of this invocation, pair by pair):")
    vv = {"integrator": "velocity-verlet", "threads": 1}
    for group, n in (("small", 1000), ("resting", 10000), ("large", 100000)):
        show(f"  kiln/LAMMPS particle-steps/s, resting, N={n}",
             paired(rows, group, dict(code="kiln", **vv), dict(code="LAMMPS"), rate),
             "" if n == 1000 else "  (goal >= 2.5)")
    show("  kiln/LIGGGHTS particle-steps/s, resting, N=10000",
         paired(rows, "resting", dict(code="kiln", **vv), dict(code="LIGGGHTS"), rate))
    show("  kiln/LAMMPS particle-steps/s, flowing, N=10000",
         paired(rows, "flowing", dict(code="kiln", **vv), dict(code="LAMMPS"), rate))
    show("  kiln/LAMMPS particle-steps/s, numbered at random (mixed), N=100000",
         paired(rows, "mixed", dict(code="kiln", **vv), dict(code="LAMMPS"), rate), "  (goal >= 2.5)")
    show("  heat: kiln thermal / plain step time, N=10000",
         paired(rows, "cost", dict(code="kiln", model="thermal", **vv), dict(code="kiln", model="resting", **vv),
                step_seconds), "  (goal <= 1.20)")
    show("  heat: LIGGGHTS heat/gran/conduction / plain step time, N=10000",
         paired(rows, "cost", dict(code="LIGGGHTS", model="thermal"), dict(code="LIGGGHTS", model="resting"),
                step_seconds))
    show("  ARKODE erk2 right-hand side / velocity-Verlet step, N=10000",
         paired(rows, "cost", dict(code="kiln", integrator="erk2"), dict(code="kiln", model="resting", **vv),
                lambda r: rhs_seconds(r) if r["integrator"] != "velocity-verlet" else step_seconds(r)),
         "  (goal <= 1.20)")

    # Memory per particle: the slope of peak RSS between the smallest and the largest pile each
    # code ran, which leaves out its fixed footprint (binary, libraries, MPI runtime). The goal's
    # figure is the process's peak, as for the peers; kiln's run alone (its system, lists and
    # steps, without the stability estimate that precedes it) is printed beside it.
    slopes = {}
    for code, figure, what in (("kiln", "peak_rss_mb", "kiln"), ("LAMMPS", "peak_rss_mb", "LAMMPS"),
                               ("kiln", "run_rss_mb", "kiln's run alone")):
        match = dict(code=code, model="resting", **(vv if code == "kiln" else {}))
        measured = [r for r in rows if r[figure] is not None]
        sizes = sorted({r["n"] for r in select(measured, **match)})
        if len(sizes) >= 2:
            small, large = sizes[0], sizes[-1]
            m = [median_of(measured, lambda r: r[figure], n=size, **match) for size in (small, large)]
            slopes[what] = (m[1] - m[0]) * 1024 * 1024 / (large - small)
            print(f"  memory per particle, {what}: {slopes[what]:.0f} bytes (peak RSS slope from N={small} to N={large}; "
                  f"{m[1]:.1f} MB at N={large})")
    if "kiln" in slopes and "LAMMPS" in slopes:
        print(f"  memory per particle, kiln/LAMMPS: {slopes['kiln'] / slopes['LAMMPS']:.2f}  (goal <= 1)")
    alone = "kiln's run alone"
    if alone in slopes and "LAMMPS" in slopes:
        print(f"  memory per particle, {alone}/LAMMPS: {slopes[alone] / slopes['LAMMPS']:.2f}"
              "  (the stability estimate before it left out)")

    for code in ("kiln", "LAMMPS"):
        ns = []
        for n in (1000, 10000, 100000):
            value = median_of(rows, lambda r: 1e9 / r["rate"], code=code, model="resting", n=n,
                              **(vv if code == "kiln" else {}))
            if value is not None:
                ns.append((n, value))
        if ns:
            figures = ", ".join(f"{v:.1f} at N={n}" for n, v in ns)
            growth = f"; largest/smallest N: {ns[-1][1] / ns[0][1]:.2f}" if len(ns) > 1 else ""
            print(f"  ns per particle-step, {code}: {figures}{growth}" + ("  (goal: flat)" if code == "kiln" else ""))

    # A neighbour rebuild per disc: kiln's rebuilds while timed (or its first build, when none),
    # LAMMPS' Neigh time per build of the timed run.
    rebuilt = [r for r in rows if r["rebuild_ns_per_disc"] is not None]
    show("  neighbour rebuild per disc, kiln/LAMMPS, flowing, N=10000",
         paired(rebuilt, "flowing", dict(code="kiln", **vv), dict(code="LAMMPS"), lambda r: r["rebuild_ns_per_disc"]),
         "  (goal <= 1)")
    for code in ("kiln", "LAMMPS"):
        ns = median_of(rebuilt, lambda r: r["rebuild_ns_per_disc"], group="flowing", code=code)
        if ns is not None:
            print(f"  neighbour rebuild per disc, {code}, flowing, N=10000: {ns:.0f} ns")

    show("  kiln 2-thread speed-up, N=100000 (1-thread / 2-thread loop time)",
         paired(rows, "large", dict(code="kiln", integrator="velocity-verlet", threads=2),
                dict(code="kiln", integrator="velocity-verlet", threads=1), lambda r: 1 / r["loop_s"]),
         "  (goal >= 1.8)")

    # The same physics: contacts per disc at the end of the timed runs on the 10,000 pile.
    counted = [r for r in rows if r["contacts_per_disc"] is not None]
    for group in ("resting", "flowing"):
        k = median_of(counted, lambda r: r["contacts_per_disc"], group=group, code="kiln")
        lmp = median_of(counted, lambda r: r["contacts_per_disc"], group=group, code="LAMMPS")
        if k is not None and lmp is not None:
            print(f"  contacts per disc (particle-particle), N=10000 {group}, end of the timed run: kiln {k:.3f}, "
                  f"LAMMPS {lmp:.3f} ({100 * (k - lmp) / lmp:+.1f} %)")
    print()
    last = paired(rows, "resting", dict(code="kiln", **vv), dict(code="LAMMPS"), rate)
    print(f"ratio kiln/LAMMPS particle-steps/s: {last[0]:.2f} at N=10000" if last else
          "ratio kiln/LAMMPS particle-steps/s: n/a at N=10000")


if __name__ == "__main__":
    main(sys.argv[1])
