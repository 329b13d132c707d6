#!/usr/bin/env python3
"""Runs navigation_node headless on each scene for its whole scripted
procedure and reports what it held: the real-time factor, the publish rate
and the longest stall between two frames (wall time); with --xray it also
watches the virtual fluoroscopy (xray/image, which the node renders only
while subscribed) and reports its frame rate. Not a timed test: the
figures go into docs/performance.md.

Usage: scripts/node_benchmark.py [--xray] [SCENE ...]   (default: the navigation scenes)
Needs the built workspace (scripts/build.sh); starts its own master.
"""
import os
import random
import subprocess
import sys
import time

import yaml

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = ['carotid', 'carotid_selective', 'carotid_catheter', 'network', 'aneurysm',
          'aneurysm_coiling', 'patient_example']


def duration_of(scene):
    with open(os.path.join(REPO, 'config', 'scenes', scene + '.yaml')) as f:
        return float(yaml.safe_load(f).get('duration', 1.0))


def measure(scene, duration, xray):
    """Child process: subscribes to stats until the scene's duration has been
    simulated (or 20x that in wall time); prints one result line."""
    import rospy
    from endovascular_sim.msg import StepStats
    from sensor_msgs.msg import Image
    arrivals, sims, images = [], [], []

    def on_stats(msg):
        if msg.scene == scene:
            arrivals.append(time.monotonic())
            sims.append(msg.sim_time)

    rospy.init_node('node_benchmark', anonymous=True)
    rospy.Subscriber('stats', StepStats, on_stats)
    if xray:
        rospy.Subscriber('xray/image', Image, lambda msg: images.append(time.monotonic()),
                         queue_size=1, buff_size=2 ** 22)
    deadline = time.monotonic() + 60.0 + 20.0 * duration
    while time.monotonic() < deadline and (not sims or sims[-1] < duration):
        time.sleep(0.05)
    if len(arrivals) < 2:
        print('%-18s no frames received' % scene)
        return 1
    wall = arrivals[-1] - arrivals[0]
    gaps = [b - a for a, b in zip(arrivals, arrivals[1:])]
    line = '%-18s %8.2f %10.2f %10.1f %12.0f' % (scene, sims[-1] - sims[0], (sims[-1] - sims[0]) / wall,
                                               (len(arrivals) - 1) / wall, 1e3 * max(gaps))
    if xray:
        shown = [t for t in images if arrivals[0] <= t <= arrivals[-1]]
        line += ' %14.1f' % (max(0, len(shown) - 1) / wall)
    print(line)
    return 0


def run(scene, xray):
    port = 13000 + random.randrange(1000)
    env = dict(os.environ, ROS_MASTER_URI='http://localhost:%d' % port)
    launch = subprocess.Popen(['roslaunch', '-p', str(port), 'endovascular_sim', 'navigation.launch',
                               'scene:=' + scene], env=env, stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL)
    try:
        child = subprocess.run([sys.executable, __file__, '--measure', scene,
                                str(duration_of(scene))] + (['--xray'] if xray else []),
                               env=env, capture_output=True, text=True)
        for line in child.stdout.splitlines():  # (rospy's waits for the master left out)
            if line.startswith(scene):
                print(line, flush=True)
        return child.returncode
    finally:
        launch.terminate()
        launch.wait(timeout=30)


def main(argv):
    if len(argv) >= 4 and argv[1] == '--measure':
        return measure(argv[2], float(argv[3]), '--xray' in argv[4:])
    xray = '--xray' in argv[1:]
    scenes = [a for a in argv[1:] if a != '--xray'] or SCENES
    print('%-18s %8s %10s %10s %12s' % ('scene', 'sim [s]', 'RTF held', 'frames/s', 'stall [ms]')
          + (' %14s' % 'xray frames/s' if xray else ''))
    return max(run(s, xray) for s in scenes)


if __name__ == '__main__':
    sys.exit(main(sys.argv))
