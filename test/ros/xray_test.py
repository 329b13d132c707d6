#!/usr/bin/env python3
"""rostest of the node's virtual fluoroscopy (xray/image, xray/camera_info).

The expected values come from outside the node: the C-arm's defaults as the
scene format documents them (docs/sensors.md), the guidewire's tip as the
node reports it on device_states (projected here with the published
CameraInfo and tf, as any ROS tool would back-project), and the requests the
test sends.
"""
import math
import os
import threading
import time
import unittest

import rospy
import rostest
import tf2_ros
from dynamic_reconfigure.client import Client
from endovascular_sim.msg import DeviceStatusArray
import yaml
from endovascular_sim.srv import InjectContrast, LoadScene, SetCArm
from sensor_msgs.msg import CameraInfo, Image

from ros_geometry import quaternion_rotate as rotate

CONFIG = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                      'config')
# The documented defaults of a scene without `xray:` (docs/sensors.md).
SID, DETECTOR, PIXELS = 1.2, 0.3, 512


class XrayTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('xray_test')
        cls.lock = threading.Lock()
        cls.images, cls.infos, cls.states = [], [], None
        rospy.Subscriber('xray/image', Image, cls._on_image, queue_size=5)
        rospy.Subscriber('xray/camera_info', CameraInfo, cls._on_info, queue_size=5)
        rospy.Subscriber('device_states', DeviceStatusArray, cls._on_states)
        rospy.wait_for_service('xray/set_c_arm', timeout=60)
        rospy.wait_for_service('xray/inject_contrast', timeout=60)
        cls.set_c_arm = rospy.ServiceProxy('xray/set_c_arm', SetCArm)
        cls.inject = rospy.ServiceProxy('xray/inject_contrast', InjectContrast)
        cls.tf_buffer = tf2_ros.Buffer()
        cls.tf_listener = tf2_ros.TransformListener(cls.tf_buffer)

    @classmethod
    def _on_image(cls, msg):
        with cls.lock:
            cls.images.append(msg)

    @classmethod
    def _on_info(cls, msg):
        with cls.lock:
            cls.infos.append(msg)

    @classmethod
    def _on_states(cls, msg):
        with cls.lock:
            cls.states = msg

    def next_image(self, timeout=30.0):
        with self.lock:
            count = len(self.images)
        deadline = time.time() + timeout
        while time.time() < deadline:
            with self.lock:
                if len(self.images) > count and self.infos:
                    return self.images[-1], self.infos[-1]
            time.sleep(0.02)
        self.fail('no image on xray/image within %.0f s' % timeout)

    def test_1_image_and_its_calibration(self):
        image, info = self.next_image()
        self.assertEqual(image.encoding, 'mono8')
        self.assertEqual((image.width, image.height), (PIXELS, PIXELS))
        self.assertEqual(len(image.data), PIXELS * PIXELS)
        f = SID / (DETECTOR / PIXELS)
        self.assertAlmostEqual(info.K[0], f, places=6)
        self.assertAlmostEqual(info.K[4], f, places=6)
        self.assertAlmostEqual(info.K[2], (PIXELS - 1) / 2.0, places=9)
        self.assertEqual(info.header.frame_id, 'xray_source')
        # Frames keep coming at about the frame rate (15/s); a loaded
        # machine may slow them, not stop them.
        start = time.time()
        with self.lock:
            first = len(self.images)
        time.sleep(2.0)
        with self.lock:
            rate = (len(self.images) - first) / (time.time() - start)
        self.assertGreater(rate, 2.0)
        self.assertLess(rate, 20.0)

    def test_2_the_tip_shows_where_the_camera_projects_it(self):
        # The guidewire's radiopaque tip, 1 mm back from its end, projected
        # with the published calibration, lands on dark pixels.
        image, info = self.next_image()
        with self.lock:
            wire = [d for d in self.states.devices if d.name == 'guidewire'][0]
        p, q = wire.tip.position, wire.tip.orientation
        back = rotate((q.x, q.y, q.z, q.w), (-1e-3, 0.0, 0.0))
        point = (p.x + back[0], p.y + back[1], p.z + back[2])
        t = self.tf_buffer.lookup_transform('world', 'xray_source', rospy.Time(0),
                                            rospy.Duration(10)).transform
        rel = (point[0] - t.translation.x, point[1] - t.translation.y, point[2] - t.translation.z)
        r = t.rotation
        cam = rotate((-r.x, -r.y, -r.z, r.w), rel)
        u = info.K[0] * cam[0] / cam[2] + info.K[2]
        v = info.K[4] * cam[1] / cam[2] + info.K[5]
        self.assertTrue(0 <= u < image.width and 0 <= v < image.height, (u, v))
        ui, vi = int(round(u)), int(round(v))

        def gray(a, b):
            return image.data[b * image.width + a]

        darkest = min(gray(a, b) for a in range(ui - 1, ui + 2) for b in range(vi - 1, vi + 2))
        around = [gray(a, vi) for a in (ui - 25, ui + 25)] + [gray(ui, b) for b in (vi - 25, vi + 25)]
        self.assertLess(darkest, min(around) - 30, (darkest, around))

    def test_3_c_arm_refuses_what_cannot_image_and_turns(self):
        res = self.set_c_arm(lao_deg=0.0, cranial_deg=0.0, source_detector_distance=1.2,
                             source_isocenter_distance=5.0)
        self.assertFalse(res.success)
        self.assertIn('source_isocenter_distance', res.message)
        res = self.set_c_arm(lao_deg=120.0, cranial_deg=0.0, source_detector_distance=0.0,
                             source_isocenter_distance=0.0)
        self.assertFalse(res.success)
        self.assertIn('lao_deg', res.message)
        res = self.set_c_arm(lao_deg=90.0, cranial_deg=0.0, source_detector_distance=0.0,
                             source_isocenter_distance=0.0)
        self.assertTrue(res.success, res.message)
        # LAO 90: the beam (the camera's z) along the patient's left (+x).
        deadline = time.time() + 10
        while time.time() < deadline:
            r = self.tf_buffer.lookup_transform('world', 'xray_source', rospy.Time(0),
                                                rospy.Duration(10)).transform.rotation
            beam = rotate((r.x, r.y, r.z, r.w), (0.0, 0.0, 1.0))
            if beam[0] > 0.999:
                break
            time.sleep(0.1)
        self.assertGreater(beam[0], 0.999, beam)
        self.assertTrue(self.set_c_arm(lao_deg=0.0, cranial_deg=0.0, source_detector_distance=0.0,
                                       source_isocenter_distance=0.0).success)

    def beam(self):
        r = self.tf_buffer.lookup_transform('world', 'xray_source', rospy.Time(0),
                                            rospy.Duration(10)).transform.rotation
        return rotate((r.x, r.y, r.z, r.w), (0.0, 0.0, 1.0))

    def test_5_reconfigure_turns_the_c_arm_and_refuses_out_of_range(self):
        client = Client('navigation_node/xray', timeout=30)
        client.update_configuration({'lao_deg': 30.0})
        expected = (math.sin(math.radians(30)), math.cos(math.radians(30)), 0.0)
        deadline = time.time() + 10
        while time.time() < deadline and sum((a - b) ** 2 for a, b in zip(self.beam(), expected)) > 1e-12:
            time.sleep(0.1)
        self.assertAlmostEqual(self.beam()[0], expected[0], places=6)
        client.update_configuration({'lao_deg': 200.0})
        deadline = time.time() + 10
        while time.time() < deadline and abs(client.get_configuration(timeout=5)['lao_deg'] - 30.0) > 1e-9:
            time.sleep(0.1)
        self.assertAlmostEqual(client.get_configuration(timeout=5)['lao_deg'], 30.0)
        self.assertAlmostEqual(self.beam()[0], expected[0], places=6)
        client.update_configuration({'lao_deg': 0.0})

    def test_4_contrast_darkens_the_vessels_downstream(self):
        res = self.inject(device='no_such_device', duration=1.0)
        self.assertFalse(res.success)
        res = self.inject(device='guidewire', duration=0.0)
        self.assertFalse(res.success)
        self.assertIn('duration', res.message)
        before, _ = self.next_image()
        res = self.inject(device='guidewire', duration=30.0)
        self.assertTrue(res.success, res.message)
        self.assertGreater(res.segments, 0)
        after, _ = self.next_image()
        darker = sum(1 for a, b in zip(bytearray(before.data), bytearray(after.data)) if b + 20 < a)
        self.assertGreater(darker, 100)

    def test_6_a_new_scene_brings_its_own_c_arm(self):
        # arch_navigation's xray: section sets LAO 30 (the scene file).
        with open(os.path.join(CONFIG, 'scenes', 'arch_navigation.yaml')) as f:
            lao = math.radians(yaml.safe_load(f)['xray']['lao_deg'])
        rospy.wait_for_service('load_scene', timeout=60)
        res = rospy.ServiceProxy('load_scene', LoadScene)('arch_navigation')
        self.assertTrue(res.success, res.message)
        deadline = time.time() + 30
        while time.time() < deadline and abs(self.beam()[0] - math.sin(lao)) > 1e-6:
            self.next_image()
        self.assertAlmostEqual(self.beam()[0], math.sin(lao), places=6)
        client = Client('navigation_node/xray', timeout=30)
        deadline = time.time() + 10
        while (time.time() < deadline
               and abs(client.get_configuration(timeout=5)['lao_deg'] - math.degrees(lao)) > 1e-9):
            time.sleep(0.1)
        self.assertAlmostEqual(client.get_configuration(timeout=5)['lao_deg'], math.degrees(lao))


if __name__ == '__main__':
    rostest.rosrun('endovascular_sim', 'xray', XrayTest)
