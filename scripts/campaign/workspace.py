"""The workspace a campaign runs in: its root, build, ROS environment, ports and provenance."""
import datetime
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PROG = "run"  # the wrapper's name, for messages (set by cli)


class Refused(Exception):
    """Bad input, named: the driver prints it and exits 2 before anything runs."""


def write_file(path, text):
    """Writes `text` to `path` whole or not at all (through a temporary file and a rename): a
    full disk leaves the old file or none, never a truncated one. Raises OSError."""
    tmp = path + ".tmp"
    try:
        with open(tmp, "w") as f:
            f.write(text)
        os.replace(tmp, path)
    except OSError as e:
        try:
            os.remove(tmp)
        except OSError:
            pass
        raise OSError(e.errno, e.strerror, path) from None  # a failed close names no file


def os_error(e):
    """An OSError as one line naming the file: "PATH: No space left on device" (a copy's
    destination, not its source)."""
    path = e.filename2 or e.filename
    return f"{path}: {e.strerror}" if path else (e.strerror or str(e))


def fail(message, code=2):
    print(f"{PROG}: {message}", file=sys.stderr)
    sys.exit(code)


def say(message, error=False):
    print(f"{PROG}: {message}", file=sys.stderr if error else sys.stdout, flush=True)


def devel():
    return os.path.join(ROOT, os.environ.get("AAR_DEVEL", "devel"))


def tool(package, name):
    return os.path.join(devel(), "lib", package, name)


def absolute(path, caller):
    """A path as the caller meant it: relative paths are the caller's working folder's."""
    return os.path.normpath(os.path.join(caller, path)) if path else path


def setup_and_build():
    """scripts/setup and scripts/build, so that a fresh clone runs; stops the driver on failure."""
    if subprocess.run([os.path.join(ROOT, "scripts/setup")], stdout=subprocess.DEVNULL).returncode:
        fail("scripts/setup failed; run it to see why", 1)
    if subprocess.run([os.path.join(ROOT, "scripts/build")], stdout=subprocess.DEVNULL).returncode:
        fail("build failed; run scripts/build to see why", 1)


_ros_env = None


def ros_env():
    """The environment of devel/setup.bash (sourced once, in bash, as the nodes need it)."""
    global _ros_env
    if _ros_env is None:
        setup = os.path.join(devel(), "setup.bash")
        if not os.path.isfile(setup):
            fail(f"{setup} does not exist: build first (scripts/build)", 1)
        dump = subprocess.run(["bash", "-c", f'set +u; source "{setup}" >/dev/null && env -0'],
                              capture_output=True, check=True).stdout
        _ros_env = dict(e.split("=", 1) for e in dump.decode().split("\0") if "=" in e)
        _ros_env["PATH"] = "/usr/bin:/bin:" + _ros_env.get("PATH", "")
    return dict(_ros_env)


def free_ports(count, seed=None):
    """Distinct free ports for private ROS masters (scripts/ros-port picks each)."""
    out, seed = [], os.getpid() if seed is None else seed
    while len(out) < count:
        port = subprocess.run([os.path.join(ROOT, "scripts/ros-port"), str(seed)],
                              capture_output=True, text=True, check=True).stdout.strip()
        seed += 7919
        if port not in out:
            out.append(port)
    return out


def commit():
    """The commit checked out, marked when the work tree differs from it."""
    sha = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                         capture_output=True, text=True).stdout.strip() or "unknown"
    dirty = subprocess.run(["git", "-C", ROOT, "diff", "--quiet"],
                           stderr=subprocess.DEVNULL).returncode != 0
    return sha + (" (with uncommitted changes)" if dirty else "")


def machine():
    gib = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") // 2**30
    return f"{os.cpu_count()} cores, {gib} GiB, {os.uname().sysname} {os.uname().release}"


def utc_now():
    return datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M:%S")


def utc_stamp():
    return datetime.datetime.now(datetime.timezone.utc).strftime("%Y%m%d-%H%M%S")


ANSI = re.compile(r"\x1b\[[0-9;]*m")


def log_lines(path):
    """A roslaunch log's lines without their colour codes ([] when it cannot be read)."""
    try:
        with open(path, errors="replace") as f:
            return [ANSI.sub("", line.rstrip("\n")) for line in f]
    except OSError:
        return []
