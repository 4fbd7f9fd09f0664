#!/usr/bin/env python3
"""launch-prefix for the node whose end is the launch's end; give the node required="true" too:
  <node ... required="true" launch-prefix="$(find aar_ros_common)/scripts/end_launch_on_exit.py"/>
Runs the node as a child. When it exits 0 on its own, this interrupts roslaunch (its parent) as
Ctrl-C does, so the launch ends quietly: `required` alone prints "REQUIRED process has died" even
for a clean end. When the node fails, this exits with the node's code and `required` ends the
launch, naming the failure. SIGINT, SIGTERM and SIGHUP (roslaunch stopping) go on to the node."""
import os
import signal
import subprocess
import sys
import time


def parent_is_roslaunch():
    try:
        with open(f"/proc/{os.getppid()}/cmdline", "rb") as f:
            return b"roslaunch" in f.read()
    except OSError:
        return False


def main():
    if len(sys.argv) < 2:
        sys.exit("usage: end_launch_on_exit.py NODE [ARGS...]")
    child = subprocess.Popen(sys.argv[1:])
    stopped = False

    def forward(sig, _frame):
        nonlocal stopped
        stopped = True
        if child.returncode is None:
            child.send_signal(sig)

    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(sig, forward)
    code = child.wait()
    if code < 0:  # killed by a signal: the shell's convention
        code = 128 - code
    if code != 0 or stopped or not parent_is_roslaunch():
        return code
    os.kill(os.getppid(), signal.SIGINT)
    # roslaunch now stops every node, this one too; exiting first would count as a death.
    deadline = time.monotonic() + 30.0
    while not stopped and time.monotonic() < deadline:
        time.sleep(0.05)
    return 0


if __name__ == "__main__":
    sys.exit(main())
