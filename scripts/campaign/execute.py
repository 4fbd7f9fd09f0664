"""Flying one run: a private ROS master, the bounded roslaunch, its outcome recorded in the run's
folder (run.json), and one retry. A run whose run.json says ok with all its frames is done and
is not flown again (resuming)."""
import json
import os
import re
import shutil
import signal
import subprocess
import threading
import time

from campaign.workspace import log_lines as workspace_log_lines
from campaign.workspace import os_error, ros_env, write_file

ATTEMPTS = 2  # a failed run is retried once, then named in the report


def frames_recorded(out_dir):
    try:
        with open(os.path.join(out_dir, "frames.csv")) as f:
            return sum(1 for _ in f) - 1
    except OSError:
        return 0


def reason_of(run, campaign_dir):
    """Why a run that is not done failed, when its run.json says."""
    try:
        with open(os.path.join(campaign_dir, run.key, "run.json")) as f:
            return json.load(f).get("reason", "")
    except (OSError, ValueError):
        return ""


def is_done(run, campaign_dir):
    out = os.path.join(campaign_dir, run.key)
    try:
        with open(os.path.join(out, "run.json")) as f:
            status = json.load(f)
    except (OSError, ValueError):
        return False
    return status.get("status") == "ok" and frames_recorded(out) == run.frames


def tree_rss_mb(root):
    """Resident memory of `root` and all its descendants (a run's roslaunch and its nodes,
    which roslaunch starts in sessions of their own)."""
    page, parent, rss = os.sysconf("SC_PAGE_SIZE"), {}, {}
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open(f"/proc/{pid}/stat") as f:
                parent[int(pid)] = int(f.read().rsplit(")", 1)[1].split()[1])
            with open(f"/proc/{pid}/statm") as f:
                rss[int(pid)] = int(f.read().split()[1]) * page
        except (OSError, ValueError, IndexError):
            continue
    tree, grown = {root}, True
    while grown:
        more = {p for p, pp in parent.items() if pp in tree and p not in tree}
        tree |= more
        grown = bool(more)
    return sum(rss.get(p, 0) for p in tree) / 2**20


class Flight:
    """One attempt of one run; stop() ends it from another thread or a signal handler."""

    def __init__(self, run, out_dir, port):
        self.run, self.out_dir, self.port = run, out_dir, port
        self.proc = None
        self.peak_rss_mb = 0.0
        self.cpu_seconds = 0.0

    def fly(self):
        # The run's master and every node are on this host: they find each other as localhost
        # (a cluster node's own hostname may resolve to nothing, e.g. in a namespace of its own).
        env = dict(ros_env(), ROS_MASTER_URI=f"http://localhost:{self.port}",
                   ROS_HOSTNAME="localhost")
        env.pop("ROS_IP", None)
        with open(os.path.join(self.out_dir, "launch.log"), "w") as log:
            # Lockstep: each frame waits for its estimate, so results do not depend on speed.
            self.proc = subprocess.Popen(self.run.command(self.out_dir, self.port), stdout=log,
                                         stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                         env=env, start_new_session=True)
            done = threading.Event()
            sampler = threading.Thread(target=self._sample, args=(done,), daemon=True)
            sampler.start()
            # wait4, not wait: its rusage also holds every node the launch reaped (the run's CPU).
            _, status, usage = os.wait4(self.proc.pid, 0)
            self.proc.returncode = code = os.waitstatus_to_exitcode(status)
            self.cpu_seconds = usage.ru_utime + usage.ru_stime
            done.set()  # the sampler stops at once, not after its period
            sampler.join()
            return code

    def _sample(self, done, period=2.0):
        """The run's peak memory (every `period` s), for sizing cluster jobs. Never reaps: the
        launch's exit status and CPU time are fly()'s."""
        while not done.is_set():
            self.peak_rss_mb = max(self.peak_rss_mb, tree_rss_mb(self.proc.pid))
            if done.wait(period):
                return

    def stop(self):
        if self.proc is not None and self.proc.returncode is None:
            try:
                os.killpg(self.proc.pid, signal.SIGINT)
            except ProcessLookupError:
                pass


def execute(run, campaign_dir, port, stopping=lambda: False, on_flight=lambda f: None,
            about=None):
    """Flies `run` (retried once on failure) into campaign_dir/run.key; returns its status dict,
    also written to run.json there with `about` (e.g. the Slurm node). roslaunch exits 0 even
    when a required node dies: the frame count decides."""
    out = os.path.join(campaign_dir, run.key)
    status = {"status": "failed", "frames": run.frames, "attempts": 0, **(about or {})}
    for attempt in range(1, ATTEMPTS + 1):
        if stopping():
            status["status"] = "interrupted"
            break
        kept = _read(os.path.join(out, "launch.log")) if attempt > 1 else None
        shutil.rmtree(out, ignore_errors=True)
        os.makedirs(out)
        if kept is not None:  # the failed attempt's log stays with the run, named
            write_file(os.path.join(out, f"launch.attempt{attempt - 1}.log"), kept)
        flight = Flight(run, out, port)
        on_flight(flight)
        t0 = time.monotonic()
        code = flight.fly()
        rows = frames_recorded(out)
        status.update(attempts=attempt, recorded=rows, exit=code,
                      seconds=round(time.monotonic() - t0, 1),
                      cpu_seconds=round(flight.cpu_seconds, 1),
                      peak_rss_mb=round(flight.peak_rss_mb))
        if rows == run.frames:
            status["status"] = "ok"
            break
        status["status"] = "interrupted" if stopping() else "failed"
        status.setdefault("failed_attempts", []).append(
            {"attempt": attempt, "recorded": rows, "exit": code,
             "log": f"launch.attempt{attempt}.log"})
        reason = refusal(out)
        if reason:  # a stage refused to start: the same again on a retry
            status["reason"] = reason
            break
    if status["status"] != "ok" and status.get("failed_attempts"):
        status["failed_attempts"][-1]["log"] = "launch.log"  # the last attempt's is not renamed
    try:
        write_file(os.path.join(out, "run.json"), json.dumps(status, indent=1))
    except OSError as e:  # not recorded is not done: the run is flown again on --resume
        status.update(status="failed", reason=f"its record could not be written: {os_error(e)}")
    return status


# What a launch that could not start says: a stage refusing its parameters or model (FATAL,
# aar_ros_common::EndProcessOnStartFailure), roslaunch refusing the launch (an experiment's
# unknown namespace, check_experiment.py; a missing file).
REFUSALS = re.compile(r"\[FATAL\].*|check_experiment: .*|RLException: .*|"
                      r"ERROR: cannot launch node.*")


def log_lines(out_dir):
    """The run's launch.log, line by line without colour codes ([] when there is none)."""
    return workspace_log_lines(os.path.join(out_dir, "launch.log"))


def refusal(out_dir):
    """The first line of the run's log that says why it could not start, or ""."""
    for line in log_lines(out_dir):
        found = REFUSALS.search(line)
        if found:
            return found.group(0).strip()[:400]
    return ""


def _read(path):
    try:
        with open(path, errors="replace") as f:
            return f.read()
    except OSError:
        return None


def failed_attempts(status):
    """What each failed attempt of a run got to ("attempt 1: 123 of 300 frames, exit -9, its
    log launch.attempt1.log"), for a run that was retried; first, a Slurm requeue (its node
    lost), whose attempt's log the task kept in the campaign's slurm/ folder."""
    requeued = status.get("slurm_restarts", 0)
    lost = ([f"requeued by Slurm {requeued} time(s) (its node lost or the job preempted; the "
             f"lost attempt's log in slurm/), then flown on {status.get('node', '?')}"]
            if requeued else [])
    return lost + [f"attempt {a['attempt']}: {a['recorded']} of {status['frames']} frames, exit "
            f"{a['exit']}, its log {a['log']}" for a in status.get("failed_attempts", [])]


def retried(run, campaign_dir):
    """A finished run's failed attempts (failed_attempts) from its run.json; [] if none."""
    try:
        with open(os.path.join(campaign_dir, run.key, "run.json")) as f:
            status = json.load(f)
    except (OSError, ValueError):
        return []
    return failed_attempts(status) if status.get("status") == "ok" else []


def describe(status):
    if status["status"] == "ok":
        retried = (f" (on its retry; {'; '.join(failed_attempts(status))})"
                   if status["attempts"] > 1 else "")
        return f"ok{retried}, {status['seconds']:.0f} s ({status['cpu_seconds']:.0f} s CPU)"
    why = f": {status['reason']}" if status.get("reason") else ""
    return (f"{status['status'].upper()} ({status.get('recorded', 0)} of {status['frames']} "
            f"frames, {status['attempts']} attempt(s)){why}")


def eval_lines(run, campaign_dir, lines=12):
    """eval's closing lines of a run (its frame count and region errors), for the console."""
    found = [line for line in log_lines(os.path.join(campaign_dir, run.key))
             if re.search(r"eval: (frame|region|wrote)", line)]
    return "\n".join("  " + line[line.find("eval: "):].rstrip() for line in found[-lines:])


def log_tail(run, campaign_dir, lines=15):
    tail = log_lines(os.path.join(campaign_dir, run.key))[-lines:]
    return "\n".join(line.rstrip("\n") for line in tail)
