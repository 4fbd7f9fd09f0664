"""`campaign cost DIR...`: the cost model from finished campaigns (docs/CLUSTER.md): per experiment
the seconds a lockstep run takes per frame (start-up included) and its peak memory, from each
run's run.json, and the wall time of a planned campaign on N nodes of C cores.

  python3 scripts/campaign cost DIR [DIR...] [--approaches 1000] [--worlds 2]
      [--world-factor 1.7] [--nodes 1,10,50] [--cores 2,32]

--world-factor: how much longer a run takes in the other worlds than in the ideal one (the
realistic world's render; measured in docs/CLUSTER.md). Each run takes one core."""
import argparse
import glob
import json
import os


def measured(dirs):
    """experiment -> list of (frames, seconds, peak MB, CPU seconds or None) of the runs that
    finished first time."""
    table = {}
    for d in dirs:
        for path in glob.glob(os.path.join(d, "**", "run.json"), recursive=True):
            with open(path) as f:
                r = json.load(f)
            if r.get("status") == "ok" and r.get("attempts") == 1:
                e = os.path.basename(os.path.dirname(path))
                table.setdefault(e, []).append((r["frames"], r["seconds"], r.get("peak_rss_mb"),
                                                r.get("cpu_seconds")))
    return table


def main(argv):
    p = argparse.ArgumentParser(prog="campaign cost", description=__doc__.split("\n\n")[0])
    p.add_argument("dirs", nargs="+")
    p.add_argument("--approaches", type=int, default=1000)
    p.add_argument("--worlds", type=int, default=2)
    p.add_argument("--world-factor", type=float, default=1.0)
    p.add_argument("--nodes", default="1,10,50")
    p.add_argument("--cores", default="2,32")
    a = p.parse_args(argv)
    table = measured(a.dirs)
    if not table:
        print("cost: no finished run (run.json) under " + ", ".join(a.dirs))
        return 1
    print("| experiment | runs | frames a run | s a frame | CPU s a frame | s a run "
          "| peak memory (MB) |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    per_approach, longest = 0.0, 0.0
    for e, runs in sorted(table.items()):
        frames = sum(r[0] for r in runs)
        seconds = sum(r[1] for r in runs)
        peaks = [r[2] for r in runs if r[2]]
        timed = [r for r in runs if r[3] is not None]  # runs flown before CPU was recorded: none
        cpu = (f"{sum(r[3] for r in timed) / sum(r[0] for r in timed):.3f}" if timed else "n/a")
        rate = seconds / frames
        mean_frames = frames / len(runs)
        per_approach += rate * mean_frames
        longest = max(longest, max(r[1] for r in runs) * a.world_factor)
        print(f"| {e} | {len(runs)} | {mean_frames:.0f} | {rate:.3f} | {cpu} "
              f"| {rate * mean_frames:.0f} "
              f"| {max(peaks) if peaks else 'n/a'} |")
    worlds = 1 + (a.worlds - 1) * a.world_factor
    core_hours = per_approach * a.approaches * worlds / 3600
    runs = a.approaches * len(table) * a.worlds
    print(f"\n{a.approaches} approaches x {len(table)} experiments x {a.worlds} worlds = {runs} "
          f"runs, {core_hours:,.0f} core-hours (other worlds x{a.world_factor:g}):\n")
    print("| nodes | cores a node | runs at once | wall time (h) |")
    print("|---:|---:|---:|---:|")
    for n in map(int, a.nodes.split(",")):
        for c in map(int, a.cores.split(",")):
            # At least the longest run: a run is not split over cores.
            wall = max(core_hours / (n * c), longest / 3600)
            print(f"| {n} | {c} | {n * c} | {wall:,.2f} |")
    return 0
