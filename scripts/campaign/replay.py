"""Replays a recorded flight (scripts/make-sample-bag, or pipeline.launch record:=FILE) through
stereo -> occlusion -> registration -> eval on the bag's clock, and writes DIR/report.md as the
main job does. Checks the bag first: a missing topic, a bag without camera infos, or a broken
(truncated, unindexed) bag is named and the script exits 2 without starting anything.
  scripts/replay BAG [--experiment E] [--rate R] [--out DIR] [--compare LIVE.csv | --no-compare]
                 [--tf-outage START,DURATION] [--no-truth] [--no-build]
A bag of raw images (image_raw and their calibrated camera infos, as a rig's drivers publish
them) is rectified by image_proc in front of aar_stereo (replay.launch rectify:=true).
Rigs (issue 44): the bag's are those with left images (/R/left/image_rect, stereo first); the
experiment's (its sim rigs) are replayed (replay.launch rigs:=), a bag's further rig that the
experiment does not fly is left out; a bag without one of the experiment's rigs is refused.
--no-truth: the bag has no truth (a rig's flight): no eval and no error tables; every estimate
goes to DIR/E/estimates.csv and DIR/report.md counts them.
--compare (default: BAG with .EXPERIMENT.live.csv, if present) prints the largest per-frame
difference between the replay's errors and the live run's. --tf-outage injects a fault: tf stops
at bag time START [s] for DURATION [s], then returns.
Exit status: 0 every frame processed and estimated; 3 every frame processed, some without an
estimate (counted, with the estimates that came too late); 1 frames lost or without truth, no
report, or a difference from the live run; 2 a bad argument or bag.

(scripts/replay is a wrapper around this module: python3 scripts/campaign replay.)"""
import csv
import glob
import os
import re
import shutil
import signal
import subprocess
import sys
import time

from campaign import arguments, bag, workspace
from campaign.plan import experiment_rigs
from campaign.workspace import ROOT, Refused, fail, say


def parse(argv):
    p = arguments.Parser("replay", __doc__)
    p.add_argument("bags", nargs="*", metavar="BAG")
    p.add_argument("--experiment", default="flight")
    p.add_argument("--rate", default="0.25")
    p.add_argument("--out", default="")
    p.add_argument("--compare", default="")
    p.add_argument("--no-compare", action="store_true")
    p.add_argument("--no-truth", action="store_true")
    p.add_argument("--tf-outage", default=None, metavar="START,DURATION")
    p.add_argument("--no-build", action="store_true", help="for tests, which run inside a build")
    a = p.parse_args(argv)
    caller = os.getcwd()
    arguments.positive("--rate", a.rate, 100)
    a.outage_start, a.outage_duration = "-1", "0"
    if a.tf_outage is not None:
        start, _, duration = a.tf_outage.partition(",")
        if not (re.fullmatch(r"[0-9]+([.][0-9]+)?", start) and
                re.fullmatch(r"[0-9]+([.][0-9]+)?", duration)):
            fail(f"--tf-outage takes START,DURATION in seconds of bag time, not '{a.tf_outage}'")
        a.outage_start, a.outage_duration = start, duration
    if len(a.bags) > 1:
        fail("one bag at a time")
    if not a.bags:
        p.print_usage(sys.stderr)
        sys.exit(2)
    a.bag = arguments.absolute(a.bags[0], caller)
    a.out = arguments.absolute(a.out, caller)
    a.compare = arguments.absolute(a.compare, caller)
    if not os.path.isfile(a.bag):
        fail(f"bag '{a.bag}' does not exist")
    if not os.path.isfile(os.path.join(ROOT, "config/experiments", a.experiment + ".yaml")):
        fail(f"no experiment '{a.experiment}'")
    # The live run's errors, when it ran this experiment (scripts/make-sample-bag writes them).
    live = (a.bag[:-4] if a.bag.endswith(".bag") else a.bag) + f".{a.experiment}.live.csv"
    if not a.compare and os.path.isfile(live):
        a.compare = live
    if a.no_compare or a.no_truth:
        a.compare = ""
    if a.compare:  # eval's frames.csv of a live run, not any CSV
        if not os.path.isfile(a.compare):
            fail(f"--compare '{a.compare}' does not exist")
        with open(a.compare, errors="replace") as f:
            header = f.readline().rstrip("\n")
        columns = header.split(",")
        if not all(c in columns for c in ("t", "estimated", "x_m")):
            fail(f"--compare '{a.compare}' is not eval's frames.csv of a live run (its columns: "
                 f"{header[:60]}; a flight path?): give the live run's frames.csv, or "
                 "BAG.EXPERIMENT.live.csv as scripts/make-sample-bag writes it")
    return a


def rows_of(path):
    """Rows of a CSV with a header line (0 if there is no file)."""
    try:
        with open(path) as f:
            return sum(1 for _ in f) - 1
    except OSError:
        return 0


def column_is_one(path, column):
    """Rows (after the header) whose COLUMN (from 1) is 1."""
    try:
        with open(path) as f:
            next(f, None)
            return sum(1 for line in f if _number(line.rstrip("\n").split(","), column) == 1)
    except OSError:
        return 0


def _number(fields, column):
    try:
        return float(fields[column - 1])
    except (IndexError, ValueError):
        return None


def log_end(path):
    for line in workspace.log_lines(path)[-15:]:
        print(line, file=sys.stderr)


def run_txt(a, frames, images):
    sha = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                         text=True)
    gib = subprocess.run(["free", "-g"], capture_output=True, text=True).stdout
    gib = next((line.split()[1] for line in gib.splitlines() if "Mem:" in line), "?")
    u = os.uname()
    command = (f"scripts/replay {a.bag} --experiment {a.experiment} --rate {a.rate} --out {a.out}"
               + ("" if a.outage_duration == "0" else
                  f" --tf-outage {a.outage_start},{a.outage_duration}")
               + (" --no-truth" if a.no_truth else ""))
    with open(os.path.join(a.out, "run.txt"), "w") as f:
        f.write(f"date (UTC): {workspace.utc_now()}\n"
                f"commit: {sha.stdout.strip() if sha.returncode == 0 else 'unknown'}\n"
                f"command: {command}\nbag: {a.bag} ({frames} frames of {images}"
                f"{', rigs ' + ','.join(a.rigs) if len(a.rigs) > 1 else ''})\n"
                f"machine: {len(os.sched_getaffinity(0))} cores, {gib} GiB, {u.sysname} "
                f"{u.release}\n")


def stop(launch):
    """roslaunch stopped as Ctrl-C would; killed if it has not ended within 30 s."""
    if launch.poll() is None:
        launch.send_signal(signal.SIGINT)
        try:
            launch.wait(30)
        except subprocess.TimeoutExpired:
            launch.kill()
    launch.wait()


def fly(a, env, frames, images, rectify):
    """The graph on its own master; stopped once every frame is in eval's ledger.csv (or, with no
    truth, in estimates.csv), or at a time limit."""
    folder = os.path.join(a.out, a.experiment)
    port = subprocess.run([os.path.join(ROOT, "scripts/ros-port")], capture_output=True,
                          text=True, check=True).stdout.strip()
    limit = int(60 + frames * 0.1 / float(a.rate) * 2)
    say(f"{frames} frames from {a.bag} at rate {a.rate} (log: {folder}/launch.log)")
    with open(os.path.join(folder, "launch.log"), "w") as log:
        launch = subprocess.Popen(
            ["roslaunch", "-p", port, "launch/replay.launch", f"bag:={a.bag}",
             f"experiment:={a.experiment}", f"rate:={a.rate}", f"output_dir:={folder}",
             f"expected_frames:={frames}", f"tf_outage_start:={a.outage_start}",
             f"tf_outage_duration:={a.outage_duration}",
             f"rectify:={'true' if rectify else 'false'}", f"rigs:={','.join(a.rigs)}",
             f"truth:={'false' if a.no_truth else 'true'}"],
            stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, cwd=ROOT,
            env=dict(env, ROS_MASTER_URI=f"http://localhost:{port}"))

    def terminate(signum, frame):
        sys.exit(143)
    signal.signal(signal.SIGTERM, terminate)
    try:
        # eval settles a frame on its estimate or a stage's drop (a frame lost unseen after
        # eval's settle_after, 10 s): wait until every frame has its outcome in ledger.csv, then
        # stop the graph (the frames eval never heard of are counted afterwards).
        last_settled, last_change = 0, time.monotonic()
        for _ in range(limit * 2):
            if a.no_truth:
                # No eval: one estimate a frame, each written as it comes.
                if rows_of(os.path.join(folder, "estimates.csv")) >= frames:
                    break
            else:
                settled = rows_of(os.path.join(folder, "ledger.csv"))
                if settled >= frames:
                    break
                # Frames eval never heard of get no row: 15 s without a new one (eval's
                # settle_after is 10 s), and the rest never come.
                if settled != last_settled:
                    last_settled, last_change = settled, time.monotonic()
                if settled > 0 and time.monotonic() - last_change >= 15:
                    break
            if launch.poll() is not None:
                break
            time.sleep(0.5)
    finally:
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
        stop(launch)


def without_truth(a, frames):
    """Estimates only: how many frames got one, and with a pose; no error tables without
    truth."""
    folder = os.path.join(a.out, a.experiment)
    try:
        with open(os.path.join(folder, "estimates.csv")) as f:
            rows = list(csv.DictReader(f))
    except OSError:
        rows = []
    valid = [r for r in rows if r["valid"] == "1"]
    ranges = [float(r["range_m"]) for r in valid]
    with open(os.path.join(a.out, "run.txt")) as f:
        run = f.read()
    lines = [f"# Replay without truth: {a.experiment}", "", "```", run.rstrip(), "```", "",
             "The bag has no truth (scripts/replay --no-truth): estimates only, no error tables.",
             f"Every estimate is in `{a.experiment}/estimates.csv` (pose in the tanker frame, "
             "fitness, timing).", "",
             "| frames | estimates | with a pose | range of the poses [m] |",
             "|---:|---:|---:|---|",
             f"| {frames} | {len(rows)} | {len(valid)} | "
             + (f"{max(ranges):.1f} to {min(ranges):.1f} |" if ranges else "none |")]
    with open(os.path.join(a.out, "report.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    rows = rows_of(os.path.join(folder, "estimates.csv"))
    estimated = column_is_one(os.path.join(folder, "estimates.csv"), 2)
    say(f"wrote {a.out}/report.md ({rows} of {frames} frames estimated, {estimated} with a "
        "pose; no truth, so no errors)")
    if rows < frames:
        say(f"only {rows} of {frames} frames got an estimate (a stage down, or the graph behind "
            f"the bag at rate {a.rate}: a slower --rate); the end of the log:", error=True)
        log_end(os.path.join(folder, "launch.log"))
        return 1
    if estimated < rows:
        say(f"{rows - estimated} of {rows} frames have no pose", error=True)
        return 3
    return 0


def compare(live_csv, replay_csv):
    """The largest difference between the replay's errors and the live run's, printed; True
    when every live frame was compared and none differs in having an estimate."""
    def load(p):
        with open(p) as f:
            return {round(float(r["t"]), 3): r for r in csv.DictReader(f)}
    live, replay = load(live_csv), load(replay_csv)
    cols = ["x_m", "y_m", "z_m", "roll_deg", "pitch_deg", "yaw_deg"]
    common = sorted(set(live) & set(replay))
    worst = {c: 0.0 for c in cols}
    estimated_differ = 0
    for t in common:
        if live[t]["estimated"] != replay[t]["estimated"]:
            estimated_differ += 1
            continue
        if live[t]["estimated"] != "1":
            continue
        for c in cols:
            worst[c] = max(worst[c], abs(float(live[t][c]) - float(replay[t][c])))
    pos, ang = max(worst[c] for c in cols[:3]), max(worst[c] for c in cols[3:])
    say(f"against the live run ({live_csv}): {len(common)} of {len(live)} frames compared, "
        f"{estimated_differ} differ in having an estimate; largest difference {pos:.3g} m, "
        f"{ang:.3g} deg")
    return len(common) == len(live) and estimated_differ == 0


def with_truth(a, env, frames):
    folder = os.path.join(a.out, a.experiment)
    log = os.path.join(folder, "launch.log")
    rows = rows_of(os.path.join(folder, "frames.csv"))
    estimated = column_is_one(os.path.join(folder, "frames.csv"), 4)
    lines = workspace.log_lines(log)
    late = sum(1 for line in lines if "came after its frame was settled" in line)
    no_truth = sum(1 for line in lines if "no truth for frame" in line)
    subprocess.run([sys.executable, os.path.join(ROOT, "src/aar_eval/scripts/plot_errors.py"),
                    a.out, a.experiment], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                   env=env, cwd=ROOT)
    status = 0
    if subprocess.run([workspace.tool("aar_eval", "make_report"), a.out, a.experiment],
                      stdout=subprocess.DEVNULL, env=env, cwd=ROOT).returncode == 0:
        say(f"wrote {a.out}/report.md ({rows} of {frames} frames processed, {estimated} with an "
            "estimate)")
    else:
        status = 1
    if no_truth > 0:
        say(f"{no_truth} frames had no truth (tf to the truth frame missing at their stamp) and "
            "are not scored; eval names each in the log (a flight without truth, such as a "
            "rig's: --no-truth)", error=True)
        status = 1
    # The frame ledger: every frame sent has one outcome in ledger.csv, or never reached eval.
    ledger_rows = rows_of(os.path.join(folder, "ledger.csv"))
    ledger = next((m.group(0)[len("eval: ledger: "):] for m in
                   (re.search(r"eval: ledger: .*", line) for line in lines) if m), "")
    say(f"{ledger}; {frames - ledger_rows} of {frames} frames sent never reached eval")
    if rows + no_truth != frames:
        say(f"only {rows + no_truth} of {frames} frames reached eval; the end of the log:",
            error=True)
        log_end(log)
        status = 1
    if estimated < rows:
        say(f"{rows - estimated} of {rows} frames have no estimate", error=True)
        if late > 0:
            say(f"{late} estimates came after their frame was settled and were not counted: the "
                f"graph fell behind the bag at rate {a.rate} (a slower --rate, or fewer runs at "
                "once)", error=True)
        status = status or 3
    if a.compare:
        try:
            if not compare(a.compare, os.path.join(folder, "frames.csv")):
                status = 1
        except (OSError, KeyError, ValueError) as e:
            say(f"cannot compare with the live run: {e}", error=True)
            status = 1
    return status


def rigs_for(a, held):
    """The experiment's rigs (its sim rigs), each of which the bag must hold (HELD); a further
    rig of the bag's that the experiment does not fly is left out."""
    try:
        wanted = experiment_rigs(a.experiment).split(",")
    except Refused as e:
        fail(str(e))
    if any(r not in held for r in wanted):
        fail(f"experiment '{a.experiment}' flies the rigs {','.join(wanted)}, but bag '{a.bag}' "
             f"holds {','.join(held) or 'no rig'} (a rig R: /R/left/image_rect): record one "
             f"with them (pipeline.launch rigs:={','.join(wanted)} record:=FILE), or replay an "
             "experiment of the bag's rigs")
    if len(held) > len(wanted):
        say(f"the bag holds the rigs {','.join(held)}; {a.experiment} flies "
            f"{','.join(wanted)}: the others are not replayed")
    return wanted


def main(argv):
    workspace.PROG = "replay"
    a = parse(argv)
    a.out = a.out or os.path.join(ROOT, f"results/replay-{workspace.utc_stamp()}")
    if not a.no_build:
        workspace.setup_and_build()
    env = workspace.ros_env()
    # The bag: readable, and holding what the graph needs.
    info = bag.read(a.bag)
    a.rigs = rigs_for(a, bag.rigs_of(info))
    images, rectify, frames = bag.check(a.bag, a.rigs, info)
    if rectify:
        if len(a.rigs) > 1:
            fail("the bag holds raw images: a further rig's are not rectified (launch/include/"
                 "rig.launch has no image_proc)")
        say("the bag holds raw images (image_raw): image_proc rectifies them with the bag's "
            "camera infos in front of aar_stereo")
    folder = os.path.join(a.out, a.experiment)
    os.makedirs(folder, exist_ok=True)
    for f in (os.path.join(folder, n) for n in ("frames.csv", "ledger.csv", "estimates.csv")):
        if os.path.lexists(f):
            os.remove(f)  # not a previous replay's
    if os.path.lexists(os.path.join(a.out, "report.md")):
        os.remove(os.path.join(a.out, "report.md"))
    for f in glob.glob(os.path.join(ROOT, "config/*.yaml")):
        try:
            shutil.copy(f, folder)
        except OSError:
            pass
    run_txt(a, frames, images)
    try:
        fly(a, env, frames, images, rectify)
    except KeyboardInterrupt:
        return 130
    return without_truth(a, frames) if a.no_truth else with_truth(a, env, frames)
