"""Two hosts (docs/MULTI_HOST.md): a camera host with the simulator or a recorded flight, the ROS
master and eval against truth (launch/camera_host.launch), and a perception host with the
processing graph (launch/perception_host.launch), on two machines that share a network.
  scripts/two-hosts camera --ip ADDR (--peer ADDR | --no-firewall) [--port P] [--rate HZ]
                           [--start-time S] [--flight-path FILE | --bag FILE [--bag-rate R]]
                           [--split images|cloud] [--experiment E] [--out DIR] [--rviz]
  scripts/two-hosts perception --master URI --ip ADDR [--peer ADDR | --no-firewall]
                               [--split images|cloud] [--experiment E] [--no-manager]
                               [--give-up S]
  scripts/two-hosts netns [--split images|cloud|both] [--experiment E] [--no-firewall] [--intruder] [--out DIR]
                          [--rate HZ] [--phase S] [--flight-path FILE] [--name N]
                          [--timeout S] [--break-link] [--no-build]
camera: the master at http://ADDR:P (default port 21311), ROS_IP=ADDR; the simulator
free-running at HZ (default 2) from path time S, or FILE.bag played at R times its speed
(--bag, default 1); eval's frames.csv in DIR (default /tmp/aar_camera_host).
perception: ROS_IP=ADDR, ROS_MASTER_URI=URI (http://HOST:PORT, the camera host's). It waits for
the master, saying which URI it cannot reach and why, and retries every 2 s (for ever, or S
seconds with --give-up S: then exit 1); then the graph (experiment E, default flight).
--split (both hosts the same; default images): images: the images cross the link, stereo runs
on the perception host; cloud: the camera host runs stereo too (experiment E's settings) and
only the cloud /stereo/points2 crosses the link (22 times less than the images at 47 to 44 m).
Rigs (issue 44): the experiment's sim rigs (flight_two_rigs: stereo,share_mirror) on both hosts
(the launches' rigs:=): the simulator flies them, a --bag must hold them, and each rig's images
(or with cloud its /R/points2) cross the link.
Firewall (both hosts; docs/MULTI_HOST.md, "Threat model"): an nftables table of its own (inet
aar_two_hosts) lets only the other host, --peer ADDR, on this host's link (ADDR's interface),
and loopback reach the ROS ports (the master's port, the nodes' ephemeral ports); it is removed
when the script ends, also on SIGINT, SIGTERM or a failure. The perception host's --peer is by
default the master's host. --no-firewall: none (warned about); any host may then register,
publish, set parameters or shut nodes down.
netns (root; for tests and measurements on one machine): network namespaces of its own (N-cam,
N-per; default N aar2h<pid>) joined by a veth pair on 169.254.X.1 and .2, the two hosts above
in them (each with its firewall inside its namespace), and for each split (default both) it
measures: poses back across the link (rate, accuracy from eval, latency from a frame leaving
the camera host to its pose back there), the link's bytes a frame and Mbit/s each way, the
messages' sizes; with images also the perception host killed (kill -9, every process) and
started again while the camera host runs on (time to the next pose), and a perception host
pointed at a master that does not exist. --intruder: a third namespace, N-out (169.254.X.3),
on the same link (a bridge in N-cam) tries a non-ROS port, to register a publisher with the
master, every port either host listens on, and to publish poses at x = 1e6 m; all must
fail with the firewall (eval then has no pose off by over 1 km) and succeed with --no-firewall.
The flight path: by default the last 20.8 s of the default approach slowed to 90 + 3 PHASE s;
each phase PHASE s (default 12). DIR (default results/two-hosts-<time>) gets summary.txt, the
logs and eval's frames.csv (eval/, eval-cloud/).
--break-link: the link is down (fault injection; the run must fail, not hang); --timeout S
(default 90): the longest wait for a pose. Everything it started is stopped and its namespaces
removed at the end, also on failure or interruption.
Exit status: 0 measured (summary.txt); 1 no pose across the link in time, or a host died; 2 a
bad argument, or a namespace of that name exists.

(scripts/two-hosts is a wrapper around this module: python3 scripts/campaign two-hosts.)"""
import csv
import ctypes
import glob
import math
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time
import xmlrpc.client

from campaign import arguments, bag as bags, workspace
from campaign.plan import experiment_rigs
from campaign.workspace import ROOT, Refused

NUMBER = re.compile(r"[0-9]+([.][0-9]+)?")
TABLE = "aar_two_hosts"


def bad(message):
    print(f"two-hosts: {message}", file=sys.stderr)
    sys.exit(2)


def valid_ip(addr):
    m = re.fullmatch(r"([0-9]{1,3})\.([0-9]{1,3})\.([0-9]{1,3})\.([0-9]{1,3})", addr)
    return bool(m) and all(int(g) <= 255 for g in m.groups())


def addresses():
    """(device, IPv4 address) of each address of this host (of its network namespace)."""
    out = subprocess.run(["ip", "-o", "-4", "addr", "show"], capture_output=True,
                         text=True).stdout
    return [(w[1], w[3].split("/")[0]) for w in (line.split() for line in out.splitlines())
            if len(w) > 3]


def check_local_ip(mode, addr):
    """ADDR is an address of this host: the one ROS_IP tells the other host to reach."""
    mine = [a for _, a in addresses()]
    if addr not in mine:
        bad(f"{mode}: --ip {addr} is not an address of this host ({' '.join(mine)})")


def check_peer(mode, peer, own):
    """The other host's address, for the firewall."""
    if not peer:
        bad(f"{mode}: --peer ADDR is needed (the other host's address on the link: only it may "
            "reach this host's ROS ports), or --no-firewall (any host on any network may)")
    if not valid_ip(peer):
        bad(f"{mode}: --peer takes an IPv4 address, not '{peer}'")
    if peer == own:
        bad(f"{mode}: --peer {peer} is this host's --ip; give the other host's address")


def check_experiment(mode, experiment):
    """The experiment's stereo rigs (its sim rigs, as the launches' rigs:= takes them)."""
    if not os.path.isfile(os.path.join(ROOT, "config/experiments", experiment + ".yaml")):
        bad(f"{mode}: --experiment: no experiment '{experiment}' in config/experiments/")
    try:
        return experiment_rigs(experiment)
    except Refused as e:
        bad(f"{mode}: --experiment: {e}")


def check_split(mode, split):
    if split not in ("images", "cloud"):
        bad(f"{mode}: --split takes images or cloud (where the graph is cut), not '{split}'")


def host_env(addr, master):
    """The ROS environment with ROS_IP and ROS_MASTER_URI; ROS_HOSTNAME, which would win over
    ROS_IP, unset. The master and the nodes advertise ROS_IP but listen on every interface: the
    firewall is what binds them."""
    if os.environ.get("ROS_HOSTNAME"):
        print(f"two-hosts: ROS_HOSTNAME={os.environ['ROS_HOSTNAME']} unset (it would win over "
              f"ROS_IP={addr})", file=sys.stderr)
    env = workspace.ros_env()
    env.pop("ROS_HOSTNAME", None)
    env.update(ROS_IP=addr, ROS_MASTER_URI=master)
    return env


# --- Firewall --------------------------------------------------------------------------------
# nftables rules (docs/MULTI_HOST.md, "Threat model"). ROS 1 servers listen on every interface
# whatever ROS_IP says: the master on its port, each node's XML-RPC and TCPROS servers on a port
# the kernel picks from its ephemeral range. The rules cover those ports (TCP and UDP, IPv4 and
# IPv6) on every interface; other ports (ssh) and replies to this host's own connections
# (conntrack: established) are left alone. New connections from anyone else are dropped (the
# sender sees a timeout, not a refusal), counted. The rules live in a table of their own,
# replaced as a whole if a killed run left it.

def link_device(addr):
    """The interface that holds ADDR."""
    return next((dev for dev, a in addresses() if a == addr), "")


def ros_ports(port):
    """The ROS ports as an nft set's elements: the master's PORT and the ephemeral range."""
    with open("/proc/sys/net/ipv4/ip_local_port_range") as f:
        lo, hi = (int(v) for v in f.read().split())
    return f"{lo}-{hi}" if lo <= int(port) <= hi else f"{port}, {lo}-{hi}"


def firewall_rules(addr, peer, port):
    """The table, as nft -f reads it."""
    dev, ports = link_device(addr), ros_ports(port)
    return f"""table inet {TABLE}
delete table inet {TABLE}
table inet {TABLE} {{
  chain input {{
    type filter hook input priority filter - 10; policy accept;
    iif "lo" accept
    ct state established,related accept
    iifname "{dev}" ip saddr {peer} meta l4proto {{ tcp, udp }} th dport {{ {ports} }} accept
    meta l4proto {{ tcp, udp }} th dport {{ {ports} }} counter drop comment "ROS ports: {peer} on {dev} only"
  }}
}}
"""


def firewall_up(addr, peer, port):
    """This host's ROS ports reachable from PEER on ADDR's interface and from loopback only;
    exits 1 naming what failed."""
    if not shutil.which("nft"):
        print("two-hosts: 'nft' (nftables) is not installed: scripts/setup installs it (or "
              "--no-firewall, unprotected)", file=sys.stderr)
        sys.exit(1)
    if subprocess.run(["nft", "list", "table", "inet", TABLE], stdout=subprocess.DEVNULL,
                      stderr=subprocess.DEVNULL).returncode == 0:
        print(f"two-hosts: replacing the nftables table inet {TABLE} a previous run left")
    r = subprocess.run(["nft", "-f", "-"], input=firewall_rules(addr, peer, port), text=True,
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    if r.returncode:
        print(f"two-hosts: cannot install the nftables table inet {TABLE}: nft says: "
              f"{r.stdout.rstrip()} (it needs root, CAP_NET_ADMIN)", file=sys.stderr)
        sys.exit(1)
    print(f"two-hosts: firewall (nftables table inet {TABLE}): this host's ROS ports "
          f"({ros_ports(port)}) reachable only from {peer} on {link_device(addr)} and from "
          "loopback; removed when this script ends")


def firewall_down():
    subprocess.run(["nft", "delete", "table", "inet", TABLE], stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)


def exit_status(code):
    """A child's return code as a shell gives it (killed by signal N: 128 + N)."""
    return 128 - code if code < 0 else code


def run_host(firewall, addr, peer, port, command, env):
    """COMMAND with the firewall up (unless --no-firewall, warned about), the table removed when
    it ends, also on SIGINT or SIGTERM (passed on to it as SIGINT, roslaunch's stop) or a
    failure. Returns COMMAND's exit status."""
    if firewall:
        try:
            firewall_up(addr, peer, port)
        except BaseException:
            firewall_down()
            raise
    else:
        print(f"two-hosts: WARNING: --no-firewall: the master (port {port}) and every node's "
              "ports answer any host on any network this host is on (ROS 1 has no "
              "authentication)", file=sys.stderr)
    try:
        child = subprocess.Popen(command, stdin=subprocess.DEVNULL, env=env)

        def forward(signum, frame):
            try:
                child.send_signal(signal.SIGINT)
            except OSError:
                pass
        for s in (signal.SIGINT, signal.SIGTERM):
            signal.signal(s, forward)
        return exit_status(child.wait())
    finally:
        if firewall:
            firewall_down()


def interrupted(signum, frame):
    sys.exit(130)


# --- camera ----------------------------------------------------------------------------------

def camera(argv):
    p = arguments.Parser("two-hosts camera", __doc__, who="two-hosts: camera")
    p.add_argument("--ip", default="")
    p.add_argument("--port", default="21311")
    p.add_argument("--rate", default="2")
    p.add_argument("--start-time", default="0")
    p.add_argument("--flight-path", default=os.path.join(ROOT, "config/flight_paths/"
                                                         "approach_default.csv"))
    p.add_argument("--bag", default="")
    p.add_argument("--bag-rate", default="1")
    p.add_argument("--out", default="/tmp/aar_camera_host")
    p.add_argument("--rviz", action="store_true")
    p.add_argument("--split", default="images")
    p.add_argument("--experiment", default="flight")
    p.add_argument("--peer", default="")
    p.add_argument("--no-firewall", action="store_true")
    a = p.parse_args(argv)
    caller = os.getcwd()
    if a.ip and not valid_ip(a.ip):
        bad(f"camera: --ip takes an IPv4 address, not '{a.ip}'")
    if not (re.fullmatch(r"[0-9]{1,5}", a.port) and 1024 <= int(a.port) <= 65535):
        bad(f"camera: --port takes a port from 1024 to 65535, not '{a.port}'")
    if not (NUMBER.fullmatch(a.rate) and 0 < float(a.rate) <= 60):
        bad(f"camera: --rate takes frames per second (above 0, at most 60), not '{a.rate}'")
    if not NUMBER.fullmatch(a.start_time):
        bad(f"camera: --start-time takes seconds, not '{a.start_time}'")
    path = arguments.absolute(a.flight_path, caller)
    if not os.path.isfile(path):
        bad(f"camera: --flight-path '{path}' does not exist")
    bag = arguments.absolute(a.bag, caller)
    if bag and not os.path.isfile(bag):
        bad(f"camera: --bag '{bag}' does not exist")
    if not (NUMBER.fullmatch(a.bag_rate) and float(a.bag_rate) > 0):
        bad(f"camera: --bag-rate takes a positive speed factor, not '{a.bag_rate}'")
    check_split("camera", a.split)
    rigs = check_experiment("camera", a.experiment)
    if bag and rigs != "stereo":  # each of the experiment's rigs in the bag
        held = bags.rigs_of(bags.read(bag))
        if any(r not in held for r in rigs.split(",")):
            bad(f"camera: experiment '{a.experiment}' flies the rigs {rigs}, but --bag '{bag}' "
                f"holds {','.join(held) or 'no rig'}")
    if not a.ip:
        bad("camera: --ip ADDR is needed (this host's address on the link)")
    check_local_ip("camera", a.ip)
    if not a.no_firewall:
        check_peer("camera", a.peer, a.ip)
    out = arguments.absolute(a.out, caller)
    try:
        os.makedirs(out, exist_ok=True)
        writable = os.access(out, os.W_OK)
    except OSError:
        writable = False
    if not writable:
        bad(f"camera: --out '{out}' cannot be written")
    master = f"http://{a.ip}:{a.port}"
    env = host_env(a.ip, master)
    about = (f"playing {bag} at {a.bag_rate} times its speed" if bag else
             f"simulator at {a.rate} Hz from {path}, t = {a.start_time} s")
    print(f"camera host: master {master}, ROS_IP {a.ip}; {about}; split {a.split}")
    return run_host(not a.no_firewall, a.ip, a.peer, a.port, [
        "roslaunch", "-p", a.port, os.path.join(ROOT, "launch/camera_host.launch"),
        f"flight_path:={path}", f"rate:={a.rate}", f"start_time:={a.start_time}", f"bag:={bag}",
        f"bag_rate:={a.bag_rate}", f"output_dir:={out}", f"rviz:={str(a.rviz).lower()}",
        f"split:={a.split}", f"experiment:={a.experiment}", f"rigs:={rigs}"], env)


# --- perception ------------------------------------------------------------------------------

def master_answers(uri):
    """None when the ROS master at URI answers, else why not."""
    previous = socket.getdefaulttimeout()
    socket.setdefaulttimeout(3.0)
    try:
        code, _, _ = xmlrpc.client.ServerProxy(uri).getPid("/perception_host")
        return None if code == 1 else f"the master answered with code {code}"
    except socket.timeout:
        return "no answer within 3 s"
    except OSError as e:
        return e.strerror or str(e)
    except Exception as e:
        return f"not a ROS master: {e}"
    finally:
        socket.setdefaulttimeout(previous)


def perception(argv):
    p = arguments.Parser("two-hosts perception", __doc__, who="two-hosts: perception")
    p.add_argument("--master", default="")
    p.add_argument("--ip", default="")
    p.add_argument("--experiment", default="flight")
    p.add_argument("--no-manager", action="store_true")
    p.add_argument("--give-up", default="0")
    p.add_argument("--split", default="images")
    p.add_argument("--peer", default="")
    p.add_argument("--no-firewall", action="store_true")
    a = p.parse_args(argv)
    if a.master and not re.fullmatch(r"http://[A-Za-z0-9.-]+:[0-9]{1,5}/?", a.master):
        bad("perception: --master takes http://HOST:PORT (the camera host's master), "
            f"not '{a.master}'")
    if a.ip and not valid_ip(a.ip):
        bad(f"perception: --ip takes an IPv4 address, not '{a.ip}'")
    rigs = check_experiment("perception", a.experiment)
    if not re.fullmatch(r"[0-9]{1,6}", a.give_up):
        bad(f"perception: --give-up takes whole seconds (0: never), not '{a.give_up}'")
    check_split("perception", a.split)
    if not a.master:
        bad("perception: --master URI is needed (the camera host's, http://HOST:PORT)")
    if not a.ip:
        bad("perception: --ip ADDR is needed (this host's address on the link)")
    check_local_ip("perception", a.ip)
    host, port = a.master[len("http://"):].rstrip("/").rsplit(":", 1)
    peer = a.peer or (host if valid_ip(host) else "")  # the peer: the master's host, unless given
    if not a.no_firewall:
        check_peer("perception", peer, a.ip)
    uri = a.master.rstrip("/")
    env = host_env(a.ip, uri)
    for s in (signal.SIGINT, signal.SIGTERM):
        signal.signal(s, interrupted)
    # roslaunch, given a master on another host that does not answer, exits at once; so wait
    # here, saying what is wrong, until it answers.
    began, said, remind, give_up = time.monotonic(), None, 0, int(a.give_up)
    while True:
        why = master_answers(uri)
        if why is None:
            break
        waited = int(time.monotonic() - began)
        if why != said or waited >= remind:
            print(f"perception host: no ROS master at {uri} ({why}), {waited} s so far; retrying "
                  "every 2 s. Is the camera host up, the link up, and --master its address?",
                  file=sys.stderr)
            said, remind = why, waited + 30
        if give_up > 0 and waited >= give_up:
            print(f"perception host: gave up after {waited} s: no ROS master at {uri}",
                  file=sys.stderr)
            return 1
        time.sleep(2)
    print(f"perception host: master {uri} answers (after {int(time.monotonic() - began)} s); "
          f"ROS_IP {a.ip}; starting the processing graph ({a.experiment}, split {a.split})")
    return run_host(not a.no_firewall, a.ip, peer, port, [
        "roslaunch", os.path.join(ROOT, "launch/perception_host.launch"),
        f"experiment:={a.experiment}", f"manager:={str(not a.no_manager).lower()}",
        f"split:={a.split}", f"rigs:={rigs}"], env)


# --- netns -----------------------------------------------------------------------------------

def run(*command):
    """An `ip` command of the link's making: a failure stops the run with its status."""
    r = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if r.returncode:
        print(f"two-hosts: {' '.join(command)}: {r.stderr.strip()}", file=sys.stderr)
        sys.exit(r.returncode)


def output(*command):
    return subprocess.run(command, capture_output=True, text=True).stdout


def namespaces():
    return [line.split()[0] for line in output("ip", "netns", "list").splitlines() if line]


def ns_pids(ns):
    return [int(p) for p in output("ip", "netns", "pids", ns).split()]


def kill(pids, sig):
    for p in pids:
        try:
            os.kill(p, sig)
        except OSError:
            pass


class Failed(Exception):
    """The run failed: said in summary.txt ("FAIL: ..."), exit 1."""


class Netns:
    """Both hosts on this machine, each in a network namespace of its own."""

    def __init__(self, a):
        self.a, self.out, self.name = a, a.out, a.name
        n = a.name
        self.ns_cam, self.ns_per, self.ns_out = f"{n}-cam", f"{n}-per", f"{n}-out"
        self.veth_cam, self.veth_per = f"{n}c", f"{n}p"
        self.bridge, self.veth_in, self.veth_out = f"{n}b", f"{n}i", f"{n}o"
        self.namespaces = [self.ns_cam, self.ns_per] + ([self.ns_out] if a.intruder else [])
        # Link-local only (169.254.0.0/16): nothing outside the namespaces is ever addressed.
        octet = os.getpid() % 250 + 1
        self.ip_cam, self.ip_per = f"169.254.{octet}.1", f"169.254.{octet}.2"
        self.ip_out, self.ip_nobody = f"169.254.{octet}.3", f"169.254.{octet}.99"
        self.port = "21311"  # fixed: each namespace has its own loopback and this link only
        self.master = f"http://{self.ip_cam}:{self.port}"
        if a.no_firewall:
            self.cam_fw = self.per_fw = ["--no-firewall"]
        else:
            self.cam_fw, self.per_fw = ["--peer", self.ip_per], ["--peer", self.ip_cam]
        self.probe_env = ["env", f"ROS_IP={self.ip_cam}", f"ROS_MASTER_URI={self.master}"]
        self.env = workspace.ros_env()
        self.sfx, self.split, self.tx = "", "", {}
        self.rigs = a.rigs.split(",")
        self.cam = self.probe = None
        self.orphans = []  # processes started and not waited for (perception hosts, killed)

    # What is said: on stdout, and in summary.txt.
    def say(self, text):
        print(text)
        with open(os.path.join(self.out, "summary.txt"), "a") as f:
            f.write(text + "\n")

    def fail(self, text):
        self.say(f"FAIL: {text}")
        for f in ("perception", "camera"):
            log = os.path.join(self.out, f"{f}{self.sfx}.log")
            if not os.path.isfile(log):
                continue
            print(f"--- the end of the {f} host's log ({log}):", file=sys.stderr)
            with open(log, errors="replace") as handle:
                tail = handle.read().splitlines()[-12:]
            for line in tail:
                print(re.sub(r"\x1b\[[0-9;]*m", "", line), file=sys.stderr)
        raise Failed(text)

    # Everything in our namespaces is ours (they are made here, under a name of this run).
    def stop_ns(self, ns):
        pids = ns_pids(ns)
        if not pids:
            return
        kill(pids, signal.SIGINT)  # roslaunch stops its nodes; eval writes its last frames
        # A shell or a timeout started in the background may ignore SIGINT, and so do its
        # children: the perception host still waiting for its master under timeout. TERM them.
        for p in pids:
            try:
                with open(f"/proc/{p}/comm") as f:
                    comm = f.read().strip()
            except OSError:
                continue
            if comm in ("bash", "sleep", "timeout", "two-hosts"):
                kill([p], signal.SIGTERM)
        for _ in range(40):
            if not ns_pids(ns):
                return
            time.sleep(0.5)
        kill(ns_pids(ns), signal.SIGKILL)
        for _ in range(20):
            if not ns_pids(ns):
                return
            time.sleep(0.25)

    def stop_hosts(self):
        self.stop_ns(self.ns_per)
        self.stop_ns(self.ns_cam)
        self.reap()

    def reap(self):
        for p in self.orphans:
            p.poll()

    def cleanup(self):
        self.stop_ns(self.ns_out)
        self.stop_hosts()
        for ns in (self.ns_out, self.ns_per, self.ns_cam):
            if ns in namespaces():
                subprocess.run(["ip", "netns", "del", ns], stderr=subprocess.DEVNULL)
        # Only if they never reached their namespace.
        for dev in (self.veth_cam, self.veth_in):
            subprocess.run(["ip", "link", "del", dev], stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL)

    # A third host on the link (--intruder): a bridge in the camera host's namespace holds its
    # address and both links, to the perception host and to the intruder's namespace.
    def add_intruder(self):
        cam, out = self.ns_cam, self.ns_out
        run("ip", "-n", cam, "link", "add", self.bridge, "type", "bridge")
        run("ip", "-n", cam, "link", "set", self.veth_cam, "master", self.bridge)
        run("ip", "link", "add", self.veth_in, "type", "veth", "peer", "name", self.veth_out)
        run("ip", "link", "set", self.veth_in, "netns", cam)
        run("ip", "link", "set", self.veth_out, "netns", out)
        run("ip", "-n", cam, "link", "set", self.veth_in, "master", self.bridge)
        run("ip", "-n", out, "addr", "add", f"{self.ip_out}/16", "dev", self.veth_out)
        for dev in (self.bridge, self.veth_in):
            run("ip", "-n", cam, "link", "set", dev, "up")
        run("ip", "-n", out, "link", "set", self.veth_out, "up")
        return self.bridge

    def make_link(self):
        for ns in self.namespaces:
            r = subprocess.run(["ip", "netns", "add", ns], capture_output=True, text=True)
            if r.returncode:
                self.fail(f"cannot make network namespace {ns}: 'ip netns add' says: "
                          f"{(r.stdout + r.stderr).strip()} (it needs root with CAP_SYS_ADMIN "
                          "and a writable /run/netns; a container may forbid it)")
            run("ip", "-n", ns, "link", "set", "lo", "up")
        run("ip", "link", "add", self.veth_cam, "type", "veth", "peer", "name", self.veth_per)
        run("ip", "link", "set", self.veth_cam, "netns", self.ns_cam)
        run("ip", "link", "set", self.veth_per, "netns", self.ns_per)
        cam_dev = self.add_intruder() if self.a.intruder else self.veth_cam
        run("ip", "-n", self.ns_cam, "addr", "add", f"{self.ip_cam}/16", "dev", cam_dev)
        run("ip", "-n", self.ns_per, "addr", "add", f"{self.ip_per}/16", "dev", self.veth_per)
        run("ip", "-n", self.ns_cam, "link", "set", self.veth_cam, "up")
        # --break-link: the perception host's end stays down (a cable pulled, a switch port off).
        if not self.a.break_link:
            run("ip", "-n", self.ns_per, "link", "set", self.veth_per, "up")

    # Each host's processes: in its namespace, with its own ROS_HOME and logs.
    def in_ns(self, ns, log, *command):
        with open(log, "a") as f:
            return subprocess.Popen(
                ["ip", "netns", "exec", ns, "env", f"ROS_HOME={self.out}/ros-{ns}",
                 f"ROS_LOG_DIR={self.out}/ros-{ns}/log", *command],
                stdout=f, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, env=self.env)

    def start_perception(self, uri, log, *options):
        """The perception host (not waited for: it may be killed)."""
        self.orphans.append(self.in_ns(
            self.ns_per, log, os.path.join(ROOT, "scripts/two-hosts"), "perception", "--master",
            uri, "--ip", self.ip_per, "--split", self.split, "--experiment", self.a.experiment,
            *options))

    def link_bytes(self, ns, dev):
        """tx bytes of the link's end in NS."""
        return int(output("ip", "netns", "exec", ns, "cat",
                          f"/sys/class/net/{dev}/statistics/tx_bytes"))

    # The camera host's probe: (kind, stamp, wall, valid) of each frame leaving and each pose
    # coming back, wall on the one monotonic clock of this machine.
    def probe_rows(self):
        rows = []
        try:
            with open(self.probe_csv) as f:
                for line in f:
                    v = line.rstrip("\n").split(",")
                    try:
                        rows.append((v[0], v[1], float(v[2]), v[3] if len(v) > 3 else ""))
                    except (IndexError, ValueError):
                        continue
        except OSError:
            pass
        return rows

    def frames_between(self, t0, t1, rows):
        return [r for r in rows if r[0] == "frame" and t0 < r[2] <= t1]

    @staticmethod
    def posed(rows):
        return {r[1] for r in rows if r[0] == "estimate" and r[3] == "1"}

    def latency_between(self, t0, t1, rows):
        """(median, p95, max, n): the pose latency of frames published between T0 and T1, from
        the frame leaving the camera host (its camera info at the camera host's probe) to its
        first valid pose back there [s]."""
        sent, back = {}, {}
        for kind, stamp, wall, valid in rows:
            if kind == "frame" and t0 < wall <= t1:
                sent.setdefault(stamp, wall)
            elif kind == "estimate" and valid == "1":
                back.setdefault(stamp, wall)
        v = sorted(back[s] - sent[s] for s in sent if s in back)
        if not v:
            return "0", "0", "0", "0"
        n = len(v)
        return (f"{v[(n + 1) // 2 - 1]:.3f}", f"{v[min(int(0.95 * n) + 1, n) - 1]:.3f}",
                f"{v[-1]:.3f}", str(n))

    def wait_pose_after(self, t, limit):
        """The time of the first valid estimate after T, or None after LIMIT s."""
        start = time.monotonic()
        while True:
            pose = next((r[2] for r in self.probe_rows()
                         if r[0] == "estimate" and r[3] == "1" and r[2] > t), None)
            if pose is not None:
                return pose
            if self.cam.poll() is not None:
                self.fail("the camera host ended")
            if self.probe.poll() is not None:
                self.fail(f"the camera host's probe ended (see {self.out}/probe.log)")
            if time.monotonic() - start > limit:
                return None
            time.sleep(0.5)

    def wait_master(self):
        """The master up (a loaded machine takes seconds)."""
        check = ("import sys, xmlrpc.client\ntry: xmlrpc.client.ServerProxy(sys.argv[1])"
                 ".getPid('/two_hosts')\nexcept OSError: sys.exit(1)")
        for _ in range(60):
            if subprocess.run(["ip", "netns", "exec", self.ns_cam, sys.executable, "-c", check,
                               self.master], stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL).returncode == 0:
                return
            if self.cam.poll() is not None:
                self.fail("the camera host ended")
            time.sleep(0.5)

    def start_hosts(self):
        """Both hosts with the graph cut at the split; the perception host first, as after a
        power-up in the wrong order: it waits for the master. Then the camera host's own
        listener: when each frame leaves and each pose comes back."""
        out, sfx, split = self.out, self.sfx, self.split
        self.start_perception(self.master, f"{out}/perception{sfx}.log", *self.per_fw)
        time.sleep(4)
        cam_start = time.monotonic()
        self.cam = self.in_ns(
            self.ns_cam, f"{out}/camera{sfx}.log", os.path.join(ROOT, "scripts/two-hosts"),
            "camera", "--ip", self.ip_cam, "--port", self.port, "--rate", self.a.rate,
            "--flight-path", self.path, "--out", f"{out}/eval{sfx}", "--split", split,
            "--experiment", self.a.experiment, *self.cam_fw)
        self.wait_master()
        self.probe = self.in_ns(
            self.ns_cam, f"{out}/probe{sfx}.log", *self.probe_env, sys.executable,
            os.path.join(ROOT, "src/aar_testing/scripts/realtime_probe.py"),
            "__name:=two_hosts_probe", f"_output:={self.probe_csv}", "_stage_times:=false")
        print(f"two-hosts: split {split}: waiting up to {self.a.timeout} s for the first pose "
              "across the link")
        pose = self.wait_pose_after(0, int(self.a.timeout))
        if pose is None:
            self.fail(f"no pose came back across the link within {self.a.timeout} s of the "
                      "camera host's start")
        waiting = grep_first(f"{out}/perception{sfx}.log", "perception host: no ROS master at")
        self.say(f"split {split}: waiting: {waiting or ''}")
        self.say(f"split {split}: first pose {pose - cam_start:.1f} s after the camera host "
                 "started")

    def frame_rate(self, rows):
        """The simulator's frames per second so far, from the camera host's probe."""
        walls = [r[2] for r in rows if r[0] == "frame"]
        return f"{(len(walls) - 1) / (walls[-1] - walls[0]):.4f}" if len(walls) > 1 else "0"

    def measure(self, label):
        """A phase: the frames, their poses, the link's bytes each way (the veth's counters,
        TCP/IP and Ethernet headers included) a frame and a second, the pose latency."""
        cam, per = (self.ns_cam, self.veth_cam), (self.ns_per, self.veth_per)
        c0, p0 = self.link_bytes(*cam), self.link_bytes(*per)
        t0 = time.monotonic()
        time.sleep(int(self.a.phase))
        t1 = time.monotonic()
        c1, p1 = self.link_bytes(*cam), self.link_bytes(*per)
        time.sleep(2)  # the last frames' poses
        rows = self.probe_rows()
        sent = {r[1] for r in self.frames_between(t0, t1, rows)}
        frames, valid = len(self.frames_between(t0, t1, rows)), len(sent & self.posed(rows))
        if frames <= 0:
            self.fail(f"{label}: no frame published in {self.a.phase} s")
        fps = self.frame_rate(rows)
        # Bytes a frame: bytes a second over frames a second (counting the window's frames
        # instead would be off by up to one, a frame crossing as counters are read).
        seconds = t1 - t0

        def per_frame(d):
            return f"{d / seconds / float(fps):.0f}" if float(fps) else "0"
        self.m = dict(cam_tx=per_frame(c1 - c0), per_tx=per_frame(p1 - p0),
                      cam_mbit=f"{8 * (c1 - c0) / seconds / 1e6:.2f}",
                      per_mbit=f"{8 * (p1 - p0) / seconds / 1e6:.2f}",
                      latency=self.latency_between(t0, t1, rows))
        self.say(f"{label}: {frames} frames in {seconds:.1f} s, {valid} with a pose "
                 f"({100 * valid / frames:.1f} %), poses at {valid / seconds:.2f} Hz; link per "
                 f"frame (frames at {fps} Hz): camera->perception {self.m['cam_tx']} bytes, "
                 f"perception->camera {self.m['per_tx']} bytes")

    def sizes(self, *topics):
        """Each message's size on TOPICS, at the camera host, in the background."""
        self.sizes_proc = self.in_ns(
            self.ns_cam, f"{self.out}/sizes.log", *self.probe_env, sys.executable,
            os.path.join(ROOT, "src/aar_testing/scripts/topic_sizes.py"), self.a.phase,
            f"{self.out}/sizes-{self.split}.txt", *topics)

    def say_sizes(self):
        self.sizes_proc.wait()
        path = f"{self.out}/sizes-{self.split}.txt"
        if not os.path.isfile(path):
            self.fail(f"no message sizes: {path} was not written (see {self.out}/sizes.log)")
        with open(path) as f:
            for line in f:
                topic, n, mean, most = line.split()[:4]
                self.say(f"size: {topic} {n} messages, mean {mean} bytes, max {most} bytes")

    def say_split(self):
        """The split's figures: bandwidth each way (bytes a frame, Mbit/s at the rate run) and
        latency."""
        m = self.m
        median, p95, most, n = m["latency"]
        self.say(f"split {self.split}: link camera->perception {m['cam_tx']} bytes a frame, "
                 f"{m['cam_mbit']} Mbit/s at {self.a.rate} Hz; perception->camera {m['per_tx']} "
                 f"bytes a frame, {m['per_mbit']} Mbit/s; pose latency median {median} s, p95 "
                 f"{p95} s, max {most} s ({n} poses)")
        self.tx[self.split] = m["cam_tx"]

    def restart_perception(self):
        """The perception host dies (every process, kill -9: a crash or a power cut) and comes
        back; the camera host runs on."""
        cam_before = sorted(p for p in ns_pids(self.ns_cam) if p != self.probe.pid)
        victims = ns_pids(self.ns_per)
        kill(victims, signal.SIGKILL)
        killed_at = time.monotonic()
        for _ in range(40):
            self.reap()
            if not ns_pids(self.ns_per):
                break
            time.sleep(0.25)
        if ns_pids(self.ns_per):
            self.fail("the perception host's processes outlived kill -9")
        time.sleep(3)  # down a while: frames go unanswered
        restarted_at = time.monotonic()
        # Its firewall table outlived it (its script was killed too): the new one replaces it.
        self.start_perception(self.master, f"{self.out}/perception-restart.log", *self.per_fw)
        resumed = self.wait_pose_after(restarted_at, 60)
        if resumed is None:
            self.fail("no pose within 60 s of the perception host's restart")
        cam_after = set(ns_pids(self.ns_cam))
        kept = sum(1 for p in cam_before if p in cam_after)
        rows = self.probe_rows()
        lost = len({r[1] for r in self.frames_between(killed_at, resumed, rows)} -
                   self.posed(rows))
        self.say(f"restart: perception host killed ({len(victims)} processes, kill -9), started "
                 f"again {restarted_at - killed_at:.1f} s later; first pose "
                 f"{resumed - restarted_at:.2f} s after the restart; {lost} frames without a "
                 f"pose; camera host processes kept: {kept} of {len(cam_before)}")

    def wrong_master(self):
        """Phase 2, and meanwhile a perception host pointed at a master nobody runs (an address
        on the link-local net that no host has); without a firewall of its own (it starts no
        graph, and a second table in the namespace would replace the running host's)."""
        uri = f"http://{self.ip_nobody}:{self.port}"
        log = f"{self.out}/wrong-master.log"
        wrong = self.in_ns(self.ns_per, log, "timeout", "12",
                           os.path.join(ROOT, "scripts/two-hosts"), "perception", "--master",
                           uri, "--ip", self.ip_per, "--no-firewall")
        self.measure("phase 2")
        status = exit_status(wrong.wait())
        with open(log, errors="replace") as f:
            lines = sum(1 for line in f if f"no ROS master at {uri}" in line)
        end = ("was still waiting when stopped after 12 s" if status == 124 else
               f"ended with status {status}")
        said = grep_first(log, "no ROS master at") or "nothing"
        self.say(f"wrong master: a perception host given {uri} {end} ({lines} messages); it "
                 f"said: {said}")

    def listening(self, ns):
        """The TCP ports listened on in NS, P,P,..."""
        ports = {int(line.split()[3].rsplit(":", 1)[1])
                 for line in output("ip", "netns", "exec", ns, "ss", "-Htln").splitlines()
                 if len(line.split()) > 3}
        return ",".join(str(p) for p in sorted(ports))

    def intrude(self):
        """--intruder: the third host on the link tries a port that is not ROS's, the master (it
        registers a publisher of poses), every port either host listens on (as a scan would
        find them), and to publish poses at x = 1e6 m (copies of the real ones) for a phase."""
        log = f"{self.out}/intruder.log"
        status = self.in_ns(
            self.ns_out, log, "env", f"ROS_IP={self.ip_out}", f"ROS_MASTER_URI={self.master}",
            "timeout", "-k", "5", str(int(self.a.phase) + 40), sys.executable,
            os.path.join(ROOT, "src/aar_testing/scripts/intruder.py"), "--master", self.master,
            "--ports", self.listening(self.ns_cam), "--perception", self.ip_per,
            "--perception-ports", self.listening(self.ns_per), "--closed-port", "9",
            "--seconds", self.a.phase).wait()
        if status:
            self.say(f"intruder: ended with status {exit_status(status)}")
        with open(log, errors="replace") as f:
            for line in f:
                if line.startswith("intruder: "):
                    self.say(line.rstrip("\n"))

    def accuracy(self):
        """Accuracy of every pose that came back (eval's frames.csv, written as the camera host
        stopped)."""
        what, path = f"split {self.split}", f"{self.out}/eval{self.sfx}/frames.csv"
        try:
            with open(path) as f:
                rows = [r for r in csv.DictReader(f) if r["estimated"] == "1"]
        except OSError as e:
            self.fail(f"accuracy, {what}: eval's frames.csv cannot be read: {workspace.os_error(e)}")
        if not rows:
            self.say(f"accuracy, {what}: no estimated frame in eval's frames.csv")
            return
        pos = sorted(math.sqrt(sum(float(r[k]) ** 2 for k in ("x_m", "y_m", "z_m")))
                     for r in rows)
        ang = sorted(max(abs(float(r[k])) for k in ("roll_deg", "pitch_deg", "yaw_deg"))
                     for r in rows)
        ranges = [float(r["range_m"]) for r in rows]

        def p95(v):
            return v[min(len(v) - 1, int(0.95 * len(v)))]
        far = sum(1 for p in pos if p > 1000.0)
        self.say(f"accuracy, {what}: {len(rows)} poses, range {min(ranges):.1f} to "
                 f"{max(ranges):.1f} m; position error mean {sum(pos) / len(pos):.3f} m, p95 "
                 f"{p95(pos):.3f} m, max {pos[-1]:.3f} m; largest angle error mean "
                 f"{sum(ang) / len(ang):.3f} deg, p95 {p95(ang):.3f} deg, max {ang[-1]:.3f} deg; "
                 f"{far} poses off by over 1 km")

    def run_split(self, split):
        """One split: both hosts up, measured, stopped. The images split also has the perception
        host restarted and a perception host given a wrong master; --intruder tries its attacks
        meanwhile."""
        self.split, self.sfx = split, "" if split == "images" else f"-{split}"
        self.probe_csv = f"{self.out}/probe{self.sfx}.csv"
        self.start_hosts()
        time.sleep(2)
        if split == "images":  # every rig's (issue 44)
            self.sizes(*[f"/{r}/{side}/{kind}" for r in self.rigs
                         for kind in ("image_rect", "camera_info") for side in ("left", "right")],
                       "/tf", "/joint_states")
        else:
            self.sizes(*[f"/{r}/points2" for r in self.rigs], "/aar/pose_estimate", "/tf")
        self.measure(f"split {split}, phase 1")
        self.say_sizes()
        self.say_split()
        if split == "images":
            self.restart_perception()
            time.sleep(2)
            self.wrong_master()
        if self.a.intruder:
            self.intrude()
        self.stop_hosts()
        self.accuracy()

    def slow_approach(self):
        """The last 20.8 s of the default approach (from 47 m, region B, to contact at 36.5 m),
        slowed down to last the whole run at wall-clock speed: about 60 s of start-up, restart
        and pauses, the three phases and 30 s to spare."""
        path = os.path.join(self.out, "slow_approach.csv")
        factor = float(f"{(90 + 3 * int(self.a.phase)) / 20.8:.3f}")
        with open(os.path.join(ROOT, "config/flight_paths/approach_default.csv")) as f:
            lines = f.read().splitlines()
        with open(path, "w") as f:
            f.write(lines[0] + "\n")
            for line in lines[1:]:
                v = line.split(",")
                try:
                    if float(v[0]) < 30:
                        continue
                except ValueError:
                    continue
                v[0] = f"{(float(v[0]) - 30) * factor:.3f}"
                f.write(",".join(v) + "\n")
        return path

    def measure_all(self):
        a = self.a
        self.path = a.flight_path or self.slow_approach()
        commit = output("git", "-C", ROOT, "rev-parse", "--short", "HEAD").strip() or "unknown"
        if subprocess.run(["git", "-C", ROOT, "diff", "--quiet", "HEAD"],
                          stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode:
            commit += " (with uncommitted changes)"
        guard = ("no firewall (--no-firewall)" if a.no_firewall else
                 "firewall on (each host's nftables table in its namespace)")
        open(os.path.join(self.out, "summary.txt"), "w").close()
        self.say(f"two-hosts: camera host {self.ns_cam} ({self.ip_cam}, master {self.master}), "
                 f"perception host {self.ns_per} ({self.ip_per}), veth "
                 f"{self.veth_cam}-{self.veth_per}; {a.rate} Hz, phases of {a.phase} s; splits: "
                 f"{' '.join(a.splits)}; {guard}; commit {commit}; load {load()}")
        if a.intruder:
            self.say(f"intruder: namespace {self.ns_out} ({self.ip_out}) on the camera host's "
                     f"bridge {self.bridge}, the same link")
        self.say(f"command: {a.command}")
        for split in a.splits:
            self.run_split(split)
        if "images" in self.tx and "cloud" in self.tx:
            self.say(f"bandwidth: camera->perception {self.tx['images']} bytes a frame with split "
                     f"images, {self.tx['cloud']} with split cloud "
                     f"({int(self.tx['images']) / int(self.tx['cloud']):.1f} times less)")
        self.cleanup()
        left = [ns for ns in namespaces() if ns in (self.ns_cam, self.ns_per, self.ns_out)]
        if left:
            self.fail(f"namespaces left behind: {' '.join(left)}")
        self.say(f"done: load {load()}; {self.out}/summary.txt")


def grep_first(path, text):
    try:
        with open(path, errors="replace") as f:
            return next((line.rstrip("\n") for line in f if text in line), None)
    except OSError:
        return None


def load():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def netns(argv):
    p = arguments.Parser("two-hosts netns", __doc__, who="two-hosts: netns")
    p.add_argument("--out", default="")
    p.add_argument("--rate", default="2")
    p.add_argument("--phase", default="12")
    p.add_argument("--flight-path", default="")
    p.add_argument("--name", default=f"aar2h{os.getpid()}")
    p.add_argument("--timeout", default="90")
    p.add_argument("--split", default="both")
    p.add_argument("--experiment", default="flight")
    p.add_argument("--no-firewall", action="store_true")
    p.add_argument("--intruder", action="store_true")
    p.add_argument("--break-link", action="store_true")
    p.add_argument("--no-build", action="store_true", help="for tests, which run inside a build")
    a = p.parse_args(argv)
    a.command = " ".join(["scripts/two-hosts netns"] + argv)
    caller = os.getcwd()
    if not (NUMBER.fullmatch(a.rate) and 0.5 <= float(a.rate) <= 30):
        bad(f"netns: --rate takes frames per second from 0.5 to 30, not '{a.rate}'")
    if not (re.fullmatch(r"[0-9]{1,4}", a.phase) and int(a.phase) >= 4):
        bad(f"netns: --phase takes whole seconds (at least 4), not '{a.phase}'")
    a.flight_path = arguments.absolute(a.flight_path, caller)
    if a.flight_path and not os.path.isfile(a.flight_path):
        bad(f"netns: --flight-path '{a.flight_path}' does not exist")
    if not re.fullmatch(r"[a-z][a-z0-9]{1,12}", a.name):  # the link's ends: NAMEc, NAMEp (15)
        bad(f"netns: --name takes 2 to 13 lower-case letters and digits, not '{a.name}'")
    if not (re.fullmatch(r"[0-9]{1,4}", a.timeout) and int(a.timeout) >= 10):
        bad(f"netns: --timeout takes whole seconds (at least 10), not '{a.timeout}'")
    if a.split not in ("images", "cloud", "both"):
        bad(f"netns: --split takes images, cloud or both, not '{a.split}'")
    a.splits = ["images", "cloud"] if a.split == "both" else [a.split]
    a.rigs = check_experiment("netns", a.experiment)
    if os.geteuid() != 0:
        bad("netns: needs root (ip netns add, ip link add)")
    if not shutil.which("ip"):
        bad("netns: 'ip' (iproute2) is not installed; scripts/setup installs it")
    if not a.no_firewall and not shutil.which("nft"):
        bad("netns: 'nft' (nftables) is not installed; scripts/setup installs it (or "
            "--no-firewall)")
    for ns in [f"{a.name}-cam", f"{a.name}-per"] + ([f"{a.name}-out"] if a.intruder else []):
        if ns in namespaces():
            bad(f"netns: namespace '{ns}' exists already (another run's, or a killed one's: see "
                f"'ip netns pids {ns}'; 'ip netns del {ns}' removes it)")
    a.out = arguments.absolute(a.out, caller) or os.path.join(
        ROOT, f"results/two-hosts-{workspace.utc_stamp()}")
    try:
        os.makedirs(a.out, exist_ok=True)
        writable = os.access(a.out, os.W_OK)
    except OSError:
        writable = False
    if not writable:
        bad(f"netns: --out '{a.out}' cannot be written")
    if not a.no_build:
        workspace.setup_and_build()
    for pattern in ("summary.txt", "*.log", "*.csv", "sizes-*.txt", "eval*", "ros-*"):
        for f in glob.glob(os.path.join(a.out, pattern)):
            shutil.rmtree(f) if os.path.isdir(f) and not os.path.islink(f) else os.remove(f)
    run_ = Netns(a)
    for s in (signal.SIGINT, signal.SIGTERM):
        signal.signal(s, interrupted)
    try:
        run_.make_link()
        run_.measure_all()
        return 0
    except Failed:
        return 1
    finally:
        for s in (signal.SIGINT, signal.SIGTERM):
            signal.signal(s, signal.SIG_IGN)
        run_.cleanup()


def main(argv):
    workspace.PROG = "two-hosts"
    # The hosts' processes are told apart by name when a run stops them (Netns.stop_ns).
    ctypes.CDLL(None).prctl(15, b"two-hosts", 0, 0, 0)  # PR_SET_NAME
    sys.stdout.reconfigure(line_buffering=True)  # a host's log shows what it said as it said it
    os.environ["PATH"] += ":/usr/sbin:/sbin"  # ip, nft
    mode, argv = (argv[0], argv[1:]) if argv else ("", [])
    if mode in ("-h", "--help"):
        print(__doc__)
        return 0
    if not mode:
        print("two-hosts: say which: camera, perception or netns", file=sys.stderr)
        print(arguments.synopsis(__doc__), file=sys.stderr)
        return 2
    if mode not in ("camera", "perception", "netns"):
        print(f"two-hosts: unknown mode '{mode}' (camera, perception or netns)", file=sys.stderr)
        print(arguments.synopsis(__doc__), file=sys.stderr)
        return 2
    return {"camera": camera, "perception": perception, "netns": netns}[mode](argv)
