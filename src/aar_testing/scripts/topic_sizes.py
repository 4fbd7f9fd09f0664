#!/usr/bin/env python3
"""Serialized size of each message on some topics, as a subscriber gets them (scripts/two-hosts:
what images, camera infos and clouds cost a link per frame). Subscribes for SECONDS of wall
time, then writes one line per topic to OUT:
  topic messages mean_bytes max_bytes
  python3 topic_sizes.py SECONDS OUT TOPIC...
Messages are not deserialised (rospy.AnyMsg): the probe costs the host little."""
import sys
import time

import rospy


def main():
    if len(sys.argv) < 4:
        sys.exit("usage: topic_sizes.py SECONDS OUT TOPIC...")
    seconds, out, topics = float(sys.argv[1]), sys.argv[2], sys.argv[3:]
    rospy.init_node("topic_sizes", anonymous=True, disable_signals=True)
    sizes = {t: [] for t in topics}

    def record(topic):
        return lambda msg: sizes[topic].append(len(msg._buff))

    subs = [rospy.Subscriber(t, rospy.AnyMsg, record(t), queue_size=100) for t in topics]
    time.sleep(seconds)
    for s in subs:
        s.unregister()
    with open(out, "w") as f:
        for t in topics:
            n = len(sizes[t])
            mean = sum(sizes[t]) / n if n else 0.0
            f.write(f"{t} {n} {mean:.0f} {max(sizes[t], default=0)}\n")
    rospy.signal_shutdown("done")


if __name__ == "__main__":
    main()
