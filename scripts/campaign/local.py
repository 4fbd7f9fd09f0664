"""The local engine: the campaign's runs as processes on this machine, J at a time, each on a
ROS master of its own (a port per job slot)."""
import concurrent.futures
import signal
import threading

from campaign.execute import describe, eval_lines, execute, log_tail
from campaign.workspace import free_ports, say


def run_local(campaign, runs, jobs, progress):
    """Flies `runs` (a list of Run), counting each finished one on `progress`; returns (failed
    keys, interrupted)."""
    free = free_ports(jobs)
    # Re-entrant: the signal handler below takes it in the main thread, and a second signal can
    # arrive while the first one's handler holds it (`timeout` sends its SIGINT to the child
    # and to the child's group: seen to deadlock a driver with a plain lock).
    lock = threading.RLock()
    failed, flights, done = [], set(), [0]
    stop = threading.Event()

    def fly(run):
        if stop.is_set():
            return
        with lock:
            port = free.pop()

        def track(flight):
            with lock:
                flights.add(flight)
        status = execute(run, campaign.out, port, stop.is_set, track)
        with lock:
            free.append(port)
            done[0] += 1
            if status["status"] != "ok":
                failed.append(run.key)
            else:
                progress.finished(run.key)
            progress.clear()
            say(f"[{done[0]}/{len(runs)}] {run.key}: {run.frames} frames, {describe(status)}")
            progress.show()
            if campaign.kind == "run" and status["status"] == "ok":
                print(eval_lines(run, campaign.out), flush=True)
            if status["status"] == "failed":
                say(f"{run.key}: the end of its log:\n{log_tail(run, campaign.out)}", error=True)

    def interrupt(signum, frame):
        stop.set()
        with lock:
            for f in flights:
                f.stop()
    previous = [signal.signal(s, interrupt) for s in (signal.SIGINT, signal.SIGTERM)]
    try:
        with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
            list(pool.map(fly, runs))
    finally:
        for s, handler in zip((signal.SIGINT, signal.SIGTERM), previous):
            signal.signal(s, handler)
    return failed, stop.is_set()
