"""The campaign driver: one place for the run plan, frame counts, timeouts, the roslaunch of one
run, provenance, engines (local processes or Slurm job arrays), resuming and the reports.

scripts/run, scripts/run --suite and scripts/realism are thin wrappers around it
(docs/CLUSTER.md); so are scripts/bench-realtime, two-hosts, slurm-local, replay and capture,
each around a module of its own here (cli.SCRIPTS)."""
