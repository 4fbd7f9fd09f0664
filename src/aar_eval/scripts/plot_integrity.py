#!/usr/bin/python3
"""Stanford diagrams (PNG): each experiment's error against its protection level, per region.

usage: plot_integrity.py DIR EXPERIMENT[,EXPERIMENT...]
reads DIR/<experiment>/frames.csv (a run) or, when DIR/approaches exists (a suite), every
DIR/approaches/*/<experiment>/frames.csv, and writes DIR/plots/<experiment>_stanford.png: a row
for position (the norm of the x, y, z error against pl_position_m, m) and one for attitude (the
rotation angle of the roll, pitch, yaw error against pl_attitude_deg, deg), a column per region
A, B, C. Each panel is a 2-D histogram of the estimated frames not in alert (log-scaled counts,
log-log axes), the frames in alert as orange crosses, the diagonal error = level, and the
region's alert limit (the most common value of its frames' al_* column) as a horizontal and a
vertical line. Its title counts, on that quantity alone: misleading (not in alert, the error
beyond the level), HMI (not in alert, the level within the limit, the error beyond the limit)
and available (not in alert, the level within the limit) of all the region's frames. Frames
without a level are counted apart. A missing frames.csv, or one from before the integrity
columns, is said and skipped."""
import collections
import csv
import glob
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # also through rosrun's relay
import figures  # noqa: E402

# matplotlib and numpy, imported by load_plotting only when there is something to draw
# (figures.pyplot).
plt = LogNorm = np = None


def load_plotting():
    global plt, LogNorm, np
    if plt is not None:
        return
    import matplotlib.colors
    import numpy
    plt, LogNorm, np = figures.pyplot(), matplotlib.colors.LogNorm, numpy

NEEDED = ("region", "estimated", "x_m", "y_m", "z_m", "roll_deg", "pitch_deg", "yaw_deg",
          "pl_position_m", "pl_attitude_deg", "al_position_m", "al_attitude_deg", "alert")
REGIONS = ("A", "B", "C")
# (title, level column, limit column, unit)
QUANTITIES = (("position", "pl_position_m", "al_position_m", "m"),
              ("attitude", "pl_attitude_deg", "al_attitude_deg", "deg"))


def attitude_angle_deg(roll, pitch, yaw):
    """The rotation angle of Rz(yaw) Ry(pitch) Rx(roll) [deg], through its quaternion."""
    r, p, y = (math.radians(a) / 2.0 for a in (roll, pitch, yaw))
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), \
        math.sin(y)
    w = cr * cp * cy + sr * sp * sy
    x = sr * cp * cy - cr * sp * sy
    v = cr * sp * cy + sr * cp * sy
    z = cr * cp * sy - sr * sp * cy
    return math.degrees(2.0 * math.atan2(math.sqrt(x * x + v * v + z * z), abs(w)))


def read_frames(path, experiment):
    """The frames of one frames.csv as dicts of what the diagrams need; None when unusable."""
    if not os.path.exists(path):
        print(f"plot_integrity: {path} is missing", file=sys.stderr)
        return None
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        missing = [c for c in NEEDED if c not in (reader.fieldnames or [])]
        if missing:
            print(f"plot_integrity: {path} has no integrity columns (an older frames.csv: "
                  f"{', '.join(missing)} missing), left out of '{experiment}'", file=sys.stderr)
            return None
        frames = []
        for row in reader:
            try:
                frame = {"region": row["region"], "estimated": row["estimated"] == "1",
                         "alert": row["alert"] == "1"}
                if frame["estimated"]:
                    frame["position"] = math.sqrt(sum(float(row[k]) ** 2
                                                      for k in ("x_m", "y_m", "z_m")))
                    frame["attitude"] = attitude_angle_deg(
                        float(row["roll_deg"]), float(row["pitch_deg"]), float(row["yaw_deg"]))
                for _, level, limit, _ in QUANTITIES:
                    frame[level], frame[limit] = float(row[level]), float(row[limit])
            except (TypeError, ValueError) as e:
                print(f"plot_integrity: {path}: line {reader.line_num}: {e}; file left out",
                      file=sys.stderr)
                return None
            frames.append(frame)
    return frames


def experiment_frames(out_dir, experiment):
    """Every frame of the experiment (all approaches of a suite) and how many files held them."""
    approaches = os.path.join(out_dir, "approaches")
    if os.path.isdir(approaches):
        paths = sorted(os.path.join(d, experiment, "frames.csv")
                       for d in glob.glob(os.path.join(approaches, "*")) if os.path.isdir(d))
    else:
        paths = [os.path.join(out_dir, experiment, "frames.csv")]
    frames, files = [], 0
    for path in paths:
        read = read_frames(path, experiment)
        if read is not None:
            frames += read
            files += 1
    return frames, files


def most_common(values):
    finite = [v for v in values if math.isfinite(v) and v > 0.0]
    return collections.Counter(finite).most_common(1)[0][0] if finite else None


def panel(ax, fig, frames, region, quantity, level, limit, unit):
    """One Stanford diagram: the region's frames, one quantity."""
    in_region = [f for f in frames if f["region"] == region]
    estimated = [f for f in in_region if f["estimated"]]
    with_level = [f for f in estimated if math.isfinite(f[level]) and f[level] > 0.0]
    no_level = len(estimated) - len(with_level)
    ok = [f for f in with_level if not f["alert"]]
    alert = [f for f in with_level if f["alert"]]
    misleading = sum(f[quantity] > f[level] for f in ok)
    hmi = sum(f[level] <= f[limit] and f[quantity] > f[limit] for f in ok)
    available = sum(f[level] <= f[limit] for f in ok)
    al = most_common(f[limit] for f in in_region)
    title = (f"region {region}, {quantity}\nmisleading {misleading}, HMI {hmi}, available "
             f"{available} of {len(in_region)} frames")
    if no_level:
        title += f"\n{no_level} estimated without a level"
    ax.set_title(title, fontsize=9)
    ax.set_xlabel(f"{quantity} error [{unit}]")
    ax.set_ylabel(f"protection level [{unit}]")
    values = [v for f in with_level for v in (f[quantity], f[level]) if v > 0.0]
    values += [al] if al else []
    if not values:
        ax.text(0.5, 0.5, "no estimate with a level", ha="center", va="center",
                transform=ax.transAxes)
        return
    lo, hi = min(values) / 2.0, max(values) * 2.0
    if hi / lo < 10.0:
        lo, hi = lo / 3.0, hi * 3.0
    edges = np.geomspace(lo, hi, 41)
    ax.set_xscale("log")
    ax.set_yscale("log")
    if ok:
        x = np.clip([f[quantity] for f in ok], lo, hi)  # an error of 0 on the axis' edge
        y = np.clip([f[level] for f in ok], lo, hi)
        image = ax.hist2d(x, y, bins=[edges, edges], norm=LogNorm(), cmap="viridis", cmin=1)[3]
        fig.colorbar(image, ax=ax, label="frames not in alert", shrink=0.8)
    if alert:
        ax.plot(np.clip([f[quantity] for f in alert], lo, hi),
                np.clip([f[level] for f in alert], lo, hi), "x", color="tab:orange",
                markersize=4, alpha=0.7, label=f"in alert ({len(alert)})")
    ax.plot([lo, hi], [lo, hi], "k--", linewidth=0.8, label="error = level")
    if al:
        ax.axhline(al, color="tab:red", linewidth=0.9, label=f"alert limit {al:g} {unit}")
        ax.axvline(al, color="tab:red", linewidth=0.9)
    ax.set_xlim(lo, hi)
    ax.set_ylim(lo, hi)
    ax.set_aspect("equal")
    ax.grid(True, which="major", linewidth=0.3)
    ax.legend(loc="upper left", fontsize=7)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    out_dir, experiments = sys.argv[1], [e for e in sys.argv[2].split(",") if e]
    written = 0
    for experiment in experiments:
        frames, files = experiment_frames(out_dir, experiment)
        if not frames:
            print(f"plot_integrity: no frames with integrity columns for '{experiment}', no "
                  "Stanford diagram", file=sys.stderr)
            continue
        if not any(math.isfinite(f[level]) for f in frames for _, level, _, _ in QUANTITIES):
            print(f"plot_integrity: no protection level in the frames of '{experiment}' (a "
                  "publisher without integrity), no Stanford diagram", file=sys.stderr)
            continue
        load_plotting()
        fig, axes = plt.subplots(2, 3, figsize=(16, 10), dpi=100)
        for row, (quantity, level, limit, unit) in enumerate(QUANTITIES):
            for column, region in enumerate(REGIONS):
                panel(axes[row][column], fig, frames, region, quantity, level, limit, unit)
        runs = f", {files} runs" if files > 1 else ""
        fig.suptitle(f"{experiment}: Stanford diagrams ({len(frames)} frames{runs})")
        fig.tight_layout()
        os.makedirs(os.path.join(out_dir, "plots"), exist_ok=True)
        figures.save(fig, os.path.join(out_dir, "plots", f"{experiment}_stanford.png"),
                     "plot_integrity")
        written += 1
    print(f"plot_integrity: {written} Stanford diagrams in {os.path.join(out_dir, 'plots')}")


if __name__ == "__main__":
    main()
