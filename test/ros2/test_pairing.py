"""The node's and the bag command's pairing of image sets with LiDAR clouds (lidarsgm_ros.sync.LidarPairing) and
the health rules of lidarsgm_ros.health, as plain Python: stamps in, sets out."""
import os
import sys
import unittest
from types import SimpleNamespace

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "ros2", "lidarsgm_ros"))

from lidarsgm_ros import health  # noqa: E402
from lidarsgm_ros.sync import ApproximateSync, ExactSync, LidarPairing  # noqa: E402

MS = 1000000


def exact(timeout_ms=500):
    return LidarPairing(ExactSync(4, 5), 0, timeout_ms * MS, 5)


def images(p, t, now=None):
    """The four image messages of stamp t (ms); returns what they release."""
    out = []
    for i in range(4):
        out += p.add(i, t * MS, ("img", i, t), now)
    return out


def cloud(p, t, now=None):
    return p.add(4, t * MS, ("cloud", t), now)


def summary(released):
    """[(stamp ms, cloud stamp ms or None)]"""
    return [(s // MS, msgs[4][1] if msgs[4] is not None else None) for s, msgs in released]


class Pairing(unittest.TestCase):
    def test_a_cloud_pairs_before_or_after_its_images(self):
        p = exact()
        self.assertEqual(summary(images(p, 100) + cloud(p, 100)), [(100, 100)])
        self.assertEqual(summary(cloud(p, 200) + images(p, 200)), [(200, 200)])
        out = images(p, 300)
        self.assertEqual(out, [])  # waits for its cloud
        self.assertEqual(summary(cloud(p, 300)), [(300, 300)])

    def test_a_later_cloud_lets_an_unpaired_set_go(self):
        p = exact()
        self.assertEqual(images(p, 100), [])
        self.assertEqual(summary(cloud(p, 200)), [(100, None)])  # the scan of 100 was lost
        self.assertEqual(summary(images(p, 200)), [(200, 200)])

    def test_a_silent_lidar_costs_one_frame_after_the_timeout(self):
        p = exact(500)
        out = []
        for t in range(0, 500, 100):
            out += images(p, t)
        self.assertEqual(out, [])  # each waits: the LiDAR may still send
        self.assertEqual(summary(images(p, 500)), [(0, None), (100, None), (200, None), (300, None), (400, None)])
        # Silent now: a set waits only for the next one.
        self.assertEqual(summary(images(p, 600)), [(500, None)])
        # The LiDAR back: a set whose cloud comes before the next set pairs again.
        self.assertEqual(summary(images(p, 700)), [(600, None)])
        self.assertEqual(summary(cloud(p, 700)), [(700, 700)])
        self.assertEqual(images(p, 800), [])  # waits for its cloud again (not silent any more)
        self.assertEqual(summary(cloud(p, 800)), [(800, 800)])

    def test_the_clock_lets_a_set_go_after_the_timeout(self):
        p = exact(500)
        self.assertEqual(images(p, 100, now=0), [])
        self.assertEqual(p.poll(499 * MS), [])
        self.assertEqual(summary(p.poll(500 * MS)), [(100, None)])
        self.assertTrue(p.silent)

    def test_approximate_takes_the_nearest_cloud_within_the_tolerance(self):
        p = LidarPairing(ApproximateSync(4, 5, 10 * MS), 50 * MS, 500 * MS, 5)
        self.assertEqual(images(p, 100), [])
        self.assertEqual(cloud(p, 70), [])  # within 50 ms but a nearer one may follow
        self.assertEqual(summary(cloud(p, 120)), [(100, 120)])
        self.assertEqual(images(p, 200), [])
        self.assertEqual(summary(cloud(p, 260)), [(200, None)])  # beyond the tolerance: its scan is gone

    def test_time_going_back_restarts(self):
        p = exact()
        self.assertEqual(summary(images(p, 5000) + cloud(p, 5000)), [(5000, 5000)])
        # The same set again (a repeated stamp), then a jump back (a bag loop): each goes out.
        self.assertEqual(summary(images(p, 5000) + cloud(p, 5000)), [(5000, 5000)])
        self.assertEqual(summary(images(p, 2000) + cloud(p, 2000)), [(2000, 2000)])
        self.assertEqual(summary(images(p, 2100) + cloud(p, 2100)), [(2100, 2100)])
        self.assertEqual(p.restarts, 2)

    def test_a_restart_lets_waiting_sets_go(self):
        p = exact()
        self.assertEqual(images(p, 5000), [])
        self.assertEqual(summary(p.add(0, 1000 * MS, "img")), [(5000, None)])
        self.assertEqual(p.restarts, 1)

    def test_finish_lets_everything_go_and_sets_come_in_stamp_order(self):
        p = exact()
        out = images(p, 100) + images(p, 200) + cloud(p, 200) + images(p, 300)
        out += p.finish()
        self.assertEqual(summary(out), [(100, None), (200, 200), (300, None)])
        self.assertEqual(p.waiting, type(p.waiting)())

    def test_the_cloud_queue_is_bounded(self):
        p = exact()
        for t in range(0, 2000, 100):
            cloud(p, t)
        self.assertLessEqual(len(p.clouds), p.queue_size)
        self.assertGreater(p.unpaired_clouds, 0)


def result(alone="", reason=""):
    return SimpleNamespace(stereo_alone=alone, reason=reason, dropped_points=0)


class Health(unittest.TestCase):
    def test_levels(self):
        h = health.Health(max_residual=2.0, report_seconds=1.0, dark_seconds=3.0)  # (the node's bound is the module's)
        self.assertEqual(h.level(0.0)[0], health.WARN)  # no input yet
        h.message_in(0.1)
        h.output(0.2, result(), 0.05, 0.08)
        self.assertEqual(h.level(0.5), (health.OK, "fused with the LiDAR"))
        h.message_in(1.2)
        h.output(1.3, result("no cloud", "no cloud on /points within 0.50 s"), 0.05, 0.6)
        level, text = h.level(1.5)
        self.assertEqual(level, health.WARN)
        self.assertIn("no cloud on /points", text)
        self.assertEqual(h.level(2.4)[0], health.WARN)  # no input for a second
        for t in (2.5, 3.5, 4.5):
            h.message_in(t)
        h.event(4.5, "skipped:bad message", "the left image is 100x10, its camera_info 1242x375")
        level, text = h.level(4.6)
        self.assertEqual(level, health.ERROR)  # messages, and nothing out since 1.3
        self.assertIn("camera_info", text)
        h.output(4.7, result(), 0.05, 0.08)
        self.assertEqual(h.level(4.8)[0], health.WARN)  # the skip is within the last second
        self.assertEqual(h.level(5.8)[0], health.WARN)  # no input
        h.message_in(5.9)
        self.assertEqual(h.level(5.95)[0], health.OK)
        h.residual = 1.5  # under the bound given
        self.assertEqual(h.level(5.95)[0], health.OK)
        h.residual = 2.5
        self.assertEqual(h.level(5.95), (health.WARN, "the LiDAR lies 2.50 px from where the images match: check "
                                                      "the calibration"))
        h.residual = None
        h.event(6.0, "restart")
        self.assertIn("time went back", h.level(6.1)[1])
        values = dict(h.values(6.1))
        self.assertEqual(values["sets fused with the LiDAR"], 2)
        self.assertEqual(values["stereo alone: no cloud"], 1)
        self.assertEqual(values["skipped: bad message"], 1)


if __name__ == "__main__":
    unittest.main()
