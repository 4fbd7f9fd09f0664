"""Headless rviz captures: replays BAG through the graph with rviz (config/rviz/aar.rviz) on a
virtual X server and writes DIR/frame_KKK.png after the chosen frames' estimates.
  scripts/capture BAG [--frames 10,20] [--out DIR] [--no-build]

(scripts/capture is a wrapper around this module: python3 scripts/campaign capture.)"""
import glob
import os
import re
import signal
import subprocess
import sys
import time

from campaign import arguments, bag, workspace
from campaign.workspace import ROOT, fail, say


def parse(argv):
    p = arguments.Parser("capture", __doc__)
    p.add_argument("bags", nargs="*", metavar="BAG")
    p.add_argument("--frames", default="10,20")
    p.add_argument("--out", default="")
    p.add_argument("--no-build", action="store_true")
    a = p.parse_args(argv)
    caller = os.getcwd()
    a.bag = arguments.absolute(a.bags[-1], caller) if a.bags else ""
    a.out = arguments.absolute(a.out, caller)
    if not os.path.isfile(a.bag):
        fail(f"bag '{a.bag}' does not exist")
    if not re.fullmatch(r"[1-9][0-9]*(,[1-9][0-9]*)*", a.frames):
        fail("--frames takes frame numbers from 1, like 10,20")
    a.numbers = sorted({int(k) for k in a.frames.split(",")})  # ascending, once each
    a.frames = ",".join(str(k) for k in a.numbers)
    return a


def main(argv):
    workspace.PROG = "capture"
    a = parse(argv)
    a.out = a.out or os.path.join(ROOT, f"results/capture-{workspace.utc_stamp()}")
    if not a.no_build:
        workspace.setup_and_build()
    env = workspace.ros_env()
    _, _, bag_frames = bag.check(a.bag)
    last = a.numbers[-1]
    if last > bag_frames:
        fail(f"--frames asks for frame {last}, but '{a.bag}' holds {bag_frames} frames")
    os.makedirs(a.out, exist_ok=True)
    for f in glob.glob(os.path.join(a.out, "frame_*.png")):
        os.remove(f)  # a previous capture's must not count
    display = 100
    while os.path.exists(f"/tmp/.X11-unix/X{display}") or os.path.exists(f"/tmp/.X{display}-lock"):
        display += 1
    with open(os.path.join(a.out, "xvfb.log"), "w") as log:
        xvfb = subprocess.Popen(["Xvfb", f":{display}", "-screen", "0", "1400x900x24",
                                 "-nolisten", "tcp"], stdout=log, stderr=subprocess.STDOUT,
                                stdin=subprocess.DEVNULL)
    try:
        return capture(a, env, display, xvfb)
    finally:
        xvfb.kill()
        xvfb.wait()


def capture(a, env, display, xvfb):
    port = subprocess.run([os.path.join(ROOT, "scripts/ros-port")], capture_output=True,
                          text=True, check=True).stdout.strip()
    time.sleep(1)
    if xvfb.poll() is not None:
        with open(os.path.join(a.out, "xvfb.log"), errors="replace") as f:
            tail = "\n".join(f.read().splitlines()[-3:])
        fail(f"Xvfb did not start: {tail}", 1)
    limit = 120 + a.numbers[-1] * 3
    log_path = os.path.join(a.out, "launch.log")
    say(f"frames {a.frames} of {a.bag} (log: {log_path})")
    # `timeout` runs roslaunch in a process group of its own, which a terminal's SIGINT does not
    # reach; SIGINT or SIGTERM here is passed on to timeout, which passes it on to roslaunch, and
    # roslaunch stops its nodes.
    interrupted, running = [], []

    def stop(signum, frame):
        interrupted.append(signal.Signals(signum).name)
        for p in running:
            try:
                p.send_signal(signal.SIGINT)
            except OSError:
                pass
    for s in (signal.SIGINT, signal.SIGTERM):
        signal.signal(s, stop)
    with open(log_path, "w") as log:
        launch = subprocess.Popen(
            ["timeout", "--signal=INT", "--kill-after=40", str(limit), "roslaunch", "-p", port,
             "launch/capture.launch", f"bag:={a.bag}", f"frames:={a.frames}",
             f"output_dir:={a.out}"], stdout=log, stderr=subprocess.STDOUT,
            stdin=subprocess.DEVNULL, cwd=ROOT,
            env=dict(env, DISPLAY=f":{display}", ROS_MASTER_URI=f"http://localhost:{port}"))
    running.append(launch)
    if interrupted:  # before it was there to be told
        launch.send_signal(signal.SIGINT)
    launch.wait()
    if interrupted:
        say(f"{interrupted[0]}: stopped (roslaunch and its nodes ended; log: {log_path})",
            error=True)
        return 130
    missing = False
    for k in a.numbers:
        f = os.path.join(a.out, f"frame_{k:03d}.png")
        if os.path.isfile(f) and os.path.getsize(f) > 0:
            say(f"wrote {f}")
        elif os.path.isfile(f):
            avail = subprocess.run(["df", "-h", "--output=avail", a.out], capture_output=True,
                                   text=True).stdout.splitlines()
            say(f"{f} is empty: was the disk full? ({avail[-1] if avail else '?'} left)",
                error=True)
            missing = True
        else:
            say(f"no {f}", error=True)
            missing = True
    if missing:
        # The cause when a node said it (a PNG that could not be written), else the end of the
        # log.
        lines = workspace.log_lines(log_path)
        fatal = [line for line in lines if "[FATAL]" in line][:3]
        print("\n".join(fatal or lines[-15:]), file=sys.stderr)
        return 1
    return 0
