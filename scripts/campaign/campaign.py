"""A campaign: its runs, its folder, what it records about itself (campaign.json, run.txt), and
the lock that keeps two drivers out of one folder."""
import dataclasses
import errno
import fcntl
import json
import os
import shutil
import subprocess
import sys

from campaign.plan import CHECK_EXPERIMENT, Run
from campaign.workspace import ROOT, Refused, commit, machine, utc_now, write_file

RECORD = "campaign.json"


@dataclasses.dataclass
class Campaign:
    kind: str          # run (one path, the main job), suite (seeded approaches) or realism
    out: str           # its folder
    command: str       # the command line that made it
    experiments: list
    runs: list         # of Run, in the order they are flown; a Slurm task's index is its place
    units: list        # folders (relative to out) with a report each: "." or one per world
    notes: dict        # kind-specific settings the reports and run.txt need

    def save(self):
        write_file(os.path.join(self.out, RECORD), json.dumps(dataclasses.asdict(self), indent=1))

    @staticmethod
    def load(out):
        path = os.path.join(out, RECORD)
        try:
            with open(path) as f:
                record = json.load(f)
        except OSError:
            raise Refused(f"'{out}' holds no campaign ({RECORD} missing): nothing to resume")
        except ValueError as e:
            raise Refused(f"{path} is not readable ({e})")
        record["runs"] = [Run(**r) for r in record["runs"]]
        return Campaign(**record)


def refuse_existing(out):
    """A new campaign may not reuse a campaign's folder (its results would mix), nor a folder
    with anything else in it (a campaign writes and deletes files in its folder)."""
    if os.path.exists(os.path.join(out, RECORD)):
        raise Refused(f"'{out}' holds a campaign already: resume it with scripts/run --resume "
                      f"{out}, or choose another --out")
    held = sorted(os.listdir(out)) if os.path.isdir(out) else []
    if held:
        raise Refused(f"'{out}' is not empty ({', '.join(held[:3])}{' ...' if held[3:] else ''})"
                      f": a campaign writes and deletes files in its folder; choose a new or "
                      f"empty --out")
    if os.path.exists(out) and not os.path.isdir(out):
        raise Refused(f"'{out}' is a file, not a folder: choose another --out")


class Lock:
    """An exclusive lock on the campaign folder for as long as one driver works in it."""

    def __init__(self, out):
        self.out = out
        try:
            os.makedirs(out, exist_ok=True)
            self.file = open(os.path.join(out, ".lock"), "a+")
        except OSError as e:  # read-only, not a folder, no space, no permission
            raise Refused(f"--out '{out}' cannot be written: {e.strerror}")
        try:
            fcntl.flock(self.file, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            self.file.seek(0)
            holder = self.file.read().strip() or "another process"
            raise Refused(f"'{out}' is in use by another campaign driver ({holder}); wait for "
                          f"it or choose another --out")
        try:
            self.file.truncate(0)
            self.file.write(f"pid {os.getpid()}\n")
            self.file.flush()
        except OSError as e:
            raise Refused(f"--out '{out}' cannot be written: {e.strerror}")


def copy_configuration(unit_dir, experiments, extra):
    """config/*.yaml, the experiments' settings (resolved: their includes in, as the launch loads
    them) and the extra files (name -> path) into the unit's config/ folder: every result records
    the configuration it was made with."""
    config = os.path.join(unit_dir, "config")
    os.makedirs(config, exist_ok=True)
    for name in sorted(os.listdir(os.path.join(ROOT, "config"))):
        if name.endswith(".yaml"):
            shutil.copy(os.path.join(ROOT, "config", name), config)
    for e in experiments:
        out = os.path.join(config, f"experiment_{e}.yaml")
        resolved = subprocess.run([sys.executable, CHECK_EXPERIMENT, os.path.join(
            ROOT, "config/experiments", e + ".yaml"), "--resolved", out], capture_output=True,
            text=True)
        if resolved.returncode != 0:  # checked before (plans); a disk that refuses the copy
            raise OSError(errno.EIO, resolved.stderr.strip() or "check_experiment failed", out)
    for name, path in extra.items():
        if path:
            shutil.copy(path, os.path.join(config, name))


def write_provenance(unit_dir, command, lines):
    write_file(os.path.join(unit_dir, "run.txt"),
               f"date (UTC): {utc_now()}\ncommit: {commit()}\ncommand: {command}\n"
               f"machine: {machine()}\n" + "".join(line + "\n" for line in lines) +
               "configuration: config/ as copied into this folder\n")


def append_provenance(campaign, lines):
    for unit in campaign.units:
        path = os.path.join(campaign.out, unit, "run.txt")
        try:
            with open(path, "a") as f:
                f.write("".join(line + "\n" for line in lines))
        except OSError as e:  # a failed close names no file
            raise OSError(e.errno, e.strerror, path) from None
