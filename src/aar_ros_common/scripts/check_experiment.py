#!/usr/bin/env python3
"""Checks an experiment file's namespaces before a launch loads it:
  check_experiment.py FILE
An experiment (config/experiments/NAME.yaml) sets parameters of the stages by their node names:
sim, stereo/aar_stereo, occlusion, registration, eval. Each stage refuses a key it does not know
(ParamReader), but a namespace no stage reads (a misspelt `registraton:`) would be loaded and
ignored without a word: this refuses it, naming the file and the namespace, and exits 1.
On success it prints the checked namespaces (launch files use it as a command parameter, which
makes roslaunch stop before any node starts when the check fails); the campaign driver runs it
on every experiment of a campaign before the first run."""
import sys

import yaml

# The stages' node names (launch/include/processing.launch, launch/pipeline.launch): a mapping
# means a namespace of namespaces (stereo's node is stereo/aar_stereo).
STAGES = {"sim": None, "stereo": {"aar_stereo": None}, "occlusion": None, "registration": None,
          "eval": None}


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


def main(argv):
    if len(argv) != 2:
        print(__doc__.splitlines()[1].strip(), file=sys.stderr)
        return 2
    try:
        with open(argv[1]) as f:
            tree = yaml.safe_load(f) or {}
    except (OSError, yaml.YAMLError) as e:
        print(f"check_experiment: {argv[1]}: not readable: {e}", file=sys.stderr)
        return 1
    found = problems(tree, STAGES, "")
    for p in found:
        print(f"check_experiment: {argv[1]}: {p}", file=sys.stderr)
    if found:
        return 1
    print(" ".join(sorted(tree)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
