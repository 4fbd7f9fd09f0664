"""The run plan: what one run is, how many frames it has, how long it may take, and the
roslaunch command that flies it. Every frame count and timeout of scripts/ comes from here."""
import csv
import dataclasses
import functools
import os
import subprocess
import sys

from campaign.workspace import ROOT, Refused

LAUNCH = os.path.join(ROOT, "launch/pipeline.launch")
CHECK_EXPERIMENT = os.path.join(ROOT, "src/aar_ros_common/scripts/check_experiment.py")
# Each lockstep frame waits at most 5 s for its estimate (the simulator's timeout); a run that
# takes longer than every frame waiting it out, plus start-up, is hung.
SECONDS_PER_FRAME_LIMIT = 6
START_UP_LIMIT = 120


@dataclasses.dataclass
class Run:
    """One experiment flown along one path in one world: one roslaunch of the pipeline."""
    key: str               # its folder under the campaign's, e.g. approaches/01/naive
    experiment: str
    flight_path: str
    frames: int            # frames it records (the count eval must reach)
    frames_cap: int = 0    # --frames: 0 for the whole path
    start_time: str = ""   # [s] path time of the first frame ("": the launch file's)
    rate: str = ""         # [Hz] ("": config/sim.yaml's)
    noise: str = ""        # [grey levels] ("": config/sim.yaml's)
    noise_seed: str = ""
    sim_config: str = ""
    receiver: str = ""
    extra: list = dataclasses.field(default_factory=list)  # more launch arguments, name:=value

    def timeout(self):
        return START_UP_LIMIT + self.frames * SECONDS_PER_FRAME_LIMIT

    def launch_args(self, out_dir):
        """roslaunch's arguments; only those set, so the launch file's defaults hold otherwise."""
        args = [f"experiment:={self.experiment}", f"flight_path:={self.flight_path}",
                f"expected_frames:={self.frames}", f"output_dir:={out_dir}"]
        optional = [("frames", str(self.frames_cap) if self.frames_cap else ""),
                    ("start_time", self.start_time), ("rate", self.rate),
                    ("noise_stddev", self.noise), ("noise_seed", self.noise_seed),
                    ("sim_config", self.sim_config), ("receiver", self.receiver)]
        rigs = experiment_rigs(self.experiment)
        optional.append(("rigs", rigs if rigs != "stereo" else ""))
        return args + [f"{k}:={v}" for k, v in optional if v != ""] + list(self.extra)

    def command(self, out_dir, port):
        """Bounded in time: SIGINT at the limit, SIGKILL 30 s later."""
        return ["timeout", "--signal=INT", "--kill-after=30", str(self.timeout()),
                "roslaunch", "-p", str(port), LAUNCH] + self.launch_args(out_dir)


@functools.lru_cache(maxsize=None)
def experiment_rigs(experiment):
    """The stereo rigs an experiment flies, as pipeline.launch's rigs:= takes them (its sim rigs;
    check_experiment.py, which the launch runs too, refuses any other)."""
    path = os.path.join(ROOT, "config/experiments", experiment + ".yaml")
    found = subprocess.run([sys.executable, CHECK_EXPERIMENT, "--rigs-of", path],
                           capture_output=True, text=True)
    if found.returncode != 0:
        raise Refused(f"experiment '{experiment}' refused:\n{found.stderr.strip()}")
    return found.stdout.strip()


def _top_level_rate(yaml):
    with open(yaml) as f:
        for line in f:
            if line.startswith("rate:"):
                return float(line.split()[1].split("#")[0])
    return None


def sim_rate(overlay="", sim_yaml=os.path.join(ROOT, "config/sim.yaml")):
    """The simulator's frame rate, as the simulator reads it: the top-level `rate:` of the file
    loaded over config/sim.yaml (`overlay`, pipeline.launch sim_config:=), if it sets one, else
    config/sim.yaml's."""
    for yaml in ([overlay] if overlay else []) + [sim_yaml]:
        rate = _top_level_rate(yaml)
        if rate is not None:
            return rate
    raise Refused(f"{sim_yaml} has no top-level rate")


def path_times(flight_path):
    """First and last path time of a flight path CSV (column t)."""
    try:
        with open(flight_path, newline="") as f:
            times = [float(r["t"]) for r in csv.DictReader(f)]
    except (OSError, KeyError, ValueError) as e:
        raise Refused(f"flight path '{flight_path}' is not readable as a path CSV with a t "
                      f"column ({e})")
    if not times:
        raise Refused(f"flight path '{flight_path}' has no rows")
    return times[0], times[-1]


def frame_count(flight_path, rate, start_time=None, cap=0):
    """Frames the simulator flies: from start_time (default the path's first) to the path's
    end at `rate`, both ends included, at most `cap` when cap > 0. The simulator counts the same
    way (aar_sim's path sampling); eval must reach exactly this many rows."""
    first, last = path_times(flight_path)
    start = first if start_time is None else start_time
    if not first <= start <= last:
        raise Refused(f"--start-time {start:g} is outside the flight path's [{first:g}, "
                      f"{last:g}] s")
    total = int((last - start) * rate + 1e-9) + 1
    return min(total, cap) if cap > 0 else total
