#!/usr/bin/env python3
"""rostest of the NavigateTo action (actionlib) of navigation_node.

Whether the tip reached the target is judged against the scene's SWC file
itself (the tip within the named vessel's radius of its polyline, past
15 mm of it), not against the atlas the node steers and reports by.
"""
import math
import os
import threading
import unittest

import actionlib
import rospy
import rostest
from actionlib_msgs.msg import GoalStatus
from endovascular_sim.msg import (DeviceCommand, DeviceStatusArray, NavigateToAction,
                                  NavigateToGoal)
from std_srvs.srv import Trigger

PKG_DIR = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SWC = os.path.join(PKG_DIR, 'config', 'vessels', 'carotid.swc')


def vessel_segments(path, name):
    """The named vessel's segments (a, b, radius at b, path length at a) [m]."""
    starts, points = {}, {}
    with open(path) as f:
        for line in f:
            words = line.split()
            if line.startswith('# vessel:'):
                starts[int(words[3])] = words[2]
            elif words and not line.startswith('#'):
                i, x, y, z, r, parent = (int(words[0]), float(words[2]), float(words[3]),
                                         float(words[4]), float(words[5]), int(words[6]))
                points[i] = ((x * 1e-3, y * 1e-3, z * 1e-3), r * 1e-3, parent)
    vessel = {}
    for i in sorted(points):  # parents come first in the file
        vessel[i] = starts.get(i, vessel.get(points[i][2], ''))
    segments, s = [], 0.0
    for i in sorted(points):
        parent = points[i][2]
        if vessel[i] != name or parent < 0:
            continue
        a, b = points[parent][0], points[i][0]
        segments.append((a, b, points[i][1], s))
        s += math.dist(a, b)
    return segments


def nearest(segments, p):
    """(distance to the polyline, its radius there, path length there) [m]."""
    best = (math.inf, 0.0, 0.0)
    for a, b, radius, s in segments:
        ab = [b[k] - a[k] for k in range(3)]
        length2 = sum(c * c for c in ab)
        t = max(0.0, min(1.0, sum((p[k] - a[k]) * ab[k] for k in range(3)) / length2))
        q = [a[k] + t * ab[k] for k in range(3)]
        d = math.dist(p, q)
        if d < best[0]:
            best = (d, radius, s + t * math.sqrt(length2))
    return best


class NavigateActionTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('navigate_action_test')
        cls.lock = threading.Lock()
        cls.states = None
        rospy.Subscriber('device_states', DeviceStatusArray, cls._on_states)
        cls.command_pub = rospy.Publisher('command', DeviceCommand, queue_size=10)
        cls.client = actionlib.SimpleActionClient('navigate_to', NavigateToAction)
        assert cls.client.wait_for_server(rospy.Duration(60)), 'no navigate_to action server'
        rospy.wait_for_service('reset', timeout=60)
        cls.reset = rospy.ServiceProxy('reset', Trigger)

    @classmethod
    def _on_states(cls, msg):
        with cls.lock:
            cls.states = msg

    def tip(self, device):
        with self.lock:
            for d in self.states.devices:
                if d.name == device:
                    return d
        self.fail('no device %s' % device)

    def run_goal(self, target, device='', timeout=0.0, wait=60.0):
        feedback = []
        self.client.send_goal(NavigateToGoal(target=target, device=device, timeout=timeout),
                              feedback_cb=feedback.append)
        self.assertTrue(self.client.wait_for_result(rospy.Duration(wait)), 'no result')
        return self.client.get_state(), self.client.get_result(), feedback

    def test_1_unknown_target_is_refused_with_the_nearest_names(self):
        state, result, _ = self.run_goal('right_comon_carotid')
        self.assertEqual(state, GoalStatus.ABORTED)
        self.assertIn('nearest: right_common_carotid', result.reason)
        state, result, _ = self.run_goal('left_subclavian', timeout=float('nan'))
        self.assertEqual(state, GoalStatus.ABORTED)
        self.assertIn('timeout', result.reason)

    def test_2_manual_command_and_cancel_pre_empt(self):
        feedback = []
        self.client.send_goal(NavigateToGoal(target='left_common_carotid'),
                              feedback_cb=feedback.append)
        deadline = rospy.Time.now() + rospy.Duration(60)
        while not feedback and rospy.Time.now() < deadline:
            rospy.sleep(0.05)
        self.assertTrue(feedback, 'no feedback')
        self.assertEqual(feedback[0].vessel, 'descending_aorta')
        self.assertGreater(feedback[0].remaining_path, 0.05)
        self.command_pub.publish(DeviceCommand(device='guidewire', mode=DeviceCommand.VELOCITY))
        self.assertTrue(self.client.wait_for_result(rospy.Duration(30)))
        self.assertEqual(self.client.get_state(), GoalStatus.ABORTED)
        self.assertIn("manual command for 'guidewire'", self.client.get_result().reason)
        self.client.send_goal(NavigateToGoal(target='left_common_carotid'))
        rospy.sleep(1.0)
        self.client.cancel_goal()
        self.assertTrue(self.client.wait_for_result(rospy.Duration(30)))
        self.assertEqual(self.client.get_state(), GoalStatus.PREEMPTED)
        self.assertTrue(self.reset().success)

    def test_3_reaches_the_right_common_carotid(self):
        state, result, feedback = self.run_goal('right_common_carotid', wait=800.0)
        self.assertEqual(state, GoalStatus.SUCCEEDED, result.reason)
        self.assertTrue(result.reached)
        self.assertEqual(result.failed_steps, 0)
        self.assertEqual(result.final_vessel, 'right_common_carotid')
        self.assertGreater(result.peak_wall_force, 0.0)
        visited = []
        for f in feedback:
            if not visited or visited[-1] != f.vessel:
                visited.append(f.vessel)
        for vessel in ('descending_aorta', 'aortic_arch', 'brachiocephalic_trunk',
                       'right_common_carotid'):
            self.assertIn(vessel, visited)
        rospy.sleep(0.5)  # the state after the last step
        p = self.tip('guidewire').tip.position
        distance, radius, depth = nearest(vessel_segments(SWC, 'right_common_carotid'),
                                          (p.x, p.y, p.z))
        self.assertLess(distance, radius)
        self.assertGreater(depth, 0.015)


if __name__ == '__main__':
    rostest.rosrun('endovascular_sim', 'navigate_action', NavigateActionTest)
