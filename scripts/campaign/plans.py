"""The three campaign kinds: their usage, their arguments' checks (before anything is built),
and their campaigns (after the build: approaches generated, configuration copied, recorded)."""
import glob
import os
import re
import subprocess
import sys
import types

from campaign.campaign import CHECK_EXPERIMENT, Campaign, copy_configuration, write_provenance
from campaign.plan import Run, frame_count, path_times, sim_rate
from campaign.workspace import ROOT, Refused, absolute, tool, utc_stamp

USAGE = {
    "run": "The main job: each experiment flown along one path in lockstep; writes\n"
           "DIR/report.md, per-frame CSVs, plots and the configuration used (default DIR:\n"
           "results/<UTC time>). scripts/run is the front door of every campaign:\n"
           "  scripts/run ...                   one path (the options below)\n"
           "  scripts/run --suite N ...         N seeded approaches instead; DIR/suite.md\n"
           "                                    (scripts/run --suite N -h)\n"
           "  scripts/run --worlds ideal,NAME,...\n"
           "                                    the same seeded suite (--suite N, default 4) in\n"
           "                                    the ideal world and in each world NAME\n"
           "                                    (config/realism/NAME.yaml); DIR/worlds.md, each\n"
           "                                    world's cost against ideal (--worlds all: every\n"
           "                                    preset; scripts/run --worlds all -h)\n"
           "  scripts/run --resume DIR          what campaign DIR misses, of any of the three\n"
           "  scripts/run --show-experiment NAME\n"
           "                                    an experiment's settings, each with its file",
    "suite": "N seeded approaches (aar_sim's generate_approach, seed S*1000+i: start offset,\n"
             "closure, wander and boom motion vary), each experiment on each, with sensor noise\n"
             "seeded per approach; writes DIR/suite.md (means over approaches with 95 %\n"
             "intervals, paired improvements) and each run's frames.csv under\n"
             "DIR/approaches/NN/.",
    "realism": "The same seeded suite (--suite N, default 4) flown in each world of --worlds:\n"
               "ideal (config/sim.yaml alone) and each NAME, config/realism/NAME.yaml over it\n"
               "(--worlds all: ideal and every preset); writes DIR/<world>/suite.md and\n"
               "DIR/worlds.md (each world's cost against the ideal one; docs/realism/README.md).",
}
DEFAULT_EXPERIMENTS = {
    "run": "no_boom,naive,static_wings_nose,dynamic,flight",
    "suite": "naive,no_boom,culling_only,dynamic_reference_only,dynamic,flight",
    "realism": "naive,no_boom,static_wings_nose,dynamic,tracking",
}
MODELS = os.path.join(ROOT, "src/aar_description/models")


def _names(folder, pattern="*.yaml"):
    return sorted(os.path.basename(p)[:-5] for p in glob.glob(os.path.join(ROOT, folder, pattern)))




def _experiments(value, kind):
    """The experiments named, each a file of config/experiments/ whose namespaces are the
    stages' (check_experiment.py, which the launch file runs too)."""
    names = (DEFAULT_EXPERIMENTS[kind] if value is None else value).split(",")
    if not all(names):
        raise Refused(f"--experiments '{value}' has an empty name (available: "
                      f"{','.join(_names('config/experiments'))})")
    twice = sorted({e for e in names if names.count(e) > 1})
    if twice:
        raise Refused(f"--experiments '{value}' names {', '.join(twice)} twice: each experiment "
                      f"flies once a path")
    for e in names:
        path = os.path.join(ROOT, "config/experiments", e + ".yaml")
        if not os.path.isfile(path):
            raise Refused(f"no experiment '{e}' in config/experiments/ (available: "
                          f"{','.join(_names('config/experiments'))})")
        check = subprocess.run([sys.executable, CHECK_EXPERIMENT, path], capture_output=True,
                               text=True)
        if check.returncode != 0:
            raise Refused(f"experiment '{e}' refused:\n{check.stderr.strip()}")
    return names


def _file(value, caller, flag):
    path = absolute(value, caller)
    if path and not os.path.isfile(path):
        raise Refused(f"{flag} '{path}' does not exist")
    return path


def _description(a):
    """The receiver --receiver names (default c12) and its description's path."""
    name = a.receiver or "c12"
    if name.endswith((".yaml", ".yml")) or "/" in name:
        description = absolute(name, a.caller)
    else:
        description = os.path.join(MODELS, name + ".yaml")
    if not os.path.isfile(description):
        raise Refused(f"--receiver: no receiver '{name}' ({description}; available: "
                      f"{','.join(_names('src/aar_description/models'))})")
    return name, description


def _receiver(a):
    """The receiver's description and its approach (run kind)."""
    name, description = _description(a)
    if a.flight_path:
        return name, description, _file(a.flight_path, a.caller, "flight path")
    stem = os.path.basename(description)[:-5]
    path = os.path.join(ROOT, "config/flight_paths",
                        "approach_default.csv" if stem == "c12" else f"approach_{stem}.csv")
    if not os.path.isfile(path):
        raise Refused(f"--receiver {name} has no approach {path}: give --flight-path")
    return name, description, path


def _check_run(a, f):
    f.receiver, f.description, f.flight_path = _receiver(a)
    f.frames = int(_match(a.frames or "0", r"[0-9]+", "--frames",
                          "a whole number (0: all)"))
    f.start_time = a.start_time
    if f.start_time is not None:
        _match(f.start_time, r"[0-9]+(\.[0-9]+)?", "--start-time",
               "seconds of path time (e.g. 35 or 35.5)")
    f.rate = sim_rate(f.sim_config)
    # Counted now: a start outside the path is refused before the build.
    frame_count(f.flight_path, f.rate, None if f.start_time is None else float(f.start_time),
                f.frames)
    f.out = absolute(a.out or os.path.join(ROOT, "results", utc_stamp()), a.caller)


def _check_suite(a, f):
    if a.flight_path is not None:
        raise Refused("--flight-path: a suite flies the approaches it generates (seeded by "
                      "--seed, ending at --receiver's contact position); one path is scripts/run "
                      "--flight-path FILE, without --suite")
    # Without --receiver nothing names one: the runs and approaches are the C-12's as before.
    f.receiver, f.description = _description(a) if a.receiver else (None, "")
    f.suite = int(_match(a.suite or ("4" if f.kind == "realism" else ""), r"[0-9]+", "--suite",
                         "a number of approaches of at least 1", low=1))
    f.seed = int(_match(a.seed or "1", r"[0-9]{1,12}", "--seed",
                        "a whole number (at most 12 digits)"))
    if a.rate:
        _match(a.rate, r"[0-9]+(\.[0-9]+)?", "--rate", "a positive number of frames per second",
               low=1e-9)
    f.rate = float(a.rate) if a.rate else sim_rate(f.sim_config)
    f.noise = _match(a.noise or "2.0", r"[0-9]+(\.[0-9]+)?", "--noise",
                     "a sigma in grey levels (>= 0)")
    stamp = utc_stamp()
    f.out = absolute(a.out or os.path.join(
        ROOT, "results", ("suite-" if f.kind == "suite" else "realism-") + stamp), a.caller)


def _check_worlds(a, f):
    presets = _names("config/realism")
    every = ["ideal"] + [p for p in presets if p != "realistic"] + ["realistic"]
    names = every if a.worlds in (None, "all") else a.worlds.split(",")
    if names[0] != "ideal":
        raise Refused(f"--worlds must start with ideal, the world every cost is against (got "
                      f"'{names[0]}')")
    if len(names) < 2:
        raise Refused("--worlds needs ideal and at least one preset (all: every one)")
    for w in names[1:]:
        if w not in presets:
            raise Refused(f"no world '{w}': config/realism/{w}.yaml does not exist")
    f.worlds = names


def _match(value, pattern, flag, what, low=None):
    if not re.fullmatch(pattern, value) or (low is not None and float(value) < low):
        raise Refused(f"{flag} takes {what}, not '{value}'")
    return value


def check(kind, a):
    """Every argument checked; returns what create() needs."""
    f = types.SimpleNamespace(kind=kind, command="")
    if kind == "realism" and a.sim_config is not None:
        raise Refused("--sim-config: with --worlds each world is its own (ideal, or "
                      "config/realism/NAME.yaml over config/sim.yaml); a suite in one world of "
                      "your own is scripts/run --suite N --sim-config FILE")
    f.experiments = _experiments(a.experiments, kind)
    f.sim_config = _file(a.sim_config, a.caller, "--sim-config") if a.sim_config else ""
    if kind == "run":
        _check_run(a, f)
    else:
        _check_suite(a, f)
    if kind == "realism":
        _check_worlds(a, f)
    f.jobs = a.jobs
    return f


def _generate_approaches(unit_dir, suite, seed, rate, description=""):
    """approaches/NN/flight_path.csv and approaches.csv, each ending at the contact position of
    the receiver `description` (default the C-12); a failure stops before any run."""
    approaches = []
    with open(os.path.join(unit_dir, "approaches.csv"), "w") as out:
        out.write("approach,seed,elevation_deg,azimuth_deg,far_speed_mps,mid_speed_mps,"
                  "near_speed_mps,position_wander_m,attitude_wander_deg,boom_swing,frames\n")
        for i in range(1, suite + 1):
            name, approach_seed = f"{i:02d}", seed * 1000 + i
            folder = os.path.join(unit_dir, "approaches", name)
            os.makedirs(folder, exist_ok=True)
            path = os.path.join(folder, "flight_path.csv")
            receiver = ["--receiver", description] if description else []
            p = subprocess.run([tool("aar_sim", "generate_approach")] + receiver +
                               [MODELS, path, str(approach_seed)], capture_output=True, text=True)
            line = next((s for s in p.stdout.splitlines() if s.startswith("approach: ")), None)
            if p.returncode != 0 or line is None:
                raise Refused(f"approach {name} (seed {approach_seed}) failed to generate: "
                              f"{(p.stderr or p.stdout).strip()}")
            frames = frame_count(path, rate)
            settings = line[len("approach: "):].split(",")
            out.write(",".join([name] + [f"{float(v):.4g}" for v in settings] + [str(frames)])
                      + "\n")
            approaches.append((name, approach_seed, path, frames))
    return approaches


def _create_run(f):
    runs = [Run(key=e, experiment=e, flight_path=f.flight_path, frames=frame_count(
        f.flight_path, f.rate, None if f.start_time is None else float(f.start_time), f.frames),
        frames_cap=f.frames, start_time=f.start_time or repr(path_times(f.flight_path)[0]),
        sim_config=f.sim_config,
        receiver=f.description) for e in f.experiments]
    command = (f"scripts/run --receiver {f.receiver} --flight-path {f.flight_path} --experiments "
               f"{','.join(f.experiments)} --frames {f.frames}"
               f"{' --start-time ' + f.start_time if f.start_time else ''}"
               f"{' --sim-config ' + f.sim_config if f.sim_config else ''} --out {f.out}")
    copy_configuration(f.out, f.experiments, {"receiver.yaml": f.description,
                                              "sim_config.yaml": f.sim_config})
    write_provenance(f.out, command, [f"receiver: {f.description}"])
    captures = os.path.basename(f.description) == "c12.yaml"
    return Campaign("run", f.out, command, f.experiments, runs, ["."], {"captures": captures})


def _create_suites(f):
    worlds = f.worlds if f.kind == "realism" else ["."]
    receiver = f" --receiver {f.receiver}" if f.receiver else ""
    command = (f"scripts/run --suite {f.suite} --seed {f.seed}{receiver} --experiments "
               f"{','.join(f.experiments)} --rate {f.rate:g} --noise {f.noise}"
               f"{' --sim-config ' + f.sim_config if f.sim_config else ''} --out {f.out}")
    if f.kind == "realism":
        command = (f"scripts/run --suite {f.suite} --seed {f.seed}{receiver} --experiments "
                   f"{','.join(f.experiments)} --worlds {','.join(worlds)} --rate {f.rate:g} "
                   f"--noise {f.noise} --out {f.out}")
    runs = []
    for w in worlds:
        unit = os.path.normpath(os.path.join(f.out, w))
        sim_config = f.sim_config
        if f.kind == "realism" and w != "ideal":
            sim_config = os.path.join(ROOT, "config/realism", w + ".yaml")
        os.makedirs(unit, exist_ok=True)
        copy_configuration(unit, f.experiments, {"sim_config.yaml": sim_config,
                                                  "receiver.yaml": f.description})
        write_provenance(unit, command, ([f"world: {w}"] if f.kind == "realism" else []) + (
            [f"receiver: {f.description}"] if f.description else []) + [
            f"sensor noise: {f.noise} grey levels, seeded per approach (its seed)"])
        for name, seed, path, frames in _generate_approaches(unit, f.suite, f.seed, f.rate,
                                                             f.description):
            runs += [Run(key=os.path.normpath(os.path.join(w, "approaches", name, e)),
                         experiment=e, flight_path=path, frames=frames, rate=f"{f.rate:g}",
                         noise=f.noise, noise_seed=str(seed), sim_config=sim_config,
                         receiver=f.description)
                     for e in f.experiments]
    return Campaign(f.kind, f.out, command, f.experiments, runs, worlds, {})


def create(f):
    """The campaign's folder filled and recorded (campaign.json); runs not yet flown."""
    os.makedirs(f.out, exist_ok=True)
    campaign = _create_run(f) if f.kind == "run" else _create_suites(f)
    campaign.save()
    return campaign
