"""Real-time benchmark: a recorded approach replayed in real time (or S times faster) through the
processing graph (one nodelet manager), once per configuration, side by side. Per frame: the
wall-clock latency from the images leaving the bag player to the pose being published, the stage
times, frames estimated and dropped, CPU use and the replay's accuracy; per stage, the frames it
skipped, by reason (its counters on /diagnostics).
  scripts/bench-realtime [--configs flight,dynamic] [--flight-path FILE] [--rate HZ]
                         [--sim-config FILE] [--speed S | --headroom] [--bag FILE] [--out DIR]
                         [--no-stage-times] [--no-build]
--sim-config FILE: a YAML loaded over config/sim.yaml for the recording (the realistic world:
config/realism/realistic.yaml; another camera mount).
--rate is the recording's frame rate; --speed S replays it at S times real time (default 1).
--headroom replays each configuration at speeds 1, 1.5, 2 and 3, up to the first that fails:
fewer than 99 % of the frames estimated, or a p95 latency of 50 ms or more. Results go to
DIR/<config>/speed-<S>/ when more than one speed runs, else to DIR/<config>/.
The bag (default rosbags/cache/realtime-<path>-<rate>hz.bag, 1280x960 as config/sim.yaml) is
recorded once, in lockstep, and reused while the flight path and config/sim.yaml are unchanged.
A configuration with more than one rig (flight_two_rigs; issue 44): the bag holds every rig of
the configuration with the most (<path>-<rate>hz-<further rigs>.bag, recorded with that
configuration, reused while its rigs' mounts are unchanged too); each configuration replays its
own rigs from it (one rig: the first only); every configuration's rigs must be among its.
Ends with one line per configuration and speed, the first configuration last:
  realtime: <config> <N> frames at <rate> Hz, speed <S>, estimated <E>, dropped <D>, latency p50 <a> ms p95 <b> ms p99 <c> ms
and with --headroom one per configuration, the highest speed passed (none: not even speed 1):
  headroom: <config> speed <S>

(scripts/bench-realtime is a wrapper around this module: python3 scripts/campaign bench-realtime.)"""
import csv
import glob
import hashlib
import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

from campaign import arguments, bag, workspace
from campaign.plan import CHECK_EXPERIMENT, experiment_rigs
from campaign.workspace import ROOT, Refused, fail, say

# Headroom: a speed is kept while at least 99 % of the bag's frames are estimated and p95 < 50 ms.
MIN_ESTIMATED, MAX_P95_MS = 0.99, 50.0
HEADROOM_SPEEDS = ("1", "1.5", "2", "3")


def parse(argv):
    p = arguments.Parser("bench-realtime", __doc__)
    p.add_argument("--configs", default="flight,dynamic")
    p.add_argument("--flight-path", default=os.path.join(ROOT, "config/flight_paths/"
                                                         "approach_default.csv"))
    p.add_argument("--rate", default="30")
    p.add_argument("--sim-config", default="")
    p.add_argument("--speed", default="")
    p.add_argument("--headroom", action="store_true")
    p.add_argument("--bag", default="")
    p.add_argument("--out", default="")
    p.add_argument("--no-build", action="store_true")
    p.add_argument("--no-stage-times", action="store_true", help="the probe listens to no cloud")
    a = p.parse_args(argv)
    caller = os.getcwd()
    for k in ("flight_path", "sim_config", "bag", "out"):
        setattr(a, k, arguments.absolute(getattr(a, k), caller))
    arguments.positive("--rate", a.rate)
    if a.speed:
        arguments.positive("--speed", a.speed)
    if not os.path.isfile(a.flight_path):
        fail(f"flight path '{a.flight_path}' does not exist")
    if a.sim_config and not os.path.isfile(a.sim_config):
        fail(f"--sim-config '{a.sim_config}' does not exist")
    if not re.fullmatch(r"[0-9]+(\.[0-9]+)?", a.rate):
        fail(f"--rate takes frames per second, not '{a.rate}'")
    if a.headroom:
        if a.speed:
            fail("--headroom picks its own speeds; no --speed with it")
        a.speeds = list(HEADROOM_SPEEDS)
    else:
        a.speed = a.speed or "1"
        if not re.fullmatch(r"([0-9]+(\.[0-9]*)?|\.[0-9]+)", a.speed) or not float(a.speed) > 0:
            fail(f"--speed takes a positive number (times real time), not '{a.speed}'")
        a.speeds = [f"{float(a.speed):g}"]  # 2.0 -> 2, for the lines and folders
    a.names = a.configs.split(",")
    for c in a.names:
        if not os.path.isfile(os.path.join(ROOT, "config/experiments", c + ".yaml")):
            fail(f"no experiment '{c}' in config/experiments")
    # Each configuration's rigs; the bag holds those of the one with the most, which must hold
    # every other's.
    try:
        a.rigs = {c: experiment_rigs(c).split(",") for c in a.names}
    except Refused as e:
        fail(str(e))
    a.most = max(a.names, key=lambda c: len(a.rigs[c]))
    for c in a.names:
        if not set(a.rigs[c]) <= set(a.rigs[a.most]):
            fail(f"configurations {a.most} and {c} fly different rigs ({','.join(a.rigs[a.most])}; "
                 f"{','.join(a.rigs[c])}): one bag cannot serve both; bench them apart")
    return a


def sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def sim_section(experiment):
    """The experiment's sim settings (its rigs' mounts), resolved, as one line of JSON."""
    import yaml
    with tempfile.TemporaryDirectory() as d:
        resolved = os.path.join(d, "resolved.yaml")
        if subprocess.run([sys.executable, CHECK_EXPERIMENT,
                           os.path.join(ROOT, "config/experiments", experiment + ".yaml"),
                           "--resolved", resolved], stdout=subprocess.DEVNULL).returncode:
            fail(f"experiment '{experiment}' refused (check_experiment.py)")
        with open(resolved) as f:
            tree = yaml.safe_load(f) or {}
    return json.dumps(tree.get("sim", {}), sort_keys=True)


def record(a, env):
    """The recording: reused while what it was made from is unchanged. Returns its frames."""
    stem = os.path.basename(a.flight_path)
    stem = stem[:-4] if stem.endswith(".csv") else stem
    world = ""
    if a.sim_config:
        world = os.path.basename(a.sim_config)
        world = "-" + (world[:-5] if world.endswith(".yaml") else world)
    # One rig: the recording flies tracking (any experiment's images are the simulator's); more:
    # the configuration with the most rigs, whose sim flies them, and the bag is theirs.
    rigs = a.rigs[a.most]
    experiment = "tracking" if len(rigs) == 1 else a.most
    further = "".join("-" + r for r in rigs[1:])
    a.bag = a.bag or os.path.join(ROOT, f"rosbags/cache/realtime-{stem}{world}-{a.rate}hz"
                                  f"{further}.bag")
    os.makedirs(os.path.dirname(a.bag), exist_ok=True)
    sources = [a.flight_path, os.path.join(ROOT, "config/sim.yaml")] + \
        ([a.sim_config] if a.sim_config else [])
    made_from = "".join(sha256(f) + " " for f in sources) + \
        f" rate {a.rate}, re-timed to the stamps"
    if len(rigs) > 1:
        made_from += f", rigs {','.join(rigs)} {sim_section(experiment)}"
    try:
        with open(a.bag + ".source") as f:
            recorded_from = f.read().rstrip("\n")
    except OSError:
        recorded_from = None
    if not os.path.isfile(a.bag) or recorded_from != made_from:
        say(f"recording {a.flight_path} at {a.rate} Hz into {a.bag} (once; lockstep, a few "
            f"minutes; {experiment}, rigs {','.join(rigs)})")
        for f in (a.bag, a.bag + ".source"):
            if os.path.lexists(f):
                os.remove(f)
        with open(os.path.join(a.out, "recording.log"), "w") as log:
            status = subprocess.run(
                [sys.executable, os.path.join(ROOT, "scripts/campaign"), "fly", "--experiment",
                 experiment, "--flight-path", a.flight_path, "--rate", a.rate, "--sim-config",
                 a.sim_config, "--out", os.path.join(a.out, "recording"), "record:=" + a.bag],
                stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, cwd=ROOT,
                env=env).returncode
        if status:
            fail(f"recording failed; see {a.out}/recording.log", 1)
        for _ in range(60):  # rosbag renames on exit
            if os.path.isfile(a.bag):
                break
            time.sleep(0.5)
        if not os.path.isfile(a.bag):
            fail(f"no bag was written; see {a.out}/recording.log", 1)
        # Lockstep recording under the simulated clock stamps a message's receipt with the
        # clock's 33 ms ticks: in 5 to 10 % of frames the right half, and in most the boom's tf,
        # were recorded a tick after the left image, a lag no camera pair or encoder has, which
        # the player would replay. Each message is re-timed to its own stamp (tf: its latest
        # transform's).
        if subprocess.run([sys.executable, os.path.join(ROOT, "scripts/campaign"),
                           "bench-realtime-retime", a.bag], env=env, cwd=ROOT).returncode:
            os.remove(a.bag)
            fail(f"re-timing {a.bag} failed", 1)
        with open(a.bag + ".source", "w") as f:
            f.write(made_from + "\n")
    info = subprocess.run(["rosbag", "info", "--yaml", "--key", "topics", a.bag], env=env,
                          capture_output=True, text=True).stdout
    frames = bag.topic_messages(info, "/stereo/left/image_rect")
    if frames <= 0:
        fail(f"bag '{a.bag}' has no left images")
    held = bag.rigs_of(info)
    if any(r not in held for r in rigs):
        fail(f"bag '{a.bag}' holds the rigs {','.join(held)}, {a.most} flies {','.join(rigs)}")
    return frames


def retime(path):
    """bench-realtime-retime BAG: each message at its own stamp (in the ROS environment)."""
    import rosbag
    with rosbag.Bag(path) as src, rosbag.Bag(path + ".retimed", "w", compression="lz4") as dst:
        for topic, msg, t, header in src.read_messages(return_connection_header=True):
            stamp = None
            if topic == "/tf" and msg.transforms:
                stamp = max(tr.header.stamp for tr in msg.transforms)
            elif topic != "/tf_static" and hasattr(msg, "header"):
                stamp = msg.header.stamp
            dst.write(topic, msg, stamp if stamp is not None and not stamp.is_zero() else t,
                      connection_header=header)
    os.replace(path + ".retimed", path)
    return 0


def skips_recorder(out):
    """bench-realtime-skips FILE (in the ROS environment, ROS_MASTER_URI the replay's): the
    stages' frames dropped by reason (their frame ledger's keys, "ledger: frames dropped:
    REASON"), and registration's outline counters (frames aligned, fused, without its inputs),
    from /diagnostics: the last value of each (status, key), kept in FILE (CSV: status,key,count)
    as they change and at the end (SIGINT). A counter that goes down is a stage that came back
    (respawned): its counts are added."""
    import threading
    import genpy.dynamic
    import rospy
    counter = re.compile("^(ledger: frames dropped: |outline: frames)")
    lock = threading.Lock()
    last, base, types = {}, {}, {}

    def write():
        with lock:
            with open(out + ".tmp", "w", newline="") as f:
                w = csv.writer(f)
                w.writerow(["status", "key", "count"])
                for k in sorted(last):
                    w.writerow([k[0], k[1], base.get(k, 0) + last[k]])
            os.replace(out + ".tmp", out)

    def on_diagnostics(raw):
        # Any message, decoded with the definition it came with: python3-diagnostic-msgs is not
        # among scripts/debian-packages.txt (the C++ side only, libdiagnostic-updater-dev).
        header = raw._connection_header
        if header["md5sum"] not in types:
            types[header["md5sum"]] = genpy.dynamic.generate_dynamic(
                header["type"], header["message_definition"])[header["type"]]
        msg = types[header["md5sum"]]().deserialize(raw._buff)
        changed = False
        with lock:
            for status in msg.status:
                for kv in status.values:
                    try:
                        value = int(kv.value) if counter.search(kv.key) else None
                    except ValueError:
                        value = None
                    if value is None:
                        continue
                    k = (status.name, kv.key)
                    if k in last and value < last[k]:
                        base[k] = base.get(k, 0) + last[k]
                    changed |= last.get(k) != value
                    last[k] = value
        if changed:
            write()

    rospy.init_node("bench_realtime_skips", anonymous=True)
    write()
    rospy.Subscriber("/diagnostics", rospy.AnyMsg, on_diagnostics, queue_size=100)
    rospy.spin()
    write()
    return 0


# --- The report ------------------------------------------------------------------------------

def pct(xs, q):
    if not xs:
        return math.nan
    xs = sorted(xs)
    k = (len(xs) - 1) * q / 100.0
    f = math.floor(k)
    return xs[f] if f == k else xs[f] + (xs[f + 1] - xs[f]) * (k - f)


def median(xs):
    return pct(xs, 50)


def load(folder, bag_frames):
    """One run's figures from its folder: probe.csv, frames.csv (eval's), cpu.txt, skips.csv."""
    first = {}
    try:
        with open(os.path.join(folder, "probe.csv")) as f:
            for r in csv.DictReader(f):
                first.setdefault((r["kind"], int(r["stamp_ns"])), (float(r["wall_s"]), r))
    except FileNotFoundError:
        pass
    frames = sorted(s for (k, s) in first if k == "frame")
    lat, stereo, occl, reg, reg_cpu = [], [], [], [], []
    region_of = {}  # stamp [ms] -> region, from eval's frames.csv
    try:
        with open(os.path.join(folder, "frames.csv")) as f:
            for r in csv.DictReader(f):
                region_of[round(float(r["t"]) * 1000)] = r["region"]
    except FileNotFoundError:
        pass
    profile = {}  # region -> stage -> [ms]
    estimated = 0
    for s in frames:
        t_in = first[("frame", s)][0]
        e = first.get(("estimate", s))
        if e is None:
            continue
        t_out, r = e
        lat.append(1000 * (t_out - t_in))
        estimated += r["valid"] == "1"
        c, fl = first.get(("cloud", s)), first.get(("filtered", s))
        if c:
            stereo.append(1000 * (c[0] - t_in))
        if c and fl:
            occl.append(1000 * (fl[0] - c[0]))
        if fl:
            reg.append(1000 * (t_out - fl[0]))
        reg_cpu.append(float(r["registration_ms"] or 0))
        stages = profile.setdefault(region_of.get(round(s / 1e6), "(no eval row)"), {})
        stages.setdefault("latency", []).append(lat[-1])
        if c:
            stages.setdefault("stereo", []).append(stereo[-1])
        if c and fl:
            stages.setdefault("occlusion", []).append(occl[-1])
        if fl:
            stages.setdefault("registration", []).append(reg[-1])
        stages.setdefault("registration (in node)", []).append(reg_cpu[-1])
    cpu = dict(manager_cpu_pct="nan", player_cpu_pct="nan", machine_busy_pct="nan",
               seconds="nan", cores="0")
    try:
        with open(os.path.join(folder, "cpu.txt")) as f:
            cpu.update(line.strip().split("=") for line in f if "=" in line)
    except FileNotFoundError:
        pass
    # Accuracy of the replay, per region, from eval's frames.csv.
    acc = {}
    try:
        with open(os.path.join(folder, "frames.csv")) as f:
            for r in csv.DictReader(f):
                a = acc.setdefault(r["region"], {"n": 0, "e": 0, "x": 0.0, "ang": 0.0})
                a["n"] += 1
                if r["estimated"] == "1":
                    a["e"] += 1
                    a["x"] += abs(float(r["x_m"]))
                    a["ang"] += max(abs(float(r[k])) for k in ("roll_deg", "pitch_deg",
                                                                "yaw_deg"))
    except FileNotFoundError:
        pass
    # The stages' skip counters (/diagnostics); None: none recorded.
    try:
        with open(os.path.join(folder, "skips.csv")) as f:
            counters = [(r["status"], r["key"], int(r["count"])) for r in csv.DictReader(f)]
        skips = [c for c in counters if not c[1].startswith("outline: ")]
        outline = {k[len("outline: frames "):]: n for (_, k, n) in counters
                   if k.startswith("outline: ")}
    except (FileNotFoundError, ValueError, KeyError):
        skips, outline = None, {}
    # A frame the probe never saw still left the bag: it counts as dropped.
    return dict(n=bag_frames, est=estimated, drop=bag_frames - len(lat), lat=lat, stereo=stereo,
                occl=occl, reg=reg, reg_cpu=reg_cpu, cpu=cpu, acc=acc, skips=skips,
                outline=outline, folder=folder, profile=profile)


def passes(r):
    return r["n"] > 0 and r["est"] / r["n"] >= MIN_ESTIMATED and pct(r["lat"], 95) < MAX_P95_MS


def skipped(r):
    return sum(c for (_, _, c) in r["skips"] or [])


def check(folder, name, speed, bag_frames, rate):
    """One run's line, and whether it passes the headroom test."""
    r = load(folder, bag_frames)
    ok = passes(r)
    skips = ("no counters on /diagnostics" if r["skips"] is None
             else f"{skipped(r)} frames skipped (/diagnostics)")
    say(f"{name} at speed {speed}: the player ran {float(r['cpu']['seconds']):.1f} s "
        f"(the bag's {bag_frames / rate:.1f} s / {speed} = "
        f"{bag_frames / rate / float(speed):.1f} s, after a 3 s delay); "
        f"estimated {r['est']} of {r['n']} ({100 * r['est'] / r['n']:.1f} %), p95 latency "
        f"{pct(r['lat'], 95):.1f} ms, {skips}: {'within' if ok else 'outside'} the headroom test "
        f"(>= {100 * MIN_ESTIMATED:g} %, p95 < {MAX_P95_MS:g} ms)")
    return ok


def report(out, rate, bag_frames, headroom, speeds, names):
    """OUT/bench-realtime.md, printed too, from the runs made (OUT/runs.txt)."""
    rows = {}
    with open(os.path.join(out, "runs.txt")) as f:
        for line in f:
            name, speed, folder = line.rstrip("\n").split("\t")
            rows[(name, speed)] = load(folder, bag_frames)
    runs = [(name, speed) for name in names for speed in speeds if (name, speed) in rows]

    lines = []
    w = lines.append
    if headroom:
        w(f"# Real-time replay at speeds {', '.join(speeds)} (headroom: up to the first that "
          f"fails), {rate:g} Hz")
    else:
        w(f"# Real-time replay at speed {speeds[0]}, {rate:g} Hz")
    w("")
    with open(os.path.join(out, "run.txt")) as f:
        w(f.read().strip().replace("\n", "  \n"))
    w("")
    w("| config | speed | frames | estimated | dropped | latency p50 [ms] | p95 | p99 | max | "
      "stereo p50 [ms] | occlusion p50 | registration p50 (in node) | manager CPU [% of a core] "
      "| player CPU | machine busy |")
    w("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name, speed in runs:
        r = rows[(name, speed)]
        w(f"| {name} | {speed} | {r['n']} | {r['est']} | {r['drop']} | {pct(r['lat'], 50):.1f} | "
          f"{pct(r['lat'], 95):.1f} | {pct(r['lat'], 99):.1f} | "
          f"{max(r['lat']) if r['lat'] else math.nan:.1f} | {median(r['stereo']):.1f} | "
          f"{median(r['occl']):.1f} | {median(r['reg']):.1f} ({median(r['reg_cpu']):.1f}) | "
          f"{float(r['cpu']['manager_cpu_pct']):.0f} | {float(r['cpu']['player_cpu_pct']):.0f} | "
          f"{float(r['cpu']['machine_busy_pct']):.0f}% of {r['cpu']['cores']} cores |")
    w("")
    w("Speed: times real time (rosbag play --rate). Stage times are arrival-to-arrival at the "
      "probe: stereo")
    w("from the images to /stereo/points2, occlusion to /aar/points_filtered, registration to")
    w("/aar/pose_estimate (in brackets: the node's own time).")
    w("")
    if headroom:
        w("Headroom: each configuration from the slowest speed up to the first that fails, that "
          "is with fewer than")
        w(f"{100 * MIN_ESTIMATED:g} % of the bag's frames estimated or a p95 latency of "
          f"{MAX_P95_MS:g} ms or more. The player's")
        w("time is from its start (it waits 3 s) to its end.")
        w("")
        w("| config | speed | player [s] | estimated | estimated [%] | dropped | latency p95 [ms] "
          "| skipped (/diagnostics) | passes |")
        w("|---|---:|---:|---:|---:|---:|---:|---:|---|")
        for name, speed in runs:
            r = rows[(name, speed)]
            w(f"| {name} | {speed} | {float(r['cpu']['seconds']):.1f} | {r['est']} | "
              f"{100 * r['est'] / r['n']:.1f} | {r['drop']} | {pct(r['lat'], 95):.1f} | "
              f"{'n/a' if r['skips'] is None else skipped(r)} | "
              f"{'yes' if passes(r) else 'no'} |")
        w("")
    w("Profile by region (A 175-70 m, B 70-38 m, C 38-32 m, eval's frames.csv): p50 / p95 [ms] "
      "of each")
    w("stage, arrival-to-arrival as above, over the frames that got an estimate.")
    w("")
    w("| config | speed | region | frames | latency | stereo | occlusion | registration | "
      "registration (in node) |")
    w("|---|---:|---|---:|---:|---:|---:|---:|---:|")
    for name, speed in runs:
        for region, st in sorted(rows[(name, speed)]["profile"].items()):
            def cell(k):
                return f"{pct(st.get(k, []), 50):.1f} / {pct(st.get(k, []), 95):.1f}"
            w(f"| {name} | {speed} | {region} | {len(st['latency'])} | {cell('latency')} | "
              f"{cell('stereo')} | {cell('occlusion')} | {cell('registration')} | "
              f"{cell('registration (in node)')} |")
    w("")
    w("Accuracy of the replay (eval's frames.csv): per region, frames estimated, mean |x| [m] and "
      "mean of the")
    w("largest of |roll|, |pitch|, |yaw| [deg].")
    w("")
    w("| config | speed | region | estimated | mean abs x [m] | mean max abs angle [deg] |")
    w("|---|---:|---|---:|---:|---:|")
    for name, speed in runs:
        for region in sorted(rows[(name, speed)]["acc"]):
            a = rows[(name, speed)]["acc"][region]
            x = a["x"] / a["e"] if a["e"] else math.nan
            ang = a["ang"] / a["e"] if a["e"] else math.nan
            w(f"| {name} | {speed} | {region} | {a['e']}/{a['n']} | {x:.3f} | {ang:.2f} |")
    w("")
    w("Frames skipped by the stages, by reason: the last value of each counter on /diagnostics "
      "whose key says")
    w("skipped, dropped, superseded or stale (a stage that came back adds its new counts), the "
      "non-zero ones.")
    w("\"Dropped\" above is the probe's: frames that got no estimate at all.")
    for name, speed in runs:
        r = rows[(name, speed)]
        w("")
        w(f"Skipped, {name} at speed {speed}:")
        w("")
        if r["skips"] is None:
            w(f"no /diagnostics recorded (see {os.path.join(r['folder'], 'skips.log')})")
            continue
        w("| status | counter | count |")
        w("|---|---|---:|")
        for status, key, count in r["skips"]:
            if count:
                w(f"| {status} | {key.replace('|', '/')} | {count} |")
        w(f"| total | | {skipped(r)} |")
        if r["outline"]:  # the outline ran (registration's counters): on how many frames
            o = r["outline"]
            w("")
            w(f"Outline (registration): aligned on {o.get('aligned', 0)} of {r['n']} frames, "
              f"fused on {o.get('fused', 0)}, {o.get('without its inputs', 0)} without its "
              "images.")
    w("")
    for name in reversed(names):
        for speed in speeds:
            if (name, speed) not in rows:
                continue
            r = rows[(name, speed)]
            w(f"realtime: {name} {r['n']} frames at {rate:g} Hz, speed {speed}, estimated "
              f"{r['est']}, dropped {r['drop']}, latency p50 {pct(r['lat'], 50):.1f} ms p95 "
              f"{pct(r['lat'], 95):.1f} ms p99 {pct(r['lat'], 99):.1f} ms")
    if headroom:
        for name in reversed(names):
            best = "none"
            for speed in speeds:  # tried in increasing order, up to the first that failed
                if (name, speed) not in rows or not passes(rows[(name, speed)]):
                    break
                best = speed
            w(f"headroom: {name} speed {best}")
    text = "\n".join(lines) + "\n"
    with open(os.path.join(out, "bench-realtime.md"), "w") as f:
        f.write(text)
    print(text, end="", flush=True)


# --- The runs --------------------------------------------------------------------------------

def run_txt(a, frames):
    sha = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                         text=True)
    commit = sha.stdout.strip() if sha.returncode == 0 else "unknown"
    if subprocess.run(["git", "diff", "--quiet"], cwd=ROOT, stdout=subprocess.DEVNULL,
                      stderr=subprocess.DEVNULL).returncode:
        commit += " (uncommitted changes)"
    model = ""
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    gib = subprocess.run(["free", "-g"], capture_output=True, text=True).stdout
    gib = next((line.split()[1] for line in gib.splitlines() if "Mem:" in line), "?")
    u = os.uname()
    command = (f"scripts/bench-realtime --configs {a.configs} --flight-path {a.flight_path} "
               f"--rate {a.rate}" + (f" --sim-config {a.sim_config}" if a.sim_config else "") +
               (" --headroom" if a.headroom else f" --speed {a.speeds[0]}") +
               f" --bag {a.bag} --out {a.out}" + (" --no-stage-times" if a.no_stage_times else ""))
    with open(os.path.join(a.out, "run.txt"), "w") as f:
        f.write(f"date (UTC): {workspace.utc_now()}\ncommit: {commit}\ncommand: {command}\n"
                f"bag: {a.bag} ({frames} frames)\n"
                f"machine: {cores()} cores ({model}), {gib} GiB, {u.sysname} {u.release}\n")


def cores():
    return len(os.sched_getaffinity(0))


def ticks(pid):
    """CPU time of `pid` so far (user + system) [clock ticks]; 0 once it is gone."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        return int(fields[11]) + int(fields[12])
    except (OSError, IndexError, ValueError):
        return 0


def machine_ticks():
    """(idle, total) of /proc/stat's cpu line (idle: idle and iowait)."""
    with open("/proc/stat") as f:
        v = [int(x) for x in f.readline().split()[1:9]]
    return v[3] + v[4], sum(v)


def alive(pid):
    try:
        os.kill(pid, 0)
        return True
    except OSError:
        return False


def child(parent, pattern):
    """The first child of `parent` whose command line matches `pattern` (pgrep -f), or None."""
    found = subprocess.run(["pgrep", "-P", str(parent), "-f", pattern], capture_output=True,
                           text=True).stdout.split()
    return int(found[0]) if found else None


def stop(proc):
    """A process of ours (the replay's roslaunch, the skips recorder), stopped as Ctrl-C would;
    what roslaunch started goes with it if it does not end within 30 s."""
    if proc is None or proc.poll() is not None:
        return
    try:
        proc.send_signal(signal.SIGINT)
        proc.wait(30)
    except subprocess.TimeoutExpired:
        found = subprocess.run(["pgrep", "-P", str(proc.pid)], capture_output=True,
                               text=True).stdout.split()
        for pid in found + [str(proc.pid)]:
            try:
                os.kill(int(pid), signal.SIGKILL)
            except OSError:
                pass
    proc.wait()


def replay(a, env, name, speed, frames, running):
    """One configuration at one speed: its folder filled; True when it passes the headroom
    test."""
    folder = os.path.join(a.out, name)
    if len(a.speeds) > 1:
        folder = os.path.join(folder, f"speed-{speed}")
    os.makedirs(folder, exist_ok=True)
    for f in ("probe.csv", "frames.csv", "skips.csv", "cpu.txt"):
        if os.path.lexists(os.path.join(folder, f)):
            os.remove(os.path.join(folder, f))
    say(f"{name}, {frames} frames at speed {speed} (log: {folder}/launch.log)")
    port = subprocess.run([os.path.join(ROOT, "scripts/ros-port")], capture_output=True,
                          text=True, check=True).stdout.strip()
    master = dict(env, ROS_MASTER_URI=f"http://localhost:{port}")
    with open(os.path.join(folder, "launch.log"), "w") as log:
        launch = subprocess.Popen(
            ["roslaunch", "-p", port, "launch/replay.launch", f"bag:={a.bag}",
             f"experiment:={name}", f"rigs:={','.join(a.rigs[name])}", f"rate:={speed}",
             "realtime:=true", f"output_dir:={folder}",
             f"expected_frames:={frames}", f"probe:={folder}/probe.csv",
             f"probe_stages:={'false' if a.no_stage_times else 'true'}"],
            stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, cwd=ROOT, env=master)
    running.append(launch)
    # CPU: the manager (all four stages) and the bag player, from the player's start to its end;
    # of this roslaunch (its children), not of another replay on the machine.
    manager = player = None
    for _ in range(120):
        manager = child(launch.pid, "__name:=aar_manager")
        player = child(launch.pid, "rosbag/play.*--clock")
        if manager and player:
            break
        time.sleep(0.5)
    if not player:
        fail(f"the replay did not start; see {folder}/launch.log", 1)
    with open(os.path.join(folder, "skips.log"), "w") as log:
        recorder = subprocess.Popen(
            [sys.executable, os.path.join(ROOT, "scripts/campaign"), "bench-realtime-skips",
             os.path.join(folder, "skips.csv")],
            stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, cwd=ROOT, env=master)
    running.insert(0, recorder)
    m0, p0, w0 = ticks(manager) if manager else 0, ticks(player), time.time()
    idle0, total0 = machine_ticks()
    # Setup, and twice the bag's length at this speed.
    limit = int(120 + 2 * frames / float(a.rate) / float(speed))
    m1, p1, w1, idle1, total1 = m0, p0, w0, idle0, total0
    for _ in range(limit * 2):
        if not alive(player):
            break
        m1, p1, w1 = ticks(manager) if manager else 0, ticks(player), time.time()
        idle1, total1 = machine_ticks()
        time.sleep(0.5)
    time.sleep(3)  # the last frames' estimates
    stop(recorder)
    stop(launch)
    running.clear()
    hz = os.sysconf("SC_CLK_TCK")
    s = w1 - w0 if w1 - w0 > 0 else 1
    i, t = idle1 - idle0, total1 - total0
    with open(os.path.join(folder, "cpu.txt"), "w") as f:
        f.write(f"manager_cpu_pct={100 * (m1 - m0) / hz / s:.1f}\n"
                f"player_cpu_pct={100 * (p1 - p0) / hz / s:.1f}\n"
                f"machine_busy_pct={100 * (t - i) / t if t > 0 else 0:.1f}\n"
                f"seconds={s:.1f}\ncores={cores()}\n")
    with open(os.path.join(a.out, "runs.txt"), "a") as f:
        f.write(f"{name}\t{speed}\t{folder}\n")
    return check(folder, name, speed, frames, float(a.rate))


def main(argv):
    workspace.PROG = "bench-realtime"
    a = parse(argv)
    if not a.no_build:
        workspace.setup_and_build()
    env = workspace.ros_env()
    a.out = a.out or os.path.join(ROOT, f"results/bench-realtime-{workspace.utc_stamp()}")
    os.makedirs(a.out, exist_ok=True)
    running = []  # what to stop when this ends, also on SIGINT or SIGTERM

    def terminate(signum, frame):
        sys.exit(143)
    signal.signal(signal.SIGTERM, terminate)
    try:
        frames = record(a, env)
        run_txt(a, frames)
        for f in glob.glob(os.path.join(ROOT, "config/*.yaml")) + \
                glob.glob(os.path.join(ROOT, "config/experiments/*.yaml")):
            try:
                shutil.copy(f, a.out)
            except OSError:
                pass
        if os.path.lexists(os.path.join(a.out, "runs.txt")):
            os.remove(os.path.join(a.out, "runs.txt"))
        for name in a.names:
            for speed in a.speeds:
                if not replay(a, env, name, speed, frames, running) and a.headroom:
                    break  # no faster speed for this configuration
        report(a.out, float(a.rate), frames, a.headroom, a.speeds, a.names)
    except KeyboardInterrupt:
        return 130
    finally:
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
        for proc in running:
            stop(proc)
    return 0
