#!/usr/bin/python3
"""Error-against-range plots (PNG) for each experiment's frames.csv.

usage: plot_errors.py DIR EXPERIMENT[,EXPERIMENT...]
writes DIR/plots/<experiment>_position.png and _orientation.png."""
import csv
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # also through rosrun's relay
import figures  # noqa: E402


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    out_dir, experiments = sys.argv[1], sys.argv[2].split(",")
    plt = None
    os.makedirs(os.path.join(out_dir, "plots"), exist_ok=True)
    for experiment in experiments:
        path = os.path.join(out_dir, experiment, "frames.csv")
        if not os.path.exists(path):
            print(f"plot_errors: {path} is missing, no plots for '{experiment}'", file=sys.stderr)
            continue
        plt = plt or figures.pyplot()
        with open(path) as f:
            rows = [r for r in csv.DictReader(f) if r["estimated"] == "1"]
        ranges = [float(r["range_m"]) for r in rows]
        for kind, keys, unit in (("position", ("x_m", "y_m", "z_m"), "m"),
                                 ("orientation", ("roll_deg", "pitch_deg", "yaw_deg"), "deg")):
            fig, ax = plt.subplots(figsize=(8, 4), dpi=100)
            for key in keys:
                values = [float(r[key]) for r in rows]
                ax.plot(ranges, values, ".", markersize=3, label=key.split("_")[0])
            for boundary in (38.0, 70.0):  # region boundaries C|B and B|A
                ax.axvline(boundary, color="grey", linewidth=0.8, linestyle="--")
            ax.invert_xaxis()  # the approach runs from far to near
            ax.set_xlabel("range from the tanker origin [m]")
            ax.set_ylabel(f"error [{unit}]")
            ax.set_title(f"{experiment}: {kind} error against range ({len(rows)} estimates)")
            ax.grid(True, linewidth=0.3)
            ax.legend(loc="upper left")
            if rows:
                limit = max(abs(float(r[k])) for r in rows for k in keys)
                if math.isfinite(limit) and limit > 0:
                    ax.set_ylim(-1.05 * limit, 1.05 * limit)
            fig.tight_layout()
            figures.save(fig, os.path.join(out_dir, "plots", f"{experiment}_{kind}.png"),
                         "plot_errors")
    print(f"plot_errors: plots in {os.path.join(out_dir, 'plots')}")


if __name__ == "__main__":
    main()
