"""Command lines of scripts/run, the one front door of campaigns: one path (the main job),
--suite N (seeded approaches) or --worlds ideal,NAME,... (a suite per world); and the Slurm jobs'
own (task, merge); the other scripts that are wrappers (SCRIPTS) handed to their modules.
Arguments are checked before anything is set up, built or flown."""
import argparse
import importlib
import os
import re
import subprocess
import sys

from campaign import cluster, drive, plans, slurm, workspace
from campaign.campaign import CHECK_EXPERIMENT, Campaign, Lock, refuse_existing
from campaign.workspace import Refused, fail, os_error, say

DEFAULTS = {
    "run": "no_boom,naive,static_wings_nose,dynamic,flight",
    "suite": "naive,no_boom,culling_only,dynamic_reference_only,dynamic,flight",
    "realism": "naive,no_boom,static_wings_nose,dynamic,tracking",
}
# The other scripts whose logic is the driver's (each scripts/NAME execs it with NAME).
SCRIPTS = {"bench-realtime": "bench_realtime", "two-hosts": "two_hosts",
           "slurm-local": "slurm_local", "replay": "replay", "capture": "capture"}
HELD = []  # the campaign folder's lock, held until the driver exits
PLAN_KEYS = ("receiver", "flight_path", "experiments", "frames", "start_time", "sim_config",
             "out", "suite", "seed", "rate", "noise", "worlds")


class Parser(argparse.ArgumentParser):
    def error(self, message):
        fail(message)


def engine_arguments(p):
    g = p.add_argument_group("where the runs go")
    g.add_argument("--jobs", default=None, help="local engine: runs at a time, at most the "
                   "number of cores (default: 1 for one path, 2 capped at the cores otherwise)")
    g.add_argument("--engine", choices=("local", "slurm"), default="local",
                   help="local: processes here; slurm: a job array on a Slurm cluster "
                   "(docs/CLUSTER.md; with no cluster configured, a single-node one here)")
    g.add_argument("--partition", default="", help="slurm: the partition to submit to")
    g.add_argument("--cpus-per-task", default="1", help="slurm: CPUs per run")
    g.add_argument("--max-parallel", default="0", help="slurm: runs at a time (0: no limit)")
    g.add_argument("--no-wait", action="store_true", help="slurm: submit and return; the merge "
                   "job writes the report")
    g.add_argument("--resume", default=None, metavar="DIR", help="fly the runs of campaign DIR "
                   "that are not done, then write its reports")
    g.add_argument("--no-build", action="store_true", help="skip scripts/setup and build")
    g.add_argument("--caller", default=os.getcwd(), help=argparse.SUPPRESS)


def parser(kind):
    doc = plans.USAGE[kind]
    p = Parser(prog={"run": "scripts/run", "suite": "scripts/run --suite",
                     "realism": "scripts/run --worlds"}[kind], description=doc,
               formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--experiments", default=None, help=f"default {DEFAULTS[kind]}")
    # Refused with --worlds (plans.check): each world is its own sim config.
    p.add_argument("--sim-config", default=None, help=argparse.SUPPRESS if kind == "realism" else
                   "YAML loaded over config/sim.yaml (a camera mount, config/mounts/NAME.yaml, "
                   "or a world, config/realism/)")
    p.add_argument("--out", default=None, help="the campaign's folder (default: results/...)")
    if kind == "run":
        p.add_argument("--receiver", default=None, help="c12 (default) or rq4, or a "
                       "description's path")
        p.add_argument("--flight-path", default=None, help="default: the receiver's approach")
        p.add_argument("--frames", default=None, help="at most N frames (0: all)")
        p.add_argument("--start-time", default=None, help="[s] path time of the first frame")
    else:
        p.add_argument("--suite", default=None, help="number of approaches N" +
                       (" (default 4)" if kind == "realism" else ""))
        p.add_argument("--receiver", default=None, help="c12 (default) or rq4, or a "
                       "description's path: each approach ends at its contact position")
        # Refused with its reason (plans._check_suite): a suite generates its own paths.
        p.add_argument("--flight-path", default=None, help=argparse.SUPPRESS)
        p.add_argument("--seed", default=None, help="suite seed S: approach i uses S*1000+i "
                       "(default 1)")
        p.add_argument("--rate", default=None, help="[Hz] frames per second of path time "
                       "(default: config/sim.yaml's)")
        p.add_argument("--noise", default=None, help="[grey levels] sensor noise sigma "
                       "(default 2.0)")
    if kind == "realism":
        p.add_argument("--worlds", default=None, metavar="ideal,NAME,...|all", help="ideal "
                       "(config/sim.yaml alone) first, then each NAME, config/realism/NAME.yaml "
                       "over it; all: ideal and every preset there, realistic last")
    engine_arguments(p)
    return p


def number(value, name, pattern, low, high, what):
    if not re.fullmatch(pattern, value) or not low <= float(value) <= high:
        raise Refused(f"{name} takes {what}, not '{value}'")
    return value


def check_engine(a):
    cores = os.cpu_count() or 1
    if a.jobs is not None:
        number(a.jobs, "--jobs", r"[0-9]+", 1, cores, f"1 to {cores} (this machine's cores)")
    number(a.cpus_per_task, "--cpus-per-task", r"[0-9]+", 1, 4096, "a whole number of CPUs")
    number(a.max_parallel, "--max-parallel", r"[0-9]+", 0, 1e6, "a whole number (0: no limit)")
    if a.engine == "local" and (a.partition or a.no_wait):
        raise Refused("--partition and --no-wait are for --engine slurm")


def main(argv):
    try:
        return _main(argv)
    except OSError as e:  # the driver's own files: a full or read-only disk, named, no traceback
        out = HELD[0].out if HELD else None
        if out and os.path.isfile(os.path.join(out, "campaign.json")):
            hint = f"; what is recorded in {out} is kept: make room, then scripts/run --resume {out}"
        elif out:
            hint = f"; nothing was flown: make room, remove {out} and run again"
        say(f"{os_error(e)}{hint if out else ''}", error=True)
        return 1


def flag_given(argv, flag):
    """`flag` is on the command line (--flag VALUE or --flag=VALUE): it picks the campaign."""
    return any(a == flag or a.startswith(flag + "=") for a in argv)


def show_experiment(argv):
    """scripts/run --show-experiment NAME|FILE: the experiment's settings, each with the file that
    gives it (check_experiment.py --show); the stages' defaults (config/*.yaml) lie under them."""
    if len(argv) != 1:
        fail("--show-experiment takes one experiment: a name of config/experiments/ or a file")
    path = argv[0] if os.path.isfile(argv[0]) else os.path.join(
        workspace.ROOT, "config/experiments", argv[0] + ".yaml")
    if not os.path.isfile(path):
        fail(f"no experiment '{argv[0]}' in config/experiments/ (available: "
             f"{','.join(plans._names('config/experiments'))})")
    return subprocess.run([sys.executable, CHECK_EXPERIMENT, "--show", path]).returncode


def _main(argv):
    if argv and argv[0] in ("task", "merge"):
        from campaign import jobs
        return jobs.main(argv)
    if argv and argv[0] == "fly":
        from campaign import fly
        return fly.main(argv[1:])
    if argv and argv[0] == "cost":
        from campaign import cost
        return cost.main(argv[1:])
    if argv and argv[0] in SCRIPTS:  # scripts/NAME, a wrapper around campaign/MODULE.py
        return importlib.import_module("campaign." + SCRIPTS[argv[0]]).main(argv[1:])
    if argv and argv[0] in ("bench-realtime-retime", "bench-realtime-skips"):  # BAG; FILE
        from campaign import bench_realtime  # its helpers, run in the ROS environment
        helper = {"bench-realtime-retime": bench_realtime.retime,
                  "bench-realtime-skips": bench_realtime.skips_recorder}[argv[0]]
        return helper(argv[1])
    kind, argv = argv[0], argv[1:]
    if kind == "run" and argv and argv[0] == "--show-experiment":
        return show_experiment(argv[1:])
    if kind == "run" and flag_given(argv, "--worlds"):  # a suite per world (default --suite 4)
        kind = "realism"
    elif kind == "run" and flag_given(argv, "--suite"):
        kind = "suite"
    workspace.PROG = kind
    a = parser(kind).parse_args(argv)
    started = None
    try:
        check_engine(a)
        if a.resume is not None:
            given = [k for k in PLAN_KEYS if getattr(a, k, None) is not None]
            if given:
                flag = "--" + given[0].replace("_", "-")
                raise Refused("--resume flies the campaign's own plan: give only --jobs, "
                              f"--engine and the Slurm options with it (got {flag})")
            out = workspace.absolute(a.resume, a.caller)
            campaign, fresh = Campaign.load(out), None
            workspace.PROG = campaign.kind
        else:
            fresh = plans.check(kind, a)
            refuse_existing(fresh.out)
            out = fresh.out
        if a.engine == "slurm":
            if a.no_wait and not cluster.configured():
                raise Refused("--no-wait needs a cluster that outlives the driver (SLURM_CONF or "
                              "/etc/slurm/slurm.conf); the single-node one it would bring up "
                              "here stops when it returns")
            started = cluster.ensure()  # stopped by drive(), or below when refused
            slurm.check(a.partition)
        HELD.append(Lock(out))
        if not a.no_build:
            workspace.setup_and_build()
        if fresh is not None:
            campaign = plans.create(fresh)
    except Refused as e:
        cluster.stop(started)
        fail(str(e))
    try:
        return drive.drive(campaign, a, started)
    except KeyboardInterrupt:  # after the runs (they handle their own); said where it came
        return 130


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
