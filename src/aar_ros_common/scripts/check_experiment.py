#!/usr/bin/env python3
"""Resolves and checks an experiment file before a launch loads it:
  check_experiment.py FILE [--resolved OUT] [--rigs LIST --rig-part OUT]
  check_experiment.py --show FILE
  check_experiment.py --rigs-of FILE
  check_experiment.py --redundant FILE...
An experiment (config/experiments/NAME.yaml) sets parameters of the stages by their node names:
sim, stereo/aar_stereo, occlusion, registration, eval. It may start from others: `include: BASE`
or `include: [BASE, ...]` (experiment names, looked up beside FILE, then in config/experiments/)
loads each base in order, then the file's own keys over them, key by key (cartographer's
include). Each stage refuses a key it does not know (ParamReader), but a namespace no stage reads
(a misspelt `registraton:`) would be loaded and ignored without a word: this refuses it, naming
the file and the namespace, and exits 1; so it does an include that is missing or circular.
With --rigs (the launch's rigs:=, comma-separated; issue 44) it refuses a list that is not the
experiment's sim rigs (`sim: rigs:`, default the one rig `stereo`) or whose first is not `stereo`,
and writes the settings a further rig's stages take (aar_stereo and occlusion) to --rig-part's OUT.
A sim rig's `mount: NAME` stands for config/mounts/NAME.yaml's keys (the rig's own keys win).
On success it writes the resolved settings to OUT (one YAML, what the launch loads) and prints
the namespaces (launch files use it as a command parameter, which makes roslaunch stop before
any node starts when the check fails); the campaign driver runs it on every experiment of a
campaign before the first run. --show prints every setting as `namespace/key: value  # file`,
the file that gave it (the experiment's effective settings over the stages' defaults);
--rigs-of prints the experiment's sim rigs as the launch's rigs:= takes them;
--redundant lists the settings a file gives the value its includes already give (scripts/lint)."""
import os
import sys
import time

import yaml

# The stages' node names (launch/include/processing.launch, launch/pipeline.launch): a mapping
# means a namespace of namespaces (stereo's node is stereo/aar_stereo).
STAGES = {"sim": None, "stereo": {"aar_stereo": None}, "occlusion": None, "registration": None,
          "eval": None}
ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../.."))
SHIPPED = os.path.join(ROOT, "config/experiments")


class Refused(Exception):
    pass


def problems(tree, allowed, where):
    if not isinstance(tree, dict):
        return [f"{where or 'the file'} is not a mapping of namespaces"]
    found = []
    for key, value in tree.items():
        name = f"{where}/{key}" if where else str(key)
        if key not in allowed:
            found.append(f"unknown namespace '{name}' (no stage reads it; known here: "
                         f"{', '.join(sorted(allowed))})")
        elif allowed[key] is not None:
            found += problems(value, allowed[key], name)
        elif not isinstance(value, dict):
            found.append(f"'{name}' is not a mapping of parameters")
    return found


def read(path):
    try:
        with open(path) as f:
            tree = yaml.safe_load(f) or {}
    except (OSError, yaml.YAMLError) as e:
        raise Refused(f"{path}: not readable: {e}")
    if not isinstance(tree, dict):
        raise Refused(f"{path}: the file is not a mapping of namespaces")
    return tree


def base_path(name, including):
    if not isinstance(name, str) or not name or "/" in name:
        raise Refused(f"{including}: include takes experiment names, not {name!r}")
    for folder in (os.path.dirname(os.path.abspath(including)), SHIPPED):
        path = os.path.join(folder, name + ".yaml")
        if os.path.isfile(path):
            return path
    raise Refused(f"{including}: includes '{name}', but there is no {name}.yaml beside it or in "
                  f"{SHIPPED}")


def merge(into, tree, sources, path, prefix=""):
    """Puts `tree`'s settings into `into`, key by key; sources[namespace/key] = path."""
    for key, value in tree.items():
        name = f"{prefix}/{key}" if prefix else str(key)
        if isinstance(value, dict) and value:
            merge(into.setdefault(key, {}), value, sources, path, name)
        else:
            into[key] = value
            sources[name] = path


def resolve(path, sources, chain=()):
    """The settings of the experiment at `path` with its includes; `sources` gets each setting's
    file."""
    if os.path.abspath(path) in chain:
        raise Refused(f"{path}: includes itself (through {' -> '.join(chain)})")
    tree = read(path)
    includes = tree.pop("include", [])
    merged = {}
    for name in includes if isinstance(includes, list) else [includes]:
        base = resolve(base_path(name, path), sources, chain + (os.path.abspath(path),))
        merge(merged, base, {}, path)
    found = problems(tree, STAGES, "")
    if found:
        raise Refused("\n".join(f"{path}: {p}" for p in found))
    merge(merged, tree, sources, path)
    expand_mounts(merged, path)
    return merged


MOUNTS = os.path.join(ROOT, "config/mounts")


def expand_mounts(tree, path):
    """A sim rig's `mount: NAME` becomes config/mounts/NAME.yaml's keys (the rig's own win)."""
    for rig in tree.get("sim", {}).get("rigs", []):
        if not isinstance(rig, dict) or "mount" not in rig:
            continue
        name = rig.pop("mount")
        if not isinstance(name, str) or not name or "/" in name:
            raise Refused(f"{path}: sim rig {rig.get('name')}: mount takes a mount's name (a "
                          f"file of {MOUNTS}), not {name!r}")
        mount = read(os.path.join(MOUNTS, name + ".yaml"))
        for key, value in mount.items():
            rig.setdefault(key, value)


# The stages' defaults under the experiment, as the launch files load them.
DEFAULTS = {"sim": "sim.yaml", "stereo/aar_stereo": "stereo.yaml", "occlusion": "occlusion.yaml",
            "registration": "registration.yaml"}


def show(path):
    """Every setting the stages get, `namespace/key: value  # the file that gives it`: the
    experiment's (with its includes) over config/*.yaml's defaults."""
    tree, sources = {}, {}
    config = os.path.dirname(SHIPPED)
    for ns, name in DEFAULTS.items():
        node = tree
        for part in ns.split("/"):
            node = node.setdefault(part, {})
        merge(node, read(os.path.join(config, name)), sources, os.path.join(config, name), ns)
    merge(tree, resolve(path, sources), {}, path)
    width = max(len(name) for name in sources)
    for name in sorted(sources):
        node = tree
        for part in name.split("/"):
            node = node[part]
        where = os.path.abspath(sources[name])  # the workspace's files relative to it
        where = os.path.relpath(where, ROOT) if where.startswith(ROOT + os.sep) else where
        print(f"{name + ':':<{width + 1}} {text(node):<12} # {where}")


def text(value):
    """A value as YAML writes it in a flow: true, 0.25, [1.65, 5.6]."""
    return yaml.safe_dump([value], default_flow_style=True, width=1e9).strip()[1:-1]


def redundant(paths):
    """Copies among experiments, one line each (empty when there is none): a setting a file gives
    the value its includes already give it, and two files that set more than one setting alike
    (one line in common is a coincidence, two a copy that stays behind when one changes: what
    they share belongs in a file both include)."""
    found, own_of = [], {}
    for path in paths:
        tree = read(path)
        includes = tree.pop("include", [])
        base = {}
        for name in includes if isinstance(includes, list) else [includes]:
            merge(base, resolve(base_path(name, path), {}), {}, path)
        own = {}
        merge({}, tree, own, path)
        own_of[path] = set()
        for name in sorted(own):
            node, value = base, tree
            for part in name.split("/"):
                node = node.get(part, {}) if isinstance(node, dict) else {}
                value = value[part]
            own_of[path].add(f"{name}: {text(value)}")
            if node == value and not (isinstance(value, dict) and not value):
                found.append(f"{path}: {name}: {text(value)} is what its includes give it "
                             "already")
    for i, a in enumerate(paths):
        for b in paths[i + 1:]:
            common = sorted(own_of[a] & own_of[b])
            if len(common) > 1:
                found.append(f"{a} and {b} both set {len(common)} settings alike "
                             f"({'; '.join(common)}): put them in a file both include")
    return found


def write_resolved(tree, path):
    """`tree` as YAML at `path` (whole or not at all); in the launch's folder of resolved files
    (/tmp/aar_experiments), those of launches over an hour old are removed."""
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        os.makedirs(folder, exist_ok=True)
        if os.path.basename(folder) == "aar_experiments":
            os.chmod(folder, 0o1777)  # shared by the machine's users, as /tmp is
    if os.path.basename(folder) == "aar_experiments":
        for old in os.listdir(folder):
            try:
                if time.time() - os.path.getmtime(os.path.join(folder, old)) > 3600:
                    os.remove(os.path.join(folder, old))
            except OSError:
                pass  # another launch removed it first
    with open(path + ".tmp", "w") as f:
        yaml.safe_dump(tree, f, default_flow_style=False)
    os.replace(path + ".tmp", path)


def sim_rigs(tree):
    """The names of the experiment's sim rigs, in order (one rig, stereo, when it sets none)."""
    return [str(r.get("name")) if isinstance(r, dict) else str(r)
            for r in tree.get("sim", {}).get("rigs", [{"name": "stereo"}])]


def check_rigs(tree, rigs, path):
    """Refuses a launch's rig list that is not the experiment's sim rigs."""
    names = rigs.split(",")
    wanted = sim_rigs(tree)
    if names[0] != "stereo" or len(set(names)) != len(names):
        raise Refused(f"rigs:={rigs}: the first rig must be stereo and each named once")
    if names != wanted:
        raise Refused(f"{path}: its sim rigs are {','.join(wanted)}, but the launch runs "
                      f"rigs:={rigs} (give rigs:={','.join(wanted)})")


def rig_part(tree):
    """A further rig's settings: the experiment's for the first rig's aar_stereo and occlusion."""
    part = {}
    if tree.get("stereo", {}).get("aar_stereo"):
        part["aar_stereo"] = tree["stereo"]["aar_stereo"]
    if tree.get("occlusion"):
        part["occlusion"] = tree["occlusion"]
    return part


def options(args):
    """FILE and its --resolved, --rigs and --rig-part values; None when malformed."""
    if not args or args[0].startswith("--") or len(args) % 2 != 1:
        return None
    flags = dict(zip(args[1::2], args[2::2]))
    if not set(flags) <= {"--resolved", "--rigs", "--rig-part"}:
        return None
    if ("--rigs" in flags) != ("--rig-part" in flags):
        return None
    return args[0], flags


def main(argv):
    args = argv[1:]
    try:
        if len(args) >= 2 and args[0] == "--redundant":
            found = redundant(args[1:])
            for line in found:
                print(f"check_experiment: {line}", file=sys.stderr)
            return 1 if found else 0
        if len(args) == 2 and args[0] == "--rigs-of":
            print(",".join(sim_rigs(resolve(args[1], {}))))
            return 0
        if len(args) == 2 and args[0] == "--show":
            try:
                show(args[1])
            except BrokenPipeError:  # a reader that stopped early (| head)
                sys.stderr.close()
            return 0
        parsed = options(args)
        if parsed is None:
            print(__doc__.splitlines()[1].strip() + "\n" + __doc__.splitlines()[2].strip(),
                  file=sys.stderr)
            return 2
        path, flags = parsed
        tree = resolve(path, {})
        if "--rigs" in flags:
            check_rigs(tree, flags["--rigs"], path)
    except Refused as e:
        for line in str(e).splitlines():
            print(f"check_experiment: {line}", file=sys.stderr)
        return 1
    for flag, content in (("--resolved", tree), ("--rig-part", rig_part(tree))):
        if flag not in flags:
            continue
        try:
            write_resolved(content, flags[flag])
        except OSError as e:
            print(f"check_experiment: cannot write {flags[flag]}: {e.strerror}", file=sys.stderr)
            return 1
    print(" ".join(sorted(tree)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
