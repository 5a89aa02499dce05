#!/usr/bin/env python3
"""Checks the repository's launch files (launch/*.launch) without starting them.

catkin's roslaunch-check only works on files inside a package, so this does the same and more for
the root launch/ folder: each file loads with its args (XML, substitutions, includes, required
args), every node's package and executable exist, and the nodelets follow DESIGN.md: exactly one
manager, every nodelet loaded into it (none standalone), and every plugin declared by a package;
every YAML file a node is given by name loads (UTF-8, YAML), and the camera-IMU calibration passes
camera_imu_static_tf.py's own check (strict keys, a unit quaternion).
Every *.launch in DIR is checked; files that need args get them from FILE:arg:=value,... specs.
Usage (from test/launch_files.test): check_launch_files.py DIR [FILE:arg:=value,...] ...
"""
import os
import subprocess
import sys
import tempfile
import unittest
import xml.etree.ElementTree as ET

import roslaunch.config
import roslib.packages
import rospkg
from rig_model.strict_yaml import FileError, load_yaml_file

LAUNCH_DIR = None
ARGS = {}  # file name -> [arg:=value]
GRAPH_FILES = ("rig.launch", "replay.launch", "sim.launch")  # the full processing graph


def nodelet_plugins():
    """Every nodelet class declared by a package's nodelet plugin XML."""
    out = subprocess.run(["rospack", "plugins", "--attrib=plugin", "nodelet"], check=True,
                         capture_output=True, text=True).stdout
    classes = set()
    for line in out.splitlines():
        _, path = line.split(None, 1)
        root = ET.parse(path.strip()).getroot()
        for c in root.iter("class"):
            classes.add(c.get("name"))
    return classes


def yaml_files(cfg):
    """(what, path) of every YAML file the launch hands a node by absolute path (the nodes read them)."""
    files = [("param " + k, v) for k, v in ((k, p.value) for k, p in cfg.params.items())
             if isinstance(v, str) and v.endswith(".yaml") and os.path.isabs(v)]
    files += [("node %s arg" % n.name, a) for n in cfg.nodes for a in n.args.split()
              if a.endswith(".yaml") and os.path.isabs(a)]
    return files


class LaunchFilesTest(unittest.TestCase):
    def check_files(self, name, cfg):
        """Every YAML loads; the calibrations pass camera_imu_static_tf.py's check. Returns the
        camera-IMU calibrations and gyro calibrations the launch uses."""
        for what, path in yaml_files(cfg):
            try:
                load_yaml_file(path)
            except FileError as e:
                self.fail("%s: %s: %s" % (name, what, e))
        params = {k: p.value for k, p in cfg.params.items()}
        checks = [n.args.split() for n in cfg.nodes if n.type == "camera_imu_static_tf.py"]
        checks += [[v] for k, v in params.items() if k.endswith("/camera_imu_file")]
        checks += [[params[k[:-len("gyro_calibration_file")] + "camera_imu_file"], v] for k, v in params.items()
                   if k.endswith("/gyro_calibration_file")]
        script = os.path.join(rospkg.RosPack().get_path("imu_driver"), "scripts", "camera_imu_static_tf.py")
        for files in checks:
            r = subprocess.run([sys.executable, script, "--check"] + files, capture_output=True, text=True)
            self.assertEqual(r.returncode, 0, "%s: %s" % (name, r.stderr.strip()))
        return {f[0] for f in checks}, {f[1] for f in checks if len(f) == 2}

    def check(self, name, args):
        path = os.path.join(LAUNCH_DIR, name)
        try:
            cfg = roslaunch.config.load_config_default([(path, args)], None, verbose=False)
        except Exception as e:  # the loader raises several kinds; the message is what matters
            self.fail("%s %s does not load: %s" % (name, args, e))
        rp = rospkg.RosPack()
        managers, loads = [], []
        for n in cfg.nodes:
            try:
                rp.get_path(n.package)
            except rospkg.ResourceNotFound:
                self.fail("%s: node %s: package %s not found" % (name, n.name, n.package))
            self.assertTrue(roslib.packages.find_node(n.package, n.type, rospack=rp),
                            "%s: node %s: executable %s/%s not found" % (name, n.name, n.package, n.type))
            if n.package == "nodelet":
                words = n.args.split()
                self.assertTrue(words, "%s: nodelet %s without arguments" % (name, n.name))
                self.assertNotEqual(words[0], "standalone", "%s: nodelet %s is standalone" % (name, n.name))
                if words[0] == "manager":
                    managers.append(n.name)
                else:
                    self.assertEqual(words[0], "load", "%s: nodelet %s: %s" % (name, n.name, n.args))
                    loads.append((n.name, words[1], words[2]))
        self.check_files(name, cfg)
        if not loads and not managers:
            return cfg, []
        self.assertEqual(len(managers), 1, "%s: one nodelet manager expected, found %s" % (name, managers))
        plugins = nodelet_plugins()
        for node, plugin, manager in loads:
            self.assertEqual(manager, managers[0], "%s: %s loads into %s, not the manager" % (name, node, manager))
            self.assertIn(plugin, plugins, "%s: %s: plugin %s is not declared by any package" % (name, node, plugin))
        return cfg, [p for _, p, _ in loads]

    def test_every_launch_file(self):
        names = sorted(f for f in os.listdir(LAUNCH_DIR) if f.endswith(".launch"))
        for name in GRAPH_FILES + ("record.launch",):
            self.assertIn(name, names)
        for name in names:
            _, plugins = self.check(name, ARGS.get(name, []))
            if name in GRAPH_FILES:
                for p in ("cone_tracker/ConeTrackerNodelet", "pose_ekf/PoseEkfNodelet", "ar_overlay/OverlayNodelet"):
                    self.assertIn(p, plugins, "%s: %s missing" % (name, p))
        self.assertIn("imu_driver/ImuDriverNodelet", self.check("rig.launch", [])[1])
        self.assertIn("aravis_camera/CameraNodelet", self.check("rig.launch", [])[1])
        self.assertIn("imu_driver/ImuDriverNodelet", self.check("sim.launch", [])[1])  # the pty is the default
        self.assertNotIn("imu_driver/ImuDriverNodelet", self.check("sim.launch", ["serial_pty:=false"])[1])

    def test_a_broken_file_is_caught(self):
        """The check can fail: a file without its required arg (bag:=) is refused."""
        with self.assertRaises(AssertionError):
            self.check("replay.launch", [])  # bag:= is required

    def test_every_calibration_is_checked(self):
        """rig.launch's camera-IMU calibration reaches both readers; a broken one is refused by name."""
        cfg = roslaunch.config.load_config_default([(os.path.join(LAUNCH_DIR, "rig.launch"), [])], None,
                                                   verbose=False)
        camera_imu, gyro = self.check_files("rig.launch", cfg)
        self.assertEqual(len(camera_imu), 1)  # the driver's and the tf node's are the same file
        self.assertEqual(len(gyro), 1)
        tmp = tempfile.mkdtemp(prefix="ar_bringup_launch_files_")
        path = os.path.join(tmp, "camera_imu.yaml")
        with open(path, "w") as f:
            f.write("camera_imu:\n  rotaton_xyzw: [0, 0, 0, 1]\n")
        with self.assertRaises(AssertionError) as e:
            self.check("rig.launch", ["camera_imu:=" + path])
        self.assertIn(path + ":2: unknown key 'camera_imu.rotaton_xyzw' (did you mean 'rotation_xyzw'?)",
                      str(e.exception))
        path = os.path.join(tmp, "gyro_calibration.yaml")
        with open(path, "w") as f:
            f.write("gyro_bias_rad_s: [0, 0, .nan]\n")
        with self.assertRaises(AssertionError) as e:
            self.check("rig.launch", ["gyro_calibration:=" + path])
        self.assertIn(path + ":1: gyro_bias_rad_s: must be a list of 3 finite numbers", str(e.exception))


if __name__ == "__main__":
    argv = [a for a in sys.argv[1:] if not a.startswith("__") and not a.startswith("--gtest")]
    LAUNCH_DIR = argv[0]
    for spec in argv[1:]:
        name, _, args = spec.partition(":")
        ARGS[name] = [a for a in args.split(",") if a]
    import rostest
    rostest.rosrun("ar_bringup", "launch_files", LaunchFilesTest)
