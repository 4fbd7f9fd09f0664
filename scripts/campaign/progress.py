"""A campaign's progress: runs done of all, frames a second and the time to go, as one updating
line on a terminal and as plain lines in a log (both engines: the local one as its runs end, the
Slurm one from the runs the queue has finished)."""
import sys
import time


def clock(seconds):
    """h:mm:ss"""
    seconds = int(round(seconds))
    return f"{seconds // 3600}:{seconds // 60 % 60:02d}:{seconds % 60:02d}"


class Progress:
    """Counts finished runs against the campaign's `runs` (each has .key and .frames). The rate
    is of this drive only (frames finished since it began over its wall time), so a resumed
    campaign does not count the runs it found done as flown in no time."""

    def __init__(self, runs, done_keys=(), stream=None, now=time.monotonic):
        self.frames = {r.key: r.frames for r in runs}
        self.total_frames = sum(self.frames.values())
        self.done = set(done_keys)
        self.before = sum(self.frames[k] for k in self.done)
        self.now, self.start = now, now()
        self.stream = stream or sys.stderr
        self.live = self.stream.isatty()

    def finished(self, key):
        self.done.add(key)

    def line(self):
        done_frames = sum(self.frames[k] for k in self.done)
        elapsed = max(self.now() - self.start, 1e-9)
        rate = (done_frames - self.before) / elapsed
        left = self.total_frames - done_frames
        eta = clock(left / rate) if rate > 0 else "unknown"
        return (f"{len(self.done)}/{len(self.frames)} runs, {done_frames}/{self.total_frames} "
                f"frames, {rate:.1f} frames/s, {clock(elapsed)} so far, {eta} to go")

    def clear(self):
        """Takes the updating line off a terminal before other output."""
        if self.live:
            self.stream.write("\r\033[K")
            self.stream.flush()

    def show(self):
        """The line: redrawn in place on a terminal, a plain line otherwise."""
        if self.live:
            self.stream.write("\r\033[K" + self.line())
            if len(self.done) == len(self.frames):
                self.stream.write("\n")
        else:
            self.stream.write("progress: " + self.line() + "\n")
        self.stream.flush()
