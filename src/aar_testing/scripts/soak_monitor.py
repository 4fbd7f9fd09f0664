#!/usr/bin/env python3
"""Watches a soak (scripts/soak): every --period seconds it samples the resident memory (VmRSS)
and CPU (utime + stime deltas) of every process of the launch (the descendants of --launch-pid:
master, rosout, the nodelet manager, each stage's loader, the player) and the pose rate from the
player's status file (estimates with a pose per second). It stops when the player is done, or
on a failure: the launch ended, a process of the graph ended, or no estimate with a pose for
--stall seconds while frames were being published.

It writes OUT/soak.csv, OUT/soak.png and OUT/summary.txt, and judges: a process whose RSS grows
by more than --max-growth % between the first and the last tenth of the frames after the
--warmup frames (means of the samples; start-up allocations, each worker thread's first large
frame, are not growth; the RSS at the first estimate is reported beside them), or fewer than
--min-estimated of the frames estimated, fails.
Exit status: 0 pass, 1 fail."""
import argparse
import csv
import json
import math
import os
import platform
import sys
import time

TICK = os.sysconf("SC_CLK_TCK")


def descendants(pid):
    children = {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as f:
                ppid = int(f.read().rsplit(")", 1)[1].split()[1])
        except (OSError, IndexError, ValueError):
            continue
        children.setdefault(ppid, []).append(int(entry))
    out, todo = [], [pid]
    while todo:
        p = todo.pop()
        for c in children.get(p, []):
            out.append(c)
            todo.append(c)
    return sorted(out)


def label(pid):
    """The ROS name of a process (its __name:=), 'rosmaster', or None for a helper."""
    try:
        with open(f"/proc/{pid}/cmdline", "rb") as f:
            args = [a.decode(errors="replace") for a in f.read().split(b"\0") if a]
    except OSError:
        return None
    name = next((a.split(":=", 1)[1] for a in args if a.startswith("__name:=")), None)
    if name:
        if len(args) > 1 and os.path.basename(args[0]) == "nodelet" and args[1] == "load":
            return name + " (loader)"
        return name
    if any(os.path.basename(a) == "rosmaster" for a in args[:3]):
        return "rosmaster"
    return None


def sample(pid):
    """(RSS [MB], CPU ticks) of a process, or None when it is gone."""
    try:
        with open(f"/proc/{pid}/status") as f:
            rss = next(int(line.split()[1]) for line in f if line.startswith("VmRSS:"))
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        return rss / 1024.0, int(fields[11]) + int(fields[12])
    except (OSError, StopIteration, IndexError, ValueError):
        return None


def read_status(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def alive(pid):
    try:
        os.kill(pid, 0)
        return True
    except OSError:
        return False


def machine():
    model = "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            model = next(line.split(":", 1)[1].strip() for line in f
                         if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    with open("/proc/meminfo") as f:
        mem = int(f.readline().split()[1]) / 1024.0 / 1024.0
    return (f"{os.cpu_count()} cores ({model}), {mem:.0f} GiB, {platform.system()} "
            f"{platform.release()}; load average at the end {os.getloadavg()[0]:.2f}")


def mean(values):
    values = [v for v in values if not math.isnan(v)]
    return sum(values) / len(values) if values else float("nan")


def tenths(rows, names, total, warmup):
    """The samples of the first and the last tenth of the frames after the warm-up, and per
    process: RSS at the first estimate, mean RSS in each tenth, growth [%], peak, mean CPU."""
    tenth = (total - warmup) / 10.0
    answered = [r for r in rows if r[2] > 0] or rows
    first = [r for r in rows if warmup < r[1] <= warmup + tenth] or answered[:1]
    last = [r for r in rows if r[1] >= total - tenth] or rows[-1:]
    figures = {}
    for name in names:
        a = mean([r[4][name][0] for r in first if name in r[4]])
        b = mean([r[4][name][0] for r in last if name in r[4]])
        figures[name] = {
            "start": answered[0][4][name][0] if answered and name in answered[0][4] else a,
            "first": a, "last": b, "growth": 100.0 * (b - a) / a if a > 0 else float("nan"),
            "peak": max((r[4][name][0] for r in rows if name in r[4]), default=float("nan")),
            "cpu": mean([r[4][name][1] for r in rows if name in r[4]])}
    return first, last, figures


def plot(path, rows, names, figures, total, warmup, title):
    """RSS per process against frames (log scale; the tenths shaded), RSS against its mean in the
    first tenth (the 5 % limit dashed), and the pose rate."""
    tenth = (total - warmup) / 10.0
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullFormatter, ScalarFormatter
    fig, (top, middle, bottom) = plt.subplots(3, 1, sharex=True, figsize=(8, 8),
                                              gridspec_kw={"height_ratios": [3, 2, 1]})
    for name in sorted(names, key=lambda n: -figures[n]["peak"]):
        xs = [r[1] for r in rows if name in r[4]]
        top.plot(xs, [r[4][name][0] for r in rows if name in r[4]],
                 label=f"{name}: {figures[name]['last']:.0f} MB, "
                       f"{figures[name]['growth']:+.1f} %")
        base = figures[name]["first"]
        middle.plot(xs, [100.0 * (r[4][name][0] - base) / base for r in rows if name in r[4]],
                    linewidth=1)
    top.set_yscale("log")
    top.set_yticks([v for v in (5, 10, 20, 50, 100, 200, 500, 1000, 2000)
                    if 0.5 * min(f["peak"] for f in figures.values()) <= v
                    <= 2 * max(f["peak"] for f in figures.values())] if figures else [])
    top.yaxis.set_major_formatter(ScalarFormatter())
    top.yaxis.set_minor_formatter(NullFormatter())
    top.set_ylabel("resident memory [MB]")
    top.set_title(title, fontsize=10)
    top.legend(fontsize=7, loc="center right", title="last tenth, growth from the first",
               title_fontsize=7)
    top.grid(True, which="both", alpha=0.3)
    for lo, hi, what in ((warmup, warmup + tenth, "first tenth"),
                         (total - tenth, total, "last tenth")):
        top.axvspan(lo, hi, color="grey", alpha=0.15, linewidth=0)
        top.text((lo + hi) / 2, 0.02, what, transform=top.get_xaxis_transform(),
                 ha="center", fontsize=7, color="dimgrey")
    top.axvline(warmup, color="grey", linestyle=":", linewidth=1)
    for y in (-5.0, 5.0):
        middle.axhline(y, color="red", linestyle="--", linewidth=0.8)
    middle.set_ylim(-10, 10)
    middle.set_ylabel("RSS from the first\ntenth's mean [%]")
    middle.grid(True, alpha=0.3)
    bottom.plot([r[1] for r in rows], [r[3] for r in rows], color="black", linewidth=0.8)
    bottom.set_ylabel("estimates/s")
    bottom.set_xlabel("frames")
    bottom.set_ylim(bottom=0)
    bottom.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def replot(args):
    """soak.png again from OUT/soak.csv (the figures as the run computed them)."""
    with open(os.path.join(args.out, "soak.csv")) as f:
        table = list(csv.reader(f))
    names = [c[:-len(" rss_mb")] for c in table[0][4::2]]
    rows = [(float(r[0]), int(r[1]), int(r[2]), float(r[3]),
             {n: (float(r[4 + 2 * i]), float(r[5 + 2 * i])) for i, n in enumerate(names)})
            for r in table[1:]]
    figures = tenths(rows, names, args.frames, args.warmup)[2]
    plot(os.path.join(args.out, "soak.png"), rows, names, figures, args.frames, args.warmup,
         f"soak: {rows[-1][1]} frames, {args.about}")
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--launch-pid", type=int)
    ap.add_argument("--status", help="the player's status file")
    ap.add_argument("--out", required=True)
    ap.add_argument("--frames", type=int, required=True)
    ap.add_argument("--period", type=float, default=5.0, help="[s] between samples")
    ap.add_argument("--stall", type=float, default=30.0,
                    help="[s] without an estimate with a pose while frames are published: fail")
    ap.add_argument("--min-estimated", type=float, default=0.9,
                    help="least share of the frames with an estimate with a pose")
    ap.add_argument("--warmup", type=int, default=100,
                    help="frames before the first tenth (start-up allocations)")
    ap.add_argument("--max-growth", type=float, default=5.0, help="[%%] RSS, first to last tenth")
    ap.add_argument("--start-timeout", type=float, default=180.0,
                    help="[s] for the first frame's estimate, while the graph starts")
    ap.add_argument("--command", default="")
    ap.add_argument("--commit", default="unknown")
    ap.add_argument("--about", default="", help="a line on what ran (bag, experiment)")
    ap.add_argument("--replot", action="store_true",
                    help="only draw OUT/soak.png again from OUT/soak.csv")
    args = ap.parse_args()
    if args.replot:
        return replot(args)
    failures = []

    def say(text):
        print(f"soak: {text}", flush=True)

    # The graph is up once the first frame went out and was answered (or timed out).
    start = time.monotonic()
    status = None
    while True:
        status = read_status(args.status)
        if status and (status["estimates"] > 0 or status["timeouts"] > 0):
            break
        if not alive(args.launch_pid):
            failures.append("the launch ended before the first estimate")
            break
        if time.monotonic() - start > args.start_timeout:
            failures.append(f"no estimate within {args.start_timeout:.0f} s of the start")
            break
        time.sleep(0.2)

    procs = {}  # label -> pid
    if not failures:
        for pid in descendants(args.launch_pid):
            name = label(pid)
            if name:
                procs[name] = pid
        say("watching " + ", ".join(f"{n} ({p})" for n, p in sorted(procs.items())))
    names = sorted(procs)
    # soak.csv grows a row a sample, so that a long run can be watched (and survives its end).
    os.makedirs(args.out, exist_ok=True)
    table = open(os.path.join(args.out, "soak.csv"), "w", newline="", buffering=1)
    writer = csv.writer(table)
    writer.writerow(["time_s", "frames", "estimated", "pose_rate_hz"]
                    + [c for n in names for c in (f"{n} rss_mb", f"{n} cpu_pct")])
    rows = []  # time_s, frames, valid, pose_rate, {name: (rss, cpu)}
    last_ticks = {}
    last_t, last_valid = None, None
    last_print = 0.0
    t0 = (status or {}).get("first_frame_wall") or time.monotonic()
    while not failures:
        now = time.monotonic()
        status = read_status(args.status) or status
        row = {}
        for name in names:
            s = sample(procs[name])
            if s is None:
                failures.append(f"{name} (pid {procs[name]}) ended at frame {status['frames']}")
                continue
            rss, ticks = s
            cpu = float("nan")
            if last_t is not None:
                cpu = 100.0 * (ticks - last_ticks[name]) / TICK / (now - last_t)
            last_ticks[name] = ticks
            row[name] = (rss, cpu)
        rate = float("nan") if last_t is None else (status["valid"] - last_valid) / (now - last_t)
        if not failures:
            rows.append((now - t0, status["frames"], status["valid"], rate, row))
            writer.writerow([f"{now - t0:.1f}", status["frames"], status["valid"], f"{rate:.3f}"]
                            + [f"{v:.2f}" for n in names for v in row[n]])
        last_t, last_valid = now, status["valid"]
        if status["done"] or failures:
            break
        if not alive(args.launch_pid):
            failures.append(f"the launch ended at frame {status['frames']} of {args.frames}")
            break
        since = now - (status["last_valid_wall"] or status["first_frame_wall"] or now)
        if since > args.stall:
            failures.append(f"estimates stopped: none with a pose for {since:.0f} s while frames "
                            f"were published (frame {status['frames']} of {args.frames}, "
                            f"{status['timeouts']} timed out)")
            break
        if now - last_print >= 60.0:
            last_print = now
            biggest = max(names, key=lambda n: row[n][0]) if names else None
            say(f"frame {status['frames']} of {args.frames}, {now - t0:.0f} s, "
                + (f"{biggest} {row[biggest][0]:.1f} MB, " if biggest else "")
                + f"{status['valid']} estimated"
                + ("" if math.isnan(rate) else f", pose rate {rate:.2f}/s"))
        time.sleep(max(0.0, args.period - (time.monotonic() - now)))

    table.close()

    first, last, figures = tenths(rows, names, args.frames, args.warmup)
    frames = status["frames"] if status else 0
    valid = status["valid"] if status else 0
    share = valid / frames if frames else 0.0
    complete = bool(status and status["done"])
    if complete:
        for name in names:
            g = figures[name]["growth"]
            if not g <= args.max_growth:
                failures.append(f"{name} grew {g:.1f} % ({figures[name]['first']:.1f} MB in the "
                                f"first tenth, {figures[name]['last']:.1f} MB in the last; limit "
                                f"{args.max_growth:g} %)")
        if share < args.min_estimated:
            failures.append(f"only {valid} of {frames} frames estimated ({100 * share:.1f} %; "
                            f"at least {100 * args.min_estimated:.0f} % needed)")
    rates = [r[3] for r in rows if r[2] > 0]
    elapsed = rows[-1][0] if rows else 0.0

    try:
        plot(os.path.join(args.out, "soak.png"), rows, names, figures, args.frames, args.warmup,
             f"soak: {frames} frames, {args.about}")
    except Exception as e:  # the figures still count without the plot
        failures.append(f"soak.png not written: {e}")

    lines = [
        f"command: {args.command}",
        f"date (UTC): {time.strftime('%Y-%m-%d %H:%M:%S', time.gmtime())}",
        f"commit: {args.commit}",
        f"machine: {machine()}",
        f"run: {args.about}",
        f"frames: {frames} of {args.frames} published in {elapsed:.0f} s "
        f"({elapsed / frames if frames else float('nan'):.3f} s a frame), "
        f"{status['estimates'] if status else 0} estimates, {valid} with a pose "
        f"({100 * share:.1f} %), {status['timeouts'] if status else 0} frames timed out",
        f"pose rate: mean {mean(rates):.2f} estimates with a pose per second "
        f"({len(rows)} samples every {args.period:g} s)",
        f"warm-up: {args.warmup} frames; tenths of the frames after it: first {len(first)} "
        f"samples (frames {first[0][1] if first else 0}-{first[-1][1] if first else 0}), "
        f"last {len(last)} samples "
        f"(frames {last[0][1] if last else 0}-{last[-1][1] if last else 0})",
        "",
        f"{'process':<24} {'RSS at start':>12} {'first tenth':>12} {'last tenth':>11} "
        f"{'growth':>8} {'peak':>9} {'mean CPU':>9}",
    ]
    for name in sorted(names, key=lambda n: -figures[n]["peak"]):
        f_ = figures[name]
        lines.append(f"{name:<24} {f_['start']:>9.1f} MB {f_['first']:>9.1f} MB "
                     f"{f_['last']:>8.1f} MB {f_['growth']:>+7.2f}% {f_['peak']:>6.1f} MB "
                     f"{f_['cpu']:>8.1f}%")
    lines.append("")
    lines += [f"FAIL: {f}" for f in failures] or [
        f"PASS: no process grew more than {args.max_growth:g} %, estimates never stopped for "
        f"{args.stall:g} s, {100 * share:.1f} % of the frames estimated "
        f"(at least {100 * args.min_estimated:.0f} % needed)"]
    with open(os.path.join(args.out, "summary.txt"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines[5:]), flush=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
