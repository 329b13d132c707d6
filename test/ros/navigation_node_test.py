#!/usr/bin/env python3
"""rostest of navigation_node: commands, joystick, services and refusals.

Every expected value comes from outside the node: the scene files (initial
inserted length, insertion direction), the joystick mapping file, the list of
files in config/scenes, and the commands the test itself sends.
"""
import glob
import math
import os
import re
import subprocess
import threading
import time
import unittest

import roslib.packages
import rospy
import rostest
import tf2_ros
import yaml
from endovascular_sim.msg import DeviceCommand, DeviceStatusArray, StepStats
from endovascular_sim.srv import ListScenes, LoadCenterline, LoadScene
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import Joy
from std_srvs.srv import SetBool, Trigger

from ros_geometry import quaternion_rotate

PKG_DIR = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CONFIG = os.path.join(PKG_DIR, 'config')


def load_yaml(*parts):
    with open(os.path.join(CONFIG, *parts)) as f:
        return yaml.safe_load(f)


class NavigationNodeTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('navigation_node_test')
        cls.lock = threading.RLock()
        cls.states = None
        cls.stats = None
        cls.log = []
        rospy.Subscriber('device_states', DeviceStatusArray, cls._on_states)
        rospy.Subscriber('stats', StepStats, cls._on_stats)
        rospy.Subscriber('/rosout', Log, cls._on_log)
        cls.command_pub = rospy.Publisher('command', DeviceCommand, queue_size=10)
        cls.joy_pub = rospy.Publisher('joy', Joy, queue_size=10)
        for name in ('list_scenes', 'load_scene', 'load_centerline', 'reset', 'pause'):
            rospy.wait_for_service(name, timeout=60)
        cls.list_scenes = rospy.ServiceProxy('list_scenes', ListScenes)
        cls.load_scene = rospy.ServiceProxy('load_scene', LoadScene)
        cls.load_centerline = rospy.ServiceProxy('load_centerline', LoadCenterline)
        cls.reset = rospy.ServiceProxy('reset', Trigger)
        cls.pause = rospy.ServiceProxy('pause', SetBool)
        cls.tf_buffer = tf2_ros.Buffer()
        cls.tf_listener = tf2_ros.TransformListener(cls.tf_buffer)
        cls.scene = load_yaml('scenes', 'free_insertion.yaml')
        cls.joystick = load_yaml('joystick', 'xbox.yaml')
        while cls.command_pub.get_num_connections() == 0 or cls.joy_pub.get_num_connections() == 0:
            time.sleep(0.1)

    @classmethod
    def _on_states(cls, msg):
        with cls.lock:
            cls.states = msg

    @classmethod
    def _on_stats(cls, msg):
        with cls.lock:
            cls.stats = msg

    @classmethod
    def _on_log(cls, msg):
        if msg.name.endswith('navigation_node'):
            with cls.lock:
                cls.log.append(msg)

    def setUp(self):
        self.assertTrue(self.load_scene('free_insertion').success)
        self.assertTrue(self.pause(False).success)
        self.assertTrue(self.reset().success)
        self.wait_for(lambda: self.stats is not None and self.stats.scene == 'free_insertion'
                      and self.stats.sim_time < 0.5, 'fresh free_insertion frames')
        self.wait_for(lambda: self.states is not None and self.device_names() == ['guidewire'],
                      'free_insertion device states')  # a separate topic from the stats
        with self.lock:
            self.log.clear()  # the class's list, which the subscriber fills

    # --- helpers ---------------------------------------------------------------
    def wait_for(self, condition, what, timeout=20.0):
        end = time.time() + timeout
        while time.time() < end:
            with self.lock:
                if condition():
                    return
            time.sleep(0.02)
        self.fail('timed out waiting for ' + what)

    def device(self, name='guidewire'):
        with self.lock:
            return next(d for d in self.states.devices if d.name == name)

    def device_names(self):
        with self.lock:
            return [d.name for d in self.states.devices]

    def device_and_time(self, name='guidewire'):
        """A device's status and the simulated time of the same message (the
        stats topic is a different message: pairing it with a device's state
        skews rates by up to a frame)."""
        with self.lock:
            return (next(d for d in self.states.devices if d.name == name),
                    self.states.header.stamp.to_sec())

    def sim_time(self):
        with self.lock:
            return self.stats.sim_time

    def wait_sim(self, seconds):
        t0 = self.sim_time()
        self.wait_for(lambda: self.stats.sim_time >= t0 + seconds, 'simulated time to pass',
                      timeout=30.0 + 5 * seconds)

    def command(self, mode, insertion, rotation, device='guidewire'):
        self.command_pub.publish(DeviceCommand(device=device, mode=mode, insertion=insertion,
                                               rotation=rotation))

    def warnings_containing(self, text):
        with self.lock:
            return [m.msg for m in self.log if m.level >= Log.WARN and text in m.msg]

    def tip_frame_angle(self, axis):
        """Angle of the tip frame's y axis about the insertion axis [rad]."""
        t = self.tf_buffer.lookup_transform('world', 'guidewire/tip', rospy.Time(0),
                                            rospy.Duration(5.0)).transform.rotation
        y = quaternion_rotate((t.x, t.y, t.z, t.w), (0.0, 1.0, 0.0))
        # components in the plane normal to the axis (axis = x here)
        self.assertAlmostEqual(abs(axis[0]), 1.0)
        return math.atan2(y[2], y[1])

    # --- tests -----------------------------------------------------------------
    def test_list_scenes_returns_the_shipped_files(self):
        files = sorted(os.path.splitext(os.path.basename(p))[0]
                       for p in glob.glob(os.path.join(CONFIG, 'scenes', '*.yaml')))
        self.assertEqual(sorted(self.list_scenes().scenes), files)

    def test_insertion_of_50_mm_moves_length_and_tip(self):
        initial = self.scene['devices'][0]['inserted_length']
        axis = self.scene['devices'][0]['insertion_direction']
        self.assertAlmostEqual(self.device().inserted_length, initial, places=9)
        tip0 = self.device().tip.position
        self.command(DeviceCommand.POSITION, initial + 0.05, 0.0)
        self.wait_for(lambda: abs(self.device().inserted_length - initial - 0.05) < 1e-9,
                      'the inserted length to reach +50 mm')
        self.wait_sim(0.5)  # let the free part settle
        tip1 = self.device().tip.position
        advance = sum((getattr(tip1, c) - getattr(tip0, c)) * a for c, a in zip('xyz', axis))
        self.assertAlmostEqual(advance, 0.05, delta=0.003)

    def test_rotation_turns_the_tip_frame(self):
        axis = self.scene['devices'][0]['insertion_direction']
        initial = self.scene['devices'][0]['inserted_length']
        before = self.tip_frame_angle(axis)
        self.command(DeviceCommand.POSITION, initial, math.pi / 2)
        self.wait_for(lambda: abs(self.device().rotation - math.pi / 2) < 1e-9,
                      'the rotation to reach 90 degrees')
        self.wait_sim(0.5)
        after = self.tip_frame_angle(axis)
        turned = math.remainder(after - before, 2 * math.pi)
        self.assertAlmostEqual(turned, math.pi / 2, delta=0.1)

    def test_joystick_inserts_only_with_the_deadman_button(self):
        m = self.joystick
        axes = [0.0] * (max(m['insertion_axis'], m['rotation_axis']) + 1)
        buttons = [0] * (max(m['deadman_button'], m['switch_device_button']) + 1)
        axes[m['insertion_axis']] = 1.0
        start = self.device().inserted_length
        for _ in range(10):  # full deflection without the dead-man button
            self.joy_pub.publish(Joy(axes=axes, buttons=buttons))
            time.sleep(0.05)
        self.wait_sim(0.2)
        self.assertEqual(self.device().inserted_length, start)
        buttons[m['deadman_button']] = 1
        self.joy_pub.publish(Joy(axes=axes, buttons=buttons))
        self.wait_for(lambda: self.device().inserted_length > start + 1e-4, 'joystick insertion')
        d0, t0 = self.device_and_time()
        self.wait_sim(0.3)
        d1, t1 = self.device_and_time()
        l0, l1 = d0.inserted_length, d1.inserted_length
        self.assertAlmostEqual((l1 - l0) / (t1 - t0), m['insertion_scale'], delta=0.002)
        axes[m['insertion_axis']] = 0.0  # the rotation axis alone turns the device
        axes[m['rotation_axis']] = 1.0
        self.joy_pub.publish(Joy(axes=axes, buttons=buttons))
        self.wait_sim(0.1)
        d0, t0 = self.device_and_time()
        self.wait_sim(0.3)
        d1, t1 = self.device_and_time()
        r0, r1 = d0.rotation, d1.rotation
        self.assertAlmostEqual((r1 - r0) / (t1 - t0), m['rotation_scale'], delta=0.2)
        buttons[m['deadman_button']] = 0  # release: the device stops
        self.joy_pub.publish(Joy(axes=axes, buttons=buttons))
        self.wait_sim(0.1)
        stopped = self.device().inserted_length
        self.wait_sim(0.3)
        self.assertEqual(self.device().inserted_length, stopped)

    def test_joystick_message_too_short_is_refused(self):
        self.joy_pub.publish(Joy(axes=[1.0], buttons=[1]))
        self.wait_for(lambda: self.warnings_containing('joy message ignored'), 'a refusal')

    def refused_commands(self):
        with self.lock:
            return self.stats.refused_commands

    def test_bad_commands_are_refused_and_the_state_is_kept(self):
        self.wait_sim(0.2)
        before = self.device().inserted_length
        refused = self.refused_commands()
        self.command(DeviceCommand.VELOCITY, float('nan'), 0.0)
        self.wait_for(lambda: self.warnings_containing('finite'), 'the NaN refusal')
        self.command(DeviceCommand.VELOCITY, 10.0, 0.0)
        self.wait_for(lambda: self.warnings_containing('exceeds the limit'),
                      'the out-of-range refusal')
        self.command(DeviceCommand.VELOCITY, 0.01, 0.0, device='nope')
        self.wait_for(lambda: self.warnings_containing("unknown device 'nope'"),
                      'the unknown-device refusal')
        self.command(7, 0.01, 0.0)
        self.wait_for(lambda: self.warnings_containing('mode 7'), 'the unknown-mode refusal')
        # four malformed commands, counted in /stats (a detach refused is no malformed command)
        self.wait_for(lambda: self.stats.refused_commands == refused + 4, 'a count of 4 in /stats')
        self.command(DeviceCommand.DETACH, 0.0, 0.0)  # the guidewire has no detach_section
        self.wait_for(lambda: self.warnings_containing('no detach_section'),
                      'the detach refusal')
        self.wait_sim(0.2)
        self.assertEqual(self.device().inserted_length, before)
        self.assertTrue(math.isfinite(self.device().tip.position.x))

    def test_a_flood_of_malformed_commands_is_counted_and_logged_throttled(self):
        refused = self.refused_commands()
        start = time.time()
        for _ in range(200):  # 200 commands too fast for the wire, in about a second
            self.command(DeviceCommand.VELOCITY, 30.0, 0.0)
            time.sleep(0.005)
        self.wait_for(lambda: self.stats.refused_commands == refused + 200,
                      'all 200 counted in /stats')
        elapsed = time.time() - start
        self.wait_sim(0.2)  # the last warnings reach /rosout
        with self.lock:
            warnings = len(self.warnings_containing('speed 30 m/s'))
        # the first at once, then at most one a second
        self.assertGreaterEqual(warnings, 1)
        self.assertLessEqual(warnings, 2 + int(elapsed))

    def test_unknown_scene_is_refused_and_the_scene_keeps_running(self):
        res = self.load_scene('nope')
        self.assertFalse(res.success)
        self.assertIn('nope', res.message)
        t0 = self.sim_time()
        self.wait_sim(0.2)
        with self.lock:
            self.assertEqual(self.stats.scene, 'free_insertion')
            self.assertGreater(self.stats.sim_time, t0)

    def test_load_scene_switches_and_topics_follow(self):
        res = self.load_scene('aneurysm')
        self.assertTrue(res.success, res.message)
        device = load_yaml('scenes', 'aneurysm.yaml')['devices'][0]
        self.wait_for(lambda: self.stats.scene == 'aneurysm', 'aneurysm stats')
        # stats and device states are separate topics: either may arrive first
        self.wait_for(lambda: self.device_names() == ['coil'], 'the coil in the device states')
        self.assertAlmostEqual(self.device('coil').inserted_length,
                               device.get('inserted_length', 0.0), delta=0.002)
        from nav_msgs.msg import Path
        path = rospy.wait_for_message('devices/coil/path', Path, timeout=10)
        self.assertGreater(len(path.poses), 10)

    def test_the_drive_wrench_is_published_per_device(self):
        from geometry_msgs.msg import WrenchStamped
        w = rospy.wait_for_message('devices/guidewire/drive_wrench', WrenchStamped, timeout=10)
        self.assertTrue(w.header.frame_id)
        for v in (w.wrench.force.x, w.wrench.force.y, w.wrench.force.z, w.wrench.torque.x):
            self.assertTrue(math.isfinite(v))
        self.assertTrue(math.isfinite(self.device().drive_force))
        # Every step's wrench, stamped with its step's time: 1 ms apart (the
        # scene file's time step), for more than half a simulated second.
        dt = load_yaml('scenes', 'free_insertion.yaml')['time_step']
        stamps = []
        sub = rospy.Subscriber('devices/guidewire/drive_wrench', WrenchStamped,
                               lambda m: stamps.append(m.header.stamp.to_sec()), queue_size=1000)
        self.wait_for(lambda: len(stamps) > 600, '600 drive wrenches')
        sub.unregister()
        gaps = sorted(b - a for a, b in zip(stamps, stamps[1:]))
        # On the step grid (a message the transport dropped under load leaves
        # a whole number of steps), one step apart as a rule.
        for g in gaps:
            self.assertLess(abs(g / dt - round(g / dt)), 1e-3, g)
            self.assertGreaterEqual(round(g / dt), 1, g)
        self.assertAlmostEqual(gaps[len(gaps) // 2], dt, delta=1e-6)

    def test_a_patient_centreline_loads_like_any_scene(self):
        # patient_example: a VTK centreline (VMTK layout), its branches named
        res = self.load_scene('patient_example')
        self.assertTrue(res.success, res.message)
        self.wait_for(lambda: self.stats.scene == 'patient_example', 'patient_example stats')
        self.wait_for(lambda: self.device_names() == ['guidewire'], 'the guidewire')
        self.wait_for(lambda: self.device('guidewire').tip_vessel == 'descending_aorta',
                      'the tip in the named descending aorta')

    def test_a_bare_centreline_loads_with_its_units_and_is_refused_without(self):
        vtp = '../vessels/example_patient.vtp'  # relative: from config/scenes/
        # no units (the node has no ~units): refused, free_insertion goes on
        for res in (self.load_centerline(centerline=vtp, units='', radius_array='',
                                         base_scene=''),
                    self.load_scene(vtp)):
            self.assertFalse(res.success)
            self.assertIn('units declared', res.message)
            self.assertIn('example_patient.vtp', res.message)
        res = self.load_centerline(centerline=vtp, units='furlong', radius_array='',
                                   base_scene='')
        self.assertFalse(res.success)
        self.assertIn('must be m, cm, mm or um', res.message)
        res = self.load_centerline(centerline=vtp, units='mm', radius_array='Radius',
                                   base_scene='')
        self.assertFalse(res.success)
        self.assertIn("no point-data array 'Radius'", res.message)
        t0 = self.sim_time()
        self.wait_sim(0.1)
        with self.lock:
            self.assertEqual(self.stats.scene, 'free_insertion')
            self.assertGreater(self.stats.sim_time, t0)
        # the base lies supine: without the file's frame, refused
        res = self.load_centerline(centerline=vtp, units='mm', radius_array='', base_scene='')
        self.assertFalse(res.success)
        self.assertIn('vessels.frame', res.message)
        # names that are no chain: refused, naming the branches
        res = self.load_centerline(centerline=vtp, units='mm', radius_array='', base_scene='',
                                   frame='LAS', names=['6: arch', '9: arch'])
        self.assertFalse(res.success)
        self.assertIn('do not follow one another', res.message)
        # with its units and frame: the base scene's guidewire at the widest end, the arch
        # that the file splits at its ostia named as one vessel
        res = self.load_centerline(centerline=vtp, units='mm', radius_array='', base_scene='',
                                   frame='LAS', names=['9: aortic_arch', '11: aortic_arch'])
        self.assertTrue(res.success, res.message)
        self.wait_for(lambda: self.stats.scene == 'example_patient', 'example_patient stats')
        self.wait_for(lambda: self.device_names() == ['guidewire'], 'the guidewire')
        self.wait_for(lambda: self.device('guidewire').tip_vessel.startswith('branch_'),
                      'the tip in a branch named by its id')

    def test_every_new_vessels_subscriber_gets_the_scene_mesh(self):
        from visualization_msgs.msg import Marker
        # free_insertion (setUp) has no vessels: a new subscriber is told so
        self.assertEqual(rospy.wait_for_message('vessels', Marker, timeout=30).action,
                         Marker.DELETE)
        res = self.load_scene('aneurysm')
        self.assertTrue(res.success, res.message)
        triangles = int(re.search(r'vessel mesh of (\d+) triangles', res.message).group(1))
        self.wait_for(lambda: self.stats.scene == 'aneurysm', 'aneurysm stats')
        self.wait_sim(0.2)  # frames have gone by: the mesh was published before we subscribe
        for _ in range(2):  # each wait_for_message is a fresh subscription
            mesh = rospy.wait_for_message('vessels', Marker, timeout=30)
            self.assertEqual(mesh.type, Marker.TRIANGLE_LIST)
            self.assertEqual(len(mesh.points), 3 * triangles)

    def test_reset_returns_to_the_initial_state(self):
        initial = self.scene['devices'][0]['inserted_length']
        self.command(DeviceCommand.VELOCITY, 0.02, 0.0)
        self.wait_for(lambda: self.device().inserted_length > initial + 0.005, 'insertion')
        self.assertTrue(self.reset().success)
        self.wait_for(lambda: self.stats.sim_time < 0.2, 'time to restart')
        # device_states is a separate topic from stats: it may lag a frame
        self.wait_for(lambda: abs(self.device().inserted_length - initial) <= 0.02 * 0.2 + 1e-9,
                      'the initial inserted length back in the device states')
        self.wait_sim(0.3)  # the command was cleared by the reset
        self.assertAlmostEqual(self.device().inserted_length, initial, places=9)

    def test_invalid_parameters_fail_fast_naming_each(self):
        node = roslib.packages.find_node('endovascular_sim', 'navigation_node')[0]
        run = subprocess.run([node, '__name:=bad_parameters', '_rate:=fast', '_plane_size:=1.0',
                              '_vessel_mesh_rate:=0'], capture_output=True, text=True, timeout=60)
        self.assertNotEqual(run.returncode, 0)
        out = run.stdout + run.stderr
        for name in ('~rate must be a number', '~plane_size', '~vessel_mesh_rate'):
            self.assertIn(name, out)

    def test_unloadable_start_scene_fails_fast(self):
        node = roslib.packages.find_node('endovascular_sim', 'navigation_node')[0]
        run = subprocess.run([node, '__name:=bad_scene', '_scene:=nope'], capture_output=True,
                             text=True, timeout=60)
        self.assertNotEqual(run.returncode, 0)
        self.assertIn('nope', run.stdout + run.stderr)

    def test_solver_options_change_at_run_time(self):
        import dynamic_reconfigure.client
        client = dynamic_reconfigure.client.Client('navigation_node', timeout=30)
        scene_contact = self.scene.get('contact', {})
        config = client.update_configuration({'solver': 'pgs', 'max_activation_loops': 3})
        self.assertEqual(config['solver'], 'pgs')
        self.assertEqual(config['max_activation_loops'], 3)
        self.wait_sim(0.1)  # the node keeps stepping with them
        self.assertTrue(self.load_scene('free_insertion').success)  # back to the scene's own
        expected = scene_contact.get('solver', 'status')
        end = time.time() + 10  # the update arrives on parameter_updates
        while client.get_configuration(timeout=10)['solver'] != expected and time.time() < end:
            time.sleep(0.05)
        self.assertEqual(client.get_configuration(timeout=10)['solver'], expected)
        client.close()

    def test_pause_stops_and_resumes_simulated_time(self):
        self.assertTrue(self.pause(True).success)
        self.wait_for(lambda: self.stats.paused, 'paused stats')
        t0 = self.sim_time()
        time.sleep(0.5)
        self.assertEqual(self.sim_time(), t0)
        self.assertTrue(self.pause(False).success)
        self.wait_for(lambda: self.stats.sim_time > t0 + 0.1, 'time to run again')

    def test_scene_paths_outside_the_scene_folders_are_refused(self):
        for request, words in (('../../etc/passwd', 'outside the scene folders'),
                               ('/etc/passwd', 'outside the scene folders'),
                               ('', 'empty')):
            res = self.load_scene(request)
            self.assertFalse(res.success, request)
            self.assertIn(words, res.message)
        # a relative path is taken from config/scenes/
        res = self.load_scene('aneurysm.yaml')
        self.assertTrue(res.success, res.message)
        self.wait_for(lambda: self.stats.scene == 'aneurysm', 'aneurysm stats')

    def test_malformed_scene_is_refused_and_the_scene_keeps_running(self):
        folder = os.path.join(CONFIG, 'scenes')
        bad = os.path.join(folder, '_rostest_bad.yaml')
        try:
            with open(bad, 'w') as f:
                f.write('name: bad\ntime_step: 0.001\ndevices: 7\n')
            res = self.load_scene('_rostest_bad.yaml')
        finally:
            os.remove(bad)
        self.assertFalse(res.success)
        self.assertIn('devices', res.message)
        t0 = self.sim_time()
        self.wait_sim(0.2)
        with self.lock:
            self.assertEqual(self.stats.scene, 'free_insertion')
            self.assertGreater(self.stats.sim_time, t0)

    def test_clock_follows_the_simulation_and_stamps_follow_the_clock(self):
        from rosgraph_msgs.msg import Clock
        first = rospy.wait_for_message('/clock', Clock, timeout=10).clock
        with self.lock:
            stats = self.stats
        self.wait_sim(0.5)
        later = rospy.wait_for_message('/clock', Clock, timeout=10).clock
        advanced = (later - first).to_sec()
        with self.lock:
            simulated = self.stats.sim_time - stats.sim_time
            stamp_minus_time = self.stats.header.stamp.to_sec() - self.stats.sim_time
        # the clock advanced by simulated time (give or take a frame or two),
        # and every stamp is the clock at its simulated time
        self.assertAlmostEqual(advanced, simulated, delta=0.2)
        self.assertAlmostEqual(stamp_minus_time,
                               stats.header.stamp.to_sec() - stats.sim_time, delta=1e-6)
        # a reset starts simulated time again, the clock goes on forward
        self.assertTrue(self.reset().success)
        self.wait_for(lambda: self.stats.sim_time < 0.2, 'time to restart')
        after = rospy.wait_for_message('/clock', Clock, timeout=10).clock
        self.assertGreater(after.to_sec(), later.to_sec())

    def test_out_of_range_rotation_target_is_refused(self):
        self.command(DeviceCommand.POSITION, 0.03, 1e30)
        self.wait_for(lambda: self.warnings_containing('1000 turns'), 'the rotation refusal')

    def test_out_of_range_solver_options_are_refused_with_a_message(self):
        import dynamic_reconfigure.client
        client = dynamic_reconfigure.client.Client('navigation_node', timeout=30)
        config = client.update_configuration({'lcp_tolerance': -1.0})
        self.assertGreater(config['lcp_tolerance'], 0.0)  # what is in force
        self.wait_for(lambda: self.warnings_containing('contact.tolerance must lie in'),
                      'the solver option refusal')
        client.close()


if __name__ == '__main__':
    rostest.rosrun('endovascular_sim', 'navigation_node', NavigationNodeTest)
