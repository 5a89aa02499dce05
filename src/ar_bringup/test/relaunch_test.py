#!/usr/bin/env python3
"""Restart test node (test/relaunch_replay.test): starts the replay launch file, waits until the
graph tracks, stops it, and starts it again on the same master (rostest's, on its own port). The
second start meets what the first left on the parameter server: every nodelet's parameters as
dynamic_reconfigure wrote them back (enums as ints), /use_sim_time. Both runs must track.

Waits on conditions only (messages received, processes gone); ~max_wait_s is a hang guard.
Parameters: ~launch_file, ~launch_args (list of name:=value), ~runs (2), ~min_messages (10 of each
topic per run), ~topics (pose topics that must arrive), ~max_wait_s (hang guard per wait, wall time).
"""
import signal
import subprocess
import sys
import threading
import time
import unittest

import rosgraph
import rospy
import rostest
from geometry_msgs.msg import PoseWithCovarianceStamped


def param(name, default=None):
    return rospy.get_param("~" + name, default)


class Counts:
    """Messages per topic received during the current run."""

    def __init__(self, topics):
        self.cond = threading.Condition()
        self.topics = topics
        self.counts = {t: 0 for t in topics}

    def on_message(self, topic):
        def callback(_msg):
            with self.cond:
                self.counts[topic] += 1
                self.cond.notify_all()
        return callback

    def reset(self):
        with self.cond:
            self.counts = {t: 0 for t in self.topics}

    def wait(self, minimum, alive, max_wait_s):
        """True once every topic has `minimum` messages; False if `alive()` turns false or the guard expires."""
        deadline = time.monotonic() + max_wait_s
        with self.cond:
            while min(self.counts.values()) < minimum:
                if not alive() or rospy.is_shutdown() or time.monotonic() > deadline:
                    return False
                self.cond.wait(1.0)  # re-checks the process and the guard once a second
            return True

    def snapshot(self):
        with self.cond:
            return dict(self.counts)


def publishers(topics):
    """Nodes publishing any of `topics` according to the master."""
    pubs, _, _ = rosgraph.Master("/relaunch_test").getSystemState()
    names = {rosgraph.names.resolve_name(t, "/") for t in topics}
    return [n for topic, nodes in pubs if topic in names for n in nodes]


class RelaunchTest(unittest.TestCase):
    def test_replay_tracks_after_every_start(self):
        rospy.init_node("relaunch_test")
        topics = param("topics", ["cone_tracker/pose", "pose_ekf/pose"])
        runs, minimum, max_wait_s = param("runs", 2), param("min_messages", 10), param("max_wait_s", 240.0)
        counts = Counts(topics)
        subs = [rospy.Subscriber(t, PoseWithCovarianceStamped, counts.on_message(t), queue_size=100) for t in topics]
        command = ["roslaunch", "--wait", param("launch_file")] + list(param("launch_args", []))
        for run in range(1, runs + 1):
            counts.reset()
            proc = subprocess.Popen(command)
            try:
                tracked = counts.wait(minimum, lambda: proc.poll() is None, max_wait_s)
                got = counts.snapshot()
                print("RELAUNCH run %d: %s" % (run, got))
                sys.stdout.flush()
                self.assertIsNone(proc.poll(), "run %d: roslaunch exited (code %s) before the graph tracked; "
                                  "received %s" % (run, proc.returncode, got))
                self.assertTrue(tracked, "run %d of %s: fewer than %d messages on %s within the %.0f s hang guard "
                                "(received %s); see the nodelets' FATAL lines above" %
                                (run, param("launch_file"), minimum, ", ".join(topics), max_wait_s, got))
            finally:
                self.stop(proc, max_wait_s)
            # The next run counts only its own messages: wait until this run's publishers are gone.
            deadline = time.monotonic() + max_wait_s
            while publishers(topics) and time.monotonic() < deadline:
                time.sleep(0.2)
            self.assertEqual(publishers(topics), [], "run %d's publishers still registered" % run)
        for s in subs:
            s.unregister()

    @staticmethod
    def stop(proc, max_wait_s):
        """roslaunch shuts its nodes down on SIGINT (escalating to SIGTERM/SIGKILL itself)."""
        if proc.poll() is not None:
            return
        proc.send_signal(signal.SIGINT)
        try:
            proc.wait(timeout=max_wait_s)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


if __name__ == "__main__":
    rostest.rosrun("ar_bringup", "relaunch_test", RelaunchTest, sys.argv)
