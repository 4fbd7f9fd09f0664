"""The campaign driver: one place for the run plan, frame counts, timeouts, the roslaunch of one
run, provenance, engines (local processes or Slurm job arrays), resuming and the reports.

scripts/run (one path, --suite N or --worlds ideal,NAME,...) is a thin wrapper around it
(docs/CLUSTER.md); so are scripts/bench-realtime, two-hosts, slurm-local, replay and capture,
each around a module of its own here (cli.SCRIPTS)."""
