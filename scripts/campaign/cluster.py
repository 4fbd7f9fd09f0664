"""The cluster the Slurm engine submits to: the one configured (SLURM_CONF, or Slurm's
/etc/slurm/slurm.conf), or, when none is, a single-node cluster on this machine that the driver
brings up (scripts/slurm-local) and stops again when the campaign ends."""
import os
import subprocess

from campaign.workspace import ROOT, Refused, say

SCRIPT = os.path.join(ROOT, "scripts/slurm-local")


def configured():
    return bool(os.environ.get("SLURM_CONF")) or os.path.isfile("/etc/slurm/slurm.conf")


def ensure():
    """None when a cluster is configured; else the state folder of the one started here."""
    if configured():
        return None
    say("no Slurm cluster configured (SLURM_CONF unset, no /etc/slurm/slurm.conf): bringing up "
        "a single-node one on this machine (scripts/slurm-local up; stopped at the end)")
    p = subprocess.run([SCRIPT, "up"], stdout=subprocess.PIPE, text=True)
    lines = p.stdout.strip().splitlines()
    if p.returncode != 0 or not lines:
        raise Refused("scripts/slurm-local up failed (its messages above)")
    state = lines[-1]
    os.environ["SLURM_CONF"] = os.path.join(state, "slurm.conf")
    return state


def stop(state):
    if not state:
        return
    subprocess.run([SCRIPT, "down", state], stdout=subprocess.DEVNULL)
    os.environ.pop("SLURM_CONF", None)
