"""The reports a campaign ends with, by kind: report.md (one path), suite.md (approaches), and
worlds.md (realism). The same code runs after local runs, in Slurm's merge job and on resume."""
import os
import re
import signal
import subprocess
import sys

from campaign.workspace import ROOT, ros_env, say, tool

# The suite's paired comparisons: against naive and no_boom, and each part's own gain.
SUITE_BASELINES = "naive,no_boom,culling_only,dynamic_reference_only"


def _call(cmd, log=None):
    """Runs a report step; on Ctrl-C or SIGTERM (KeyboardInterrupt) it is asked to stop (SIGINT:
    a capture ends its roslaunch and nodes) and waited for, then the interrupt goes on."""
    out = open(log, "w") if log else None
    try:
        p = subprocess.Popen(cmd, env=ros_env(), stdout=out, stderr=subprocess.STDOUT if log
                             else None, stdin=subprocess.DEVNULL)
        try:
            return p.wait()
        except KeyboardInterrupt:
            p.send_signal(signal.SIGINT)
            try:
                p.wait(timeout=90)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
            raise
    finally:
        if out:
            out.close()


def _stanford_diagrams(out, experiments):
    """DIR/plots/<experiment>_stanford.png of a run or a suite (plot_integrity.py); whether they
    were written."""
    if _call([sys.executable, os.path.join(ROOT, "src/aar_eval/scripts/plot_integrity.py"),
              out, experiments]):
        say("Stanford diagrams failed (above)", error=True)
        return False
    return True


def _why(log):
    """The last line of a report step's log that says what went wrong, or ""."""
    try:
        with open(log, errors="replace") as f:
            lines = [s.strip() for s in f if "FATAL" in s or "rror" in s or "cannot" in s]
    except OSError:
        return ""
    return ": " + re.sub(r"^\[FATAL\] \[[^]]*\]: ", "", lines[-1])[:300] if lines else ""


def write_reports(campaign, complete=True):
    """Writes the kind's reports; returns the main one's path and whether all were written.
    With runs missing (not `complete`) the rviz captures are skipped: the report is not whole."""
    experiments = ",".join(campaign.experiments)
    out = campaign.out
    if campaign.kind == "run":
        plotted = _call([sys.executable, os.path.join(
            ROOT, "src/aar_eval/scripts/plot_errors.py"), out, experiments]) == 0
        if not plotted:
            say("plots failed (above)", error=True)
        plotted &= _stanford_diagrams(out, experiments)
        # Headless rviz captures of the sample bag (a C-12 flight; other receivers go without).
        captured = True
        if campaign.notes.get("captures") and not complete:
            say("rviz captures skipped: runs are missing", error=True)
        elif campaign.notes.get("captures"):
            captured = _call([os.path.join(ROOT, "scripts/capture"), os.path.join(
                ROOT, "rosbags/sample_contact.bag"), "--frames", "6,15", "--out",
                os.path.join(out, "captures"), "--no-build"],
                os.path.join(out, "capture.log")) == 0
            if not captured:
                log = os.path.join(out, "capture.log")
                say(f"rviz captures failed{_why(log)} (log: {log})", error=True)
        ok = _call([tool("aar_eval", "make_report"), out, experiments, "naive"]) == 0
        return os.path.join(out, "report.md"), ok and captured and plotted
    ok = True
    for unit in campaign.units:
        unit_dir = os.path.normpath(os.path.join(out, unit))
        ok &= _stanford_diagrams(unit_dir, experiments)
        ok &= _call([tool("aar_eval", "make_report"), "--suite", unit_dir, experiments,
                     SUITE_BASELINES]) == 0
    if campaign.kind == "suite":
        return os.path.join(out, "suite.md"), ok
    pairs = ",".join(f"{w}={os.path.join(out, w)}" for w in campaign.units)
    ok &= _call([tool("aar_eval", "make_report"), "--worlds", os.path.join(out, "worlds.md"),
                 experiments, pairs]) == 0
    return os.path.join(out, "worlds.md"), ok
