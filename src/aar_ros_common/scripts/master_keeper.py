#!/usr/bin/env python3
"""Keeps a ROS 1 graph whole across a restart of its master (launch/include/processing.launch
runs it with respawn:=true).

roscpp and rospy nodes register themselves, their topics and services with the master once,
when they start, and never again. A master that restarts on the same URI knows none of them:
the connections already made go on, but no new subscriber finds a publisher, a respawned node
finds no parameters, and rostopic and rosnode see an empty graph. This node copies the master's
registrations (getSystemState, each node's URI, the topic types, each service's URI) and the
parameter tree every ~period seconds (default 0.5; five requests) while the master is up. When
a master with another PID answers on the same URI, it sets the parameters back and registers
again, in each node's name, the publishers, then the subscribers, then the services of every
node that still answers. Publishers first: the master then has no subscriber to tell, and
connections that exist are left alone. Not restored: what changed in the last period before the
master died, and parameter subscriptions (getParamCached)."""
import os
import sys
import time
import xmlrpc.client

import rospy


class Transport(xmlrpc.client.Transport):
    """Gives up after `timeout` seconds: a stopped process must not stop the keeper."""

    def __init__(self, timeout):
        super().__init__()
        self.timeout = timeout

    def make_connection(self, host):
        connection = super().make_connection(host)
        connection.timeout = self.timeout
        return connection


def proxy(uri, timeout=5.0):
    return xmlrpc.client.ServerProxy(uri, transport=Transport(timeout))


def call(server, method, *args):
    """The value of a ROS XML-RPC call; raises on a failed call or status."""
    code, message, value = getattr(server, method)(*args)
    if code != 1:
        raise RuntimeError(f"{method}{args[1:]}: {message}")
    return value


class Snapshot:
    """What the master knew: {node: uri}, {topic: type}, {node: ([published], [subscribed],
    [(service, uri)])}, and the parameter tree. Five requests, the lookups in one multicall."""

    def __init__(self, master, me):
        publishers, subscribers, services = call(master, "getSystemState", me)
        self.types = dict(call(master, "getTopicTypes", me))
        self.by_node = {}
        for index, entries in enumerate((publishers, subscribers)):
            for topic, nodes in entries:
                for node in nodes:
                    self.by_node.setdefault(node, ([], [], []))[index].append(topic)
        nodes = sorted(set(self.by_node) | {n for _, ns in services for n in ns})
        batch = xmlrpc.client.MultiCall(master)
        for node in nodes:
            batch.lookupNode(me, node)
        for service, _ in services:
            batch.lookupService(me, service)
        answers = list(batch())
        # A node or service gone between the two calls is left out.
        self.uris = {n: a[2] for n, a in zip(nodes, answers) if a[0] == 1}
        for (service, owners), a in zip(services, answers[len(nodes):]):
            if a[0] == 1:
                for node in owners:
                    self.by_node.setdefault(node, ([], [], []))[2].append((service, a[2]))
        self.params = call(master, "getParam", me, "/")


def alive(uri, me):
    try:
        call(proxy(uri, 2.0), "getPid", me)
        return True
    except Exception:  # refused, timed out, or no longer a ROS node
        return False


def restore(master, snapshot, me):
    """Registers again what `snapshot` holds; returns (nodes, registrations, skipped nodes)."""
    for key, value in snapshot.params.items():  # per top-level key: what is new stays
        call(master, "setParam", me, "/" + key, value)
    live = {n: u for n, u in snapshot.uris.items() if n in snapshot.by_node and alive(u, me)}
    count = 0
    for index, method in ((0, "registerPublisher"), (1, "registerSubscriber")):
        for node, uri in live.items():
            for topic in snapshot.by_node[node][index]:
                call(master, method, node, topic, snapshot.types.get(topic, "*"), uri)
                count += 1
    for node, uri in live.items():
        for service, service_uri in snapshot.by_node[node][2]:
            call(master, "registerService", node, service, service_uri, uri)
            count += 1
    return len(live), count, sorted(set(snapshot.uris) - set(live))


def main():
    rospy.init_node("master_keeper")
    period = float(rospy.get_param("~period", 0.5))
    if not period > 0.0:
        rospy.logfatal("master_keeper: ~period must be > 0 [s], not %s", period)
        sys.exit(2)
    me = rospy.get_name()
    uri = os.environ.get("ROS_MASTER_URI", "")
    master = proxy(uri)
    pid = call(master, "getPid", me)
    snapshot = None
    down_since = None
    rospy.loginfo("master_keeper: keeping the registrations of the master at %s (pid %d)", uri,
                  pid)
    while not rospy.is_shutdown():
        time.sleep(period)
        try:
            now_pid = call(master, "getPid", me)
        except Exception as e:  # the master is gone: wait for a new one
            if down_since is None:
                down_since = time.monotonic()
                rospy.logerr("master_keeper: the master at %s does not answer (%s); the graph "
                             "goes on between connected nodes, waiting for it to return", uri, e)
            continue
        try:
            if now_pid != pid and snapshot is not None:
                nodes, count, gone = restore(master, snapshot, me)
                rospy.logwarn(
                    "master_keeper: the master at %s restarted (pid %d, was %d; down %.1f s): "
                    "parameters set back and %d registrations made again for %d nodes%s",
                    uri, now_pid, pid, time.monotonic() - down_since if down_since else 0.0,
                    count, nodes, "; not answering, left out: " + ", ".join(gone) if gone else "")
            pid = now_pid
            down_since = None
            snapshot = Snapshot(master, me)
        except Exception as e:  # the master died mid-way: try again on the next round
            rospy.logerr("master_keeper: %s", e)


if __name__ == "__main__":
    main()
