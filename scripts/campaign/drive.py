"""Driving a campaign to its end: the runs not yet done through the chosen engine, then the
reports, and a last word on what is missing and how to resume."""
import json
import os
import time

from campaign import local, slurm, cluster
from campaign.campaign import append_provenance
from campaign.execute import is_done, reason_of, retried
from campaign.progress import Progress
from campaign.reports import write_reports
from campaign.workspace import Refused, commit, fail, say, utc_now, write_file


def finish(campaign, engine, seconds, flown, interrupted=False):
    """Records the outcome in run.txt, writes the reports; returns 0 when complete."""
    missing = [r.key for r in campaign.runs if not is_done(r, campaign.out)]
    lines = [f"wall time: {seconds / 60:.1f} min for {flown} runs ({engine})"]
    again = {r.key: retried(r, campaign.out) for r in campaign.runs}
    again = {key: attempts for key, attempts in again.items() if attempts}
    if again:  # a crash the retry made good is still a crash: said in run.txt and the reports
        lines.append(f"runs that failed and were flown again ({len(again)}):")
        lines += [f"  {key}: {'; '.join(attempts)}" for key, attempts in again.items()]
    if interrupted:
        lines.append("interrupted: the runs not finished are missing")
    if missing:
        lines.append(f"failed or missing runs ({len(missing)}): {', '.join(missing)}")
        reasons = {r.key: reason_of(r, campaign.out) for r in campaign.runs if r.key in missing}
        lines += [f"  {key}: {why}" for key, why in reasons.items() if why]
    append_provenance(campaign, lines)
    try:
        path, ok = write_reports(campaign, complete=not missing)
    except KeyboardInterrupt:
        say(f"interrupted while writing the reports (the step running was stopped); "
            f"scripts/run --resume {campaign.out} writes them", error=True)
        raise
    if not ok:
        say(f"{path}: not every report step succeeded (above)", error=True)
    else:
        say(f"wrote {path}")
    if missing:
        say(f"incomplete: {len(missing)} of {len(campaign.runs)} runs failed or missing: "
            f"{', '.join(missing[:12])}{' ...' if len(missing) > 12 else ''}"
            f"{'' if ok else '; a report failed'}; fly what is missing with: "
            f"scripts/run --resume {campaign.out}", error=True)
        return 1
    if not ok:
        say(f"incomplete: every run is done, but a report failed; scripts/run --resume "
            f"{campaign.out} writes the reports again", error=True)
        return 1
    return 0


def _jobs(a, campaign, runs):
    """--jobs, or 1 for one path (the main job, as it always ran), else 2 if there are cores."""
    if a.jobs is not None:
        return int(a.jobs)
    if campaign.kind == "run":
        return 1
    return max(1, min(os.cpu_count() or 1, 2, len(runs)))


def drive(campaign, a, started=None):
    """Flies what is not done and writes the reports; `started`: the state folder of a
    single-node cluster the driver brought up (stopped here)."""
    todo = [r for r in campaign.runs if not is_done(r, campaign.out)]
    if len(todo) < len(campaign.runs):
        say(f"{len(campaign.runs) - len(todo)} of {len(campaign.runs)} runs done already; "
            f"flying the other {len(todo)}")
        append_provenance(campaign, [f"resumed {utc_now()} UTC at commit {commit()}: "
                                     f"{len(todo)} runs to fly"])
    start = time.monotonic()
    flying = {r.key for r in todo}
    progress = Progress(campaign.runs, [r.key for r in campaign.runs if r.key not in flying])
    if a.engine == "local":
        jobs = _jobs(a, campaign, todo)
        say(f"{len(todo)} runs, {jobs} at a time; out {campaign.out}")
        _, interrupted = local.run_local(campaign, todo, jobs, progress) if todo else ([], False)
        return finish(campaign, f"local, {jobs} at a time", time.monotonic() - start,
                      len(todo), interrupted)
    return _drive_slurm(campaign, a, todo, start, started, progress)


def _drive_slurm(campaign, a, todo, start, started, progress):
    if not todo:
        cluster.stop(started)
        return finish(campaign, "slurm", 0.0, 0)
    try:
        indices = [campaign.runs.index(r) for r in todo]
        arrays, merge = slurm.submit(campaign, indices, a.partition, int(a.cpus_per_task),
                                    int(a.max_parallel))
        say(f"{len(todo)} runs submitted to Slurm as job array {', '.join(arrays)} "
            f"(logs: {campaign.out}/slurm/ARRAY-task-N.log), merge job {merge} after them")
        if a.no_wait:
            say(f"not waiting: the merge job writes the reports; squeue -j "
                f"{','.join(arrays)},{merge} to watch, scripts/run --resume {campaign.out} "
                f"for what fails")
            return 0
        bound = sum(campaign.runs[i].timeout() for i in indices) + 600
        record = slurm.wait(campaign, arrays, merge, bound, progress, own_cluster=bool(started))
    except Refused as e:
        fail(str(e))
    except KeyboardInterrupt:
        return 1
    finally:
        if not a.no_wait:
            cluster.stop(started)
    if record is None:
        say(f"the merge job left no record ({campaign.out}/slurm/{merge}-merge.log says why); "
            f"scripts/run --resume {campaign.out} writes the reports", error=True)
        return 1
    say(f"{len(todo)} runs through Slurm in {(time.monotonic() - start) / 60:.1f} min; "
        f"wrote {record['report']}")
    if record["status"] != 0:
        say(f"incomplete: {', '.join(record['missing']) or 'a report failed'}; fly what is "
            f"missing with: scripts/run --resume {campaign.out}", error=True)
    return record["status"]


def record_merge(campaign, status, report):
    missing = [r.key for r in campaign.runs if not is_done(r, campaign.out)]
    write_file(os.path.join(campaign.out, "slurm", "merge.json"),
               json.dumps({"status": status, "report": report, "missing": missing}))
