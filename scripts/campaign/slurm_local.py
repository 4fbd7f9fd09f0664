"""A Slurm cluster on this machine, for the campaign driver's --engine slurm when no cluster is
configured, and for its tests (docs/CLUSTER.md). No systemd: munged, slurmctld and slurmd run
as root with every file in one state folder, on free ports.
  scripts/slurm-local up [DIR] [--nodes N]
       installs Slurm and munge from Debian if missing, starts the daemons, waits until every
       node is idle; prints DIR last (default: a new /tmp/aar-slurm.XXXXXX). Then:
       export SLURM_CONF=DIR/slurm.conf
       One node (default): this machine, on 127.0.0.1. N >= 2: N compute nodes aar-node1..N,
       each slurmd in network and UTS namespaces of its own (hostname aar-nodeK, address
       169.254.X.1K on a bridge, where the controller is 169.254.X.1), the cores shared out.
  scripts/slurm-local down DIR [--keep]
       cancels DIR's jobs, stops its daemons (by their pid files), removes its namespaces and
       bridge, then DIR itself (--keep: DIR stays, with the daemons' logs in DIR/log)
  scripts/slurm-local kill DIR K kills node K (every process in its namespace, kill -9: a
                                 power cut); the controller marks it down within 15 s
AAR_SLURM_MAX_ARRAY_SIZE: the cluster's MaxArraySize (default Slurm's 1001).

(scripts/slurm-local is a wrapper around this module: python3 scripts/campaign slurm-local.)"""
import collections
import glob
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

from campaign.workspace import ROOT


def say(message):
    print(f"slurm-local: {message}", file=sys.stderr, flush=True)


def refuse(message):
    say(message)
    sys.exit(2)


def sh(*command, **kw):
    """A command that must work, as the bash script had it under `set -e`: on failure the
    script ends with its status."""
    status = subprocess.run(command, **kw).returncode
    if status:
        sys.exit(status)


def free_port(seed):
    """A port no one answers on, from a seed (scripts/ros-port's rule)."""
    return subprocess.run([os.path.join(ROOT, "scripts/ros-port"), str(seed)],
                          capture_output=True, text=True, check=True).stdout.strip()


def output(*command):
    return subprocess.run(command, capture_output=True, text=True).stdout


# The multi-node network: namespaces aar-slurm-X-K on a bridge aarslX in this namespace.
def net_names(octet, k):
    """(namespace, veth end here, veth end in the namespace) of node K."""
    return f"aar-slurm-{octet}-{k}", f"aarsl{octet}-{k}", f"aarsn{octet}-{k}"


def free_octet():
    """A 169.254.X.0/24 no interface and no namespace of ours uses."""
    start = os.getpid() % 200 + 20
    for o in list(range(start, 255)) + list(range(20, 255)):
        if f"inet 169.254.{o}." in output("ip", "-4", "addr", "show"):
            continue
        if any(line.startswith(f"aar-slurm-{o}-") for line in
               output("ip", "netns", "list").splitlines()):
            continue
        return o
    say("no free 169.254.X.0/24 for the nodes' network")
    return None


def make_network(octet, nodes):
    """The bridge (169.254.X.1, the controller) and a namespace a node; False when a namespace
    cannot be made."""
    def ip(*args):
        subprocess.run(["ip", *args])
    ip("link", "add", f"aarsl{octet}", "type", "bridge")
    ip("addr", "add", f"169.254.{octet}.1/24", "dev", f"aarsl{octet}")
    ip("link", "set", f"aarsl{octet}", "up")
    for k in range(1, nodes + 1):
        ns, host_end, node_end = net_names(octet, k)
        r = subprocess.run(["ip", "netns", "add", ns], capture_output=True, text=True)
        if r.returncode:
            say(f"cannot make network namespace {ns}: 'ip netns add' says: "
                f"{(r.stdout + r.stderr).strip()} (it needs root with CAP_SYS_ADMIN and a "
                "writable /run/netns)")
            return False
        ip("-n", ns, "link", "set", "lo", "up")  # each run's master and nodes: the loopback
        ip("link", "add", host_end, "type", "veth", "peer", "name", node_end)
        ip("link", "set", node_end, "netns", ns)
        ip("link", "set", host_end, "master", f"aarsl{octet}")
        ip("link", "set", host_end, "up")
        ip("-n", ns, "addr", "add", f"169.254.{octet}.{10 + k}/24", "dev", node_end)
        ip("-n", ns, "link", "set", node_end, "up")
    return True


def network(folder):
    """(octet, nodes) of a multi-node cluster's folder, or None."""
    try:
        with open(os.path.join(folder, "network")) as f:
            octet, nodes = f.read().split()[:2]
        return octet, int(nodes)
    except (OSError, ValueError):
        return None


def kill(pids, sig=signal.SIGKILL):
    for p in pids:
        try:
            os.kill(int(p), sig)
        except (OSError, ValueError):
            pass


def remove_network(folder):
    """Every process left in the nodes' namespaces killed, then the network."""
    net = network(folder)
    if net is None:
        return
    octet, nodes = net
    for k in range(1, nodes + 1):
        ns, host_end, _ = net_names(octet, k)
        kill(output("ip", "netns", "pids", ns).split())
        subprocess.run(["ip", "netns", "del", ns], stderr=subprocess.DEVNULL)
        subprocess.run(["ip", "link", "del", host_end], stderr=subprocess.DEVNULL)
    subprocess.run(["ip", "link", "del", f"aarsl{octet}"], stderr=subprocess.DEVNULL)
    os.remove(os.path.join(folder, "network"))


def node_lines(host, cpus, memory, nodes, octet):
    """slurm.conf's node lines: this machine, or aar-node1..N on the bridge."""
    if nodes == 1:
        return (f"NodeName={host} NodeAddr=127.0.0.1 CPUs={cpus} RealMemory={memory} "
                f"State=UNKNOWN\nPartitionName=aar Nodes={host} Default=YES MaxTime=INFINITE "
                "State=UP")
    lines = [f"NodeName=aar-node{k} NodeAddr=169.254.{octet}.{10 + k} CPUs={cpus} "
             f"RealMemory={memory} State=UNKNOWN" for k in range(1, nodes + 1)]
    lines.append(f"PartitionName=aar Nodes=aar-node[1-{nodes}] Default=YES MaxTime=INFINITE "
                 "State=UP")
    # A node that stops answering is down (and its jobs requeued) within 15 s, not Slurm's 300.
    lines.append("SlurmdTimeout=15")
    return "\n".join(lines)


def write_conf(folder, host, ctld_addr, ctld_port, node_port, nodes):
    with open(os.path.join(folder, "slurm.conf"), "w") as f:
        f.write(f"""# Written by scripts/slurm-local: this machine; every file in {folder}.
ClusterName=aar
SlurmctldHost={host}({ctld_addr})
SlurmctldPort={ctld_port}
SlurmdPort={node_port}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
# A run requeued (its node lost) waits cred_expire before it flies again: Slurm's 120 s is for
# credentials sent across a large cluster; one machine's nodes need a few.
AuthInfo=socket={folder}/munge/munge.sock,cred_expire=30
StateSaveLocation={folder}/state
SlurmdSpoolDir={folder}/spool/%n
SlurmctldPidFile={folder}/run/slurmctld.pid
SlurmdPidFile={folder}/run/slurmd-%n.pid
SlurmctldLogFile={folder}/log/slurmctld.log
SlurmdLogFile={folder}/log/slurmd-%n.log
# No cgroups in a container: processes tracked by parentage, tasks not bound.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SwitchType=switch/none
MpiDefault=none
MailProg=/bin/true
# One run per core at a time.
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
# A dependent job whose dependency can never be met is cancelled, not left pending; the
# scheduler looks at new jobs at once.
DependencyParameters=kill_invalid_depend
SchedulerParameters=batch_sched_delay=0
MinJobAge=3600
# Task ids of one array run from 0 to this minus 1 (AAR_SLURM_MAX_ARRAY_SIZE: the tests set it
# small to split a campaign over several arrays, as a large campaign is on a real cluster).
MaxArraySize={os.environ.get("AAR_SLURM_MAX_ARRAY_SIZE") or 1001}
KillWait=10
InactiveLimit=0
{nodes}
""")


def start_nodes(folder, nodes, octet):
    conf = os.path.join(folder, "slurm.conf")
    if nodes == 1:
        os.makedirs(os.path.join(folder, "spool", short_host()), exist_ok=True)
        sh("slurmd", "-f", conf)
        return
    for k in range(1, nodes + 1):
        ns = net_names(octet, k)[0]
        os.makedirs(os.path.join(folder, "spool", f"aar-node{k}"), exist_ok=True)
        # Its own hostname (UTS namespace) and address; munged's socket is a file every node
        # sees. nsenter, not 'ip netns exec', which mounts a /sys of the namespace's without
        # cgroups.
        sh("nsenter", f"--net=/run/netns/{ns}", "unshare", "--uts", "sh", "-c",
           f"hostname aar-node{k} && exec slurmd -N aar-node{k} -f '{conf}'")


def wait_idle(folder, nodes):
    """Every node idle within 60 s, or the logs shown and everything down."""
    deadline, state = time.monotonic() + 60, ""
    while True:
        r = subprocess.run(["sinfo", "-h", "-N", "-o", "%T"], capture_output=True, text=True)
        if r.returncode == 0:
            counts = collections.Counter(r.stdout.split())
            state = " ".join(f"{counts[s]} {s}" for s in sorted(counts))
            up = output("sinfo", "-h", "-N", "-t", "idle,mixed,allocated", "-o", "%N")
            if len(up.splitlines()) == nodes:
                return
        if time.monotonic() >= deadline:
            say(f"not every node is up after 60 s (states: '{state or 'none'}'); logs in "
                f"{folder}/log:")
            logs = sorted(glob.glob(os.path.join(folder, "log", "*.log")))
            if logs:
                subprocess.run(["tail", "-n", "20", *logs], stdout=sys.stderr)
            down(folder, keep=True)
            sys.exit(1)
        time.sleep(0.5)


def short_host():
    return socket.gethostname().split(".")[0]


def up(argv):
    folder, nodes = "", 1
    while argv:
        if argv[0] == "--nodes":
            value = argv[1] if len(argv) > 1 else ""
            if not re.fullmatch(r"[1-9][0-9]?", value):
                refuse(f"--nodes needs a count from 1 to 99, not '{value}'")
            nodes, argv = int(value), argv[2:]
        elif argv[0].startswith("-"):
            refuse(f"up: unknown option '{argv[0]}'")
        else:
            folder, argv = argv[0], argv[1:]
    sh(os.path.join(ROOT, "scripts/setup"), os.path.join(ROOT, "scripts/debian-packages-slurm.txt"),
       stdout=sys.stderr)
    folder = os.path.abspath(folder) if folder else tempfile.mkdtemp(prefix="aar-slurm.",
                                                                       dir="/tmp")
    os.makedirs(folder, exist_ok=True)
    os.chmod(folder, 0o755)  # munged wants every folder of its socket's path searchable
    for sub in ("munge", "state", "spool", "log", "run"):
        os.makedirs(os.path.join(folder, sub), exist_ok=True)
    host = short_host()
    cpus = max(1, len(os.sched_getaffinity(0)) // nodes)
    mem = next(line.split()[1] for line in output("free", "-m").splitlines()
               if line.startswith("Mem:"))
    memory = int(mem) // 2 // nodes
    pid = os.getpid()
    ctld_port, node_port = free_port(pid), free_port(pid + 4241)
    if node_port == ctld_port:
        node_port = free_port(pid + 9973)
    octet, ctld_addr = 0, "127.0.0.1"
    if nodes > 1:
        if os.geteuid() != 0:
            refuse(f"--nodes {nodes} needs root (network namespaces)")
        octet = free_octet()
        if octet is None:
            sys.exit(1)
        with open(os.path.join(folder, "network"), "w") as f:
            f.write(f"{octet} {nodes}\n")
        if not make_network(octet, nodes):
            down(folder, keep=True)
            sys.exit(1)
        ctld_addr = f"169.254.{octet}.1"
    key = os.path.join(folder, "munge/munge.key")
    if not os.path.isfile(key):
        sh("mungekey", "-c", "-k", key)
    os.chmod(key, 0o400)
    sh("munged", f"--socket={folder}/munge/munge.sock", f"--key-file={key}",
       f"--pid-file={folder}/run/munged.pid", f"--log-file={folder}/log/munged.log",
       f"--seed-file={folder}/munge/munged.seed")
    write_conf(folder, host, ctld_addr, ctld_port, node_port,
               node_lines(host, cpus, memory, nodes, octet))
    conf = os.environ["SLURM_CONF"] = os.path.join(folder, "slurm.conf")
    sh("slurmctld", "-f", conf)
    start_nodes(folder, nodes, octet)
    wait_idle(folder, nodes)
    if nodes == 1:
        say(f"up: node {host}, {cpus} CPUs, partition aar; export SLURM_CONF={conf}")
    else:
        say(f"up: nodes aar-node[1-{nodes}] (169.254.{octet}.11 on, {cpus} CPUs each; "
            f"controller 169.254.{octet}.1), partition aar; export SLURM_CONF={conf}")
    print(folder, flush=True)
    return 0


def running(pid):
    """A process that runs (a zombie, which init here reaps late, answers kill -0 but is
    gone)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except (OSError, IndexError):
        return False


def pid_of(pid_file):
    """The pid in PID_FILE when that process runs, else None."""
    try:
        with open(pid_file) as f:
            pid = f.read().strip()
    except OSError:
        return None
    return pid if pid.isdigit() and running(pid) else None


def down(folder, keep=False):
    if not os.path.isfile(os.path.join(folder, "slurm.conf")):
        refuse(f"'{folder}' is no cluster of scripts/slurm-local")
    os.environ["SLURM_CONF"] = os.path.join(folder, "slurm.conf")
    run = os.path.join(folder, "run")
    if pid_of(os.path.join(run, "slurmctld.pid")):
        subprocess.run(["timeout", "10", "scancel", "--quiet", "--user=root"],
                       stderr=subprocess.DEVNULL)
    for pid_file in sorted(glob.glob(os.path.join(run, "slurmd*.pid"))) + [
            os.path.join(run, "slurmctld.pid"), os.path.join(run, "munged.pid")]:
        pid = pid_of(pid_file)
        if pid is None:
            continue
        kill([pid], signal.SIGTERM)
        for _ in range(75):
            if not running(pid):
                break
            time.sleep(0.2)
        if running(pid):
            say(f"{os.path.basename(pid_file)[:-len('.pid')]} ({pid}) ignored TERM: killed")
            kill([pid])
    # Job steps outlive slurmd (re-parented to init): those with files in this folder are its
    # own.
    for pid in output("pgrep", "-x", "slurmstepd").split():
        try:
            fds = os.listdir(f"/proc/{pid}/fd")
        except OSError:
            continue
        targets = []
        for fd in fds:
            try:
                targets.append(os.readlink(f"/proc/{pid}/fd/{fd}"))
            except OSError:
                pass
        if any(folder + "/" in t for t in targets):
            kill([pid])
    remove_network(folder)
    if keep:
        say(f"down: {folder} (kept: the daemons' logs in {folder}/log)")
    else:
        shutil.rmtree(folder, ignore_errors=True)
        say(f"down: {folder} (removed)")
    return 0


def kill_node(folder, k):
    """Every process of node K, kill -9."""
    net = network(folder)
    if net is None:
        refuse(f"'{folder}' is no multi-node cluster of scripts/slurm-local")
    octet, nodes = net
    if not (k.isdigit() and 1 <= int(k) <= nodes):
        refuse(f"kill: no node '{k}' (nodes 1 to {nodes})")
    pids = output("ip", "netns", "pids", net_names(octet, k)[0]).split()
    kill(pids)
    say(f"killed node aar-node{k}: {len(pids)} processes (kill -9)")
    return 0


def main(argv):
    os.environ["PATH"] = "/usr/bin:/bin:/usr/sbin:/sbin:" + os.environ.get("PATH", "")
    verb = argv[0] if argv else ""
    if verb == "up":
        return up(argv[1:])
    if verb == "down":
        if len(argv) > 2 and argv[2] != "--keep":
            refuse(f"down: unknown option '{argv[2]}'")
        if len(argv) < 2 or not argv[1]:
            refuse("down needs the state folder")
        return down(argv[1], keep=len(argv) > 2)
    if verb == "kill":
        if len(argv) < 2 or not argv[1]:
            refuse("kill needs the state folder")
        return kill_node(argv[1], argv[2] if len(argv) > 2 else "")
    print(__doc__.split("\n\n")[0], file=sys.stderr)  # the usage
    return 2
