"""The Slurm engine: one job-array task per run (each flies its run on a ROS master of its own
on whichever node Slurm gives it), and a merge job, dependent on the whole array, that writes
the same reports as the local engine. Jobs reach the workspace and the campaign folder on a path
every node shares; nothing else is assumed of the cluster (docs/CLUSTER.md)."""
import json
import os
import shutil
import signal
import subprocess
import sys
import time

from campaign.execute import is_done
from campaign.workspace import ROOT, Refused, say, write_file

DRIVER = os.path.join(ROOT, "scripts/campaign")
POLL_SECONDS = 5


def command(name):
    """A Slurm client command: from AAR_SLURM_BIN when set (a cluster's own install, e.g.
    /opt/slurm/bin), else from PATH; None when missing."""
    return shutil.which(name, path=os.environ.get("AAR_SLURM_BIN") or None)


def _slurm(args, what):
    args = [command(args[0]) or args[0]] + args[1:]
    p = subprocess.run(args, capture_output=True, text=True)
    if p.returncode != 0:
        raise Refused(f"{what} failed: {(p.stderr or p.stdout).strip()}")
    return p.stdout.strip()


def check(partition):
    """Slurm's client is installed, a controller answers, and the partition exists."""
    for name in ("sbatch", "squeue", "sinfo"):
        if command(name) is None:
            where = os.environ.get("AAR_SLURM_BIN") or "PATH"
            raise Refused(f"--engine slurm needs Slurm's {name}, which is not on {where} (Debian "
                          f"package slurm-client: apt-get install slurm-client; with no cluster "
                          f"configured, the driver installs and starts a single-node one here)")
    listed = _slurm(["sinfo", "-h", "-o", "%R"], "sinfo (is a Slurm controller reachable? "
                    "SLURM_CONF=" + os.environ.get("SLURM_CONF", "/etc/slurm/slurm.conf") + ")")
    partitions = sorted(set(listed.split()))
    if partition and partition not in partitions:
        raise Refused(f"--partition: no partition '{partition}' on this cluster (partitions: "
                      f"{', '.join(partitions) or 'none'})")


def array_spec(indices):
    """Slurm's --array list: runs of consecutive indices as ranges (0-3,7,9-10)."""
    parts, start = [], None
    for i, k in enumerate(indices):
        if start is None:
            start = k
        if i + 1 == len(indices) or indices[i + 1] != k + 1:
            parts.append(str(start) if start == k else f"{start}-{k}")
            start = None
    return ",".join(parts)


def max_array_size():
    """The cluster's MaxArraySize (task ids run from 0 to it minus 1); Slurm's default 1001."""
    p = subprocess.run([command("scontrol") or "scontrol", "show", "config"], capture_output=True,
                       text=True)
    for line in p.stdout.splitlines():
        key, _, value = line.partition("=")
        if key.strip() == "MaxArraySize" and value.strip().isdigit():
            return int(value)
    return 1001


def submit(campaign, indices, partition, cpus_per_task, max_parallel):
    """Submits `indices` (places in campaign.runs) as job arrays, as many as MaxArraySize asks
    (array k holds runs k*size to (k+1)*size-1; task id = index - k*size), and the merge job
    after them all; returns (array ids, merge id), also written to DIR/slurm/jobs.json."""
    folder = os.path.join(campaign.out, "slurm")
    os.makedirs(folder, exist_ok=True)
    common = ["sbatch", "--parsable", "--chdir", ROOT] + (["--partition", partition]
                                                          if partition else [])
    size = max_array_size()
    arrays = []
    for base in sorted({i // size * size for i in indices}):
        chunk = [i - base for i in indices if base <= i < base + size]
        limit = max(campaign.runs[base + t].timeout() for t in chunk)
        spec = array_spec(chunk) + (f"%{max_parallel}" if max_parallel else "")
        arrays.append(_slurm(common + [
            f"--array={spec}", f"--cpus-per-task={cpus_per_task}", f"--time={limit // 60 + 2}",
            "--job-name=aar-run", f"--output={folder}/%A-task-%a.log",
            "--open-mode=append",  # a requeued task's log keeps its lost attempt's lines
            f"--wrap=exec {sys.executable} {DRIVER} task {campaign.out} "
            f"$(({base} + SLURM_ARRAY_TASK_ID))"], "sbatch (a job array)").split(";")[0])
    merge = _slurm(common + [
        f"--dependency=afterany:{':'.join(arrays)}", "--kill-on-invalid-dep=yes",
        "--cpus-per-task=1", "--time=30", "--job-name=aar-merge",
        f"--output={folder}/%j-merge.log",
        f"--wrap=exec {sys.executable} {DRIVER} merge {campaign.out}"],
        "sbatch (the merge job)").split(";")[0]
    write_file(os.path.join(folder, "jobs.json"), json.dumps(
        {"arrays": arrays, "array_size": size, "merge": merge, "indices": indices,
         "submitted": time.time()}))
    return arrays, merge


def queued(job):
    p = subprocess.run([command("squeue"), "-h", "-j", job, "-o", "%T"], capture_output=True,
                       text=True)
    return p.returncode == 0 and p.stdout.strip() != ""


def _count_finished(campaign, progress):
    """Counts the runs the queue has finished since the last look; shows progress if any."""
    fresh = [r.key for r in campaign.runs
             if r.key not in progress.done and is_done(r, campaign.out)]
    for key in fresh:
        progress.finished(key)
    if fresh:
        progress.show()


def wait(campaign, arrays, merge, bound_seconds, progress, own_cluster=False):
    """Waits until the merge job has left the queue (bounded), showing `progress` as its runs
    finish; returns the merge's record."""
    deadline = time.monotonic() + bound_seconds
    array = ",".join(arrays)

    def interrupted(signum, frame):  # Ctrl-C or SIGTERM (also when started in the background)
        raise KeyboardInterrupt
    previous = [signal.signal(s, interrupted) for s in (signal.SIGINT, signal.SIGTERM)]
    try:
        while queued(merge) or queued(array):
            if time.monotonic() > deadline:
                raise Refused(f"Slurm jobs {array} and {merge} still queued after "
                              f"{bound_seconds / 60:.0f} min; they go on: scancel "
                              f"{' '.join(arrays)} {merge} to stop them, scripts/run --resume "
                              f"{campaign.out} afterwards")
            _count_finished(campaign, progress)
            time.sleep(POLL_SECONDS)
        _count_finished(campaign, progress)
    except KeyboardInterrupt:
        if own_cluster:
            say(f"interrupted: the single-node cluster this driver brought up stops, and its "
                f"jobs with it; scripts/run --resume {campaign.out} flies what is missing",
                error=True)
            raise
        say(f"stopped waiting; Slurm jobs {array} (runs) and {merge} (merge) go on: squeue -j "
            f"{array},{merge} to watch them, scancel {' '.join(arrays)} {merge} to stop them; "
            f"when they end, scripts/run --resume {campaign.out} flies what is missing",
            error=True)
        raise
    finally:
        for s, handler in zip((signal.SIGINT, signal.SIGTERM), previous):
            signal.signal(s, handler)
    try:
        with open(os.path.join(campaign.out, "slurm", "merge.json")) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None
