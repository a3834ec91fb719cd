"""N3's profiles side by side: plot_shear_profiles.py OUT.png DIR [DIR ...] draws, for each run
directory (its summary.json `shear_profile`), the velocity along the drive over the wall's speed and
the share of the friction heat made in each layer, against the relative height eta (0 at the
bottom wall, 1 at the driven wall). Layers holding only a wall's glued grains have no velocity."""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(target, directories):
    fig, (speed, heat) = plt.subplots(1, 2, figsize=(10, 4.5), sharey=True)
    for directory in directories:
        with open(os.path.join(directory, "summary.json")) as f:
            s = json.load(f)
        p = s["shear_profile"]
        label = f"V = {p['wall_speed']:g} m/s, I = {s['inertial_number']:.2g}, mu_eff = {s['effective_friction']:.2f}"
        points = [(v, e) for v, e in zip(p["velocity_over_wall"], p["eta"]) if v is not None]
        speed.plot([v for v, _ in points], [e for _, e in points], marker=".", label=label)
        heat.plot(p["heat_share"], p["eta"], marker=".", label=label)
    speed.set_xlabel("velocity / wall speed")
    speed.set_ylabel("eta = height / gap")
    speed.set_title("velocity profile (time mean, second half)")
    heat.set_xlabel("share of the friction heat made in the layer")
    heat.set_title("friction heat against height")
    for ax in (speed, heat):
        ax.grid(True, alpha=0.3)
    speed.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    tmp = target + ".tmp.png"
    fig.savefig(tmp, dpi=100)
    os.replace(tmp, target)


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit("usage: plot_shear_profiles.py OUT.png DIR [DIR ...]")
    main(sys.argv[1], sys.argv[2:])
