"""What a Slurm job runs: `task DIR INDEX` flies run INDEX of campaign DIR on a ROS master of
its own; `merge DIR` writes the campaign's reports once the array has ended (afterany)."""
import json
import os
import signal
import sys
import time

from campaign import workspace
from campaign.campaign import Campaign
from campaign.drive import finish, record_merge
from campaign.execute import describe, execute, is_done
from campaign.workspace import Refused, free_ports, os_error, say


def task(out, index):
    campaign = Campaign.load(out)
    if not 0 <= index < len(campaign.runs):
        raise Refused(f"task {index}: campaign {out} has runs 0 to {len(campaign.runs) - 1}")
    run = campaign.runs[index]
    node = os.environ.get("SLURMD_NODENAME", "")
    restarts = int(os.environ.get("SLURM_RESTART_COUNT", "0") or 0)
    say(f"run {index}: {run.key}" + (f" on node {node}" if node else "") + (
        f" (requeued {restarts} time(s): its node was lost or the job preempted)"
        if restarts else ""))
    if is_done(run, out):
        say(f"{run.key}: done already")
        return 0
    flights, stopping = [], []

    def cancelled(signum, frame):  # scancel, or the time limit: end the graph, say so
        if not stopping:  # at once: Slurm kills what is left after its KillWait
            say(f"{run.key}: {signal.Signals(signum).name}: stopping the run (cancelled)")
        stopping.append(signum)
        for f in flights:
            f.stop()
    signal.signal(signal.SIGTERM, cancelled)
    signal.signal(signal.SIGINT, cancelled)
    if restarts:
        keep_lost_log(out, run, restarts)
    port = free_ports(1, seed=os.getpid() + 7 * index)[0]
    about = {"node": node, "slurm_restarts": restarts} if node else None
    status = execute(run, out, port, lambda: bool(stopping), flights.append, about)
    say(f"{run.key}: {run.frames} frames, {describe(status)}"
        f"{' (cancelled)' if stopping else ''}")
    return 0 if status["status"] == "ok" else 1


def keep_lost_log(out, run, restarts):
    """A requeued run's folder holds what its lost attempt wrote; its launch.log goes to
    DIR/slurm/ (the run's folder is flown afresh) and is named."""
    log = os.path.join(out, run.key, "launch.log")
    if os.path.isfile(log):
        kept = os.path.join(out, "slurm", f"{run.key.replace('/', '-')}.lost{restarts}.log")
        os.replace(log, kept)
        say(f"{run.key}: the lost attempt's log kept as {os.path.relpath(kept, out)}")


def merge(out):
    campaign = Campaign.load(out)
    try:
        with open(os.path.join(out, "slurm", "jobs.json")) as f:
            jobs = json.load(f)
        seconds, flown = time.time() - jobs["submitted"], len(jobs["indices"])
        engine = f"slurm, job array {', '.join(jobs['arrays'])}"
    except (OSError, ValueError, KeyError):
        seconds, flown, engine = 0.0, 0, "slurm"
    status = finish(campaign, engine, seconds, flown)
    record_merge(campaign, status, os.path.join(
        out, {"run": "report.md", "suite": "suite.md", "realism": "worlds.md"}[campaign.kind]))
    return status


def main(argv):
    workspace.PROG = f"campaign {argv[0]}"
    try:
        if argv[0] == "task" and len(argv) == 3 and argv[2].isdigit():
            return task(argv[1], int(argv[2]))
        if argv[0] == "merge" and len(argv) == 2:
            return merge(argv[1])
        raise Refused("usage: campaign task DIR INDEX | campaign merge DIR")
    except Refused as e:
        print(f"{workspace.PROG}: {e}", file=sys.stderr)
        return 2
    except OSError as e:  # a full or read-only disk: named in the task's log
        print(f"{workspace.PROG}: {os_error(e)}", file=sys.stderr)
        return 1
