"""`campaign fly`: one lockstep run of launch/pipeline.launch for the scripts that need a single
flight (scripts/make-sample-bag, scripts/bench-realtime's recording): the same private master,
frame count, time bound and check as every campaign run.

  python3 scripts/campaign fly --experiment E --flight-path F --out DIR [--start-time S]
      [--frames N] [--rate HZ] [--sim-config FILE] [NAME:=VALUE ...]

NAME:=VALUE: more arguments of launch/pipeline.launch (record:=BAG, rectify:=true). Exits 0 when
DIR/frames.csv has every frame, 1 otherwise (the end of the log on stderr), 2 on bad input."""
import argparse
import os

from campaign import workspace
from campaign.execute import describe, execute, log_tail
from campaign.plan import Run, frame_count, sim_rate
from campaign.workspace import Refused, fail, free_ports, say


def main(argv):
    workspace.PROG = "fly"
    p = argparse.ArgumentParser(prog="campaign fly", description=__doc__.split("\n\n")[0])
    p.add_argument("--experiment", required=True)
    p.add_argument("--flight-path", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--start-time", default="")
    p.add_argument("--frames", type=int, default=0)
    p.add_argument("--rate", default="")
    p.add_argument("--sim-config", default="")
    p.add_argument("extra", nargs="*", help="NAME:=VALUE")
    a = p.parse_args(argv)
    try:
        if not os.path.isfile(os.path.join(workspace.ROOT, "config/experiments",
                                           a.experiment + ".yaml")):
            raise Refused(f"no experiment '{a.experiment}' in config/experiments/")
        for e in a.extra:
            if ":=" not in e:
                raise Refused(f"'{e}' is no launch argument NAME:=VALUE")
        rate = float(a.rate) if a.rate else sim_rate(a.sim_config or "")
        frames = frame_count(a.flight_path, rate, float(a.start_time) if a.start_time else None,
                             a.frames)
    except (Refused, ValueError, OSError) as e:  # OSError: an unreadable --sim-config
        fail(str(e))
    out = os.path.abspath(a.out)  # roslaunch's nodes run elsewhere: every path absolute
    run = Run(key=os.path.basename(out), experiment=a.experiment,
              flight_path=os.path.abspath(a.flight_path), frames=frames, frames_cap=a.frames,
              start_time=a.start_time, rate=a.rate,
              sim_config=os.path.abspath(a.sim_config) if a.sim_config else "", extra=a.extra)
    status = execute(run, os.path.dirname(out), free_ports(1)[0])
    say(f"{a.experiment}: {frames} frames, {describe(status)}")
    if status["status"] != "ok":
        say(f"the end of its log ({out}/launch.log):\n{log_tail(run, os.path.dirname(out))}",
            error=True)
        return 1
    return 0
