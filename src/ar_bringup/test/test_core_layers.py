#!/usr/bin/env python3
"""Checks the visible layers of the packages (DESIGN.md, "Core, adapter, shim"), without building.

1. Every core folder is ROS-free: no file under a package's core folders includes a ROS header (ros/,
   nodelet, tf2_ros, sensor_msgs, image_transport, dynamic_reconfigure, and the other ROS packages
   below). A failure names the file, the line and the include.
2. Benchmarks never include test sources: no file under a package's bench/ includes anything from
   test/ (they use the package's testing library), and no CMakeLists.txt puts a test/ folder on a
   benchmark's include path.
3. The rig is described once (issue 17): cone_tracker needs rig_sim only for its tests, only rig_model's
   parser reads the cone layout's keys, and every nodelet's onInit() is at most 40 lines.

Usage: test_core_layers.py [--src DIR] [--xml RESULT.xml]   (DIR defaults to the repository's src/)
"""
import argparse
import os
import re
import sys
import unittest
import xml.etree.ElementTree as ET

SRC = os.path.realpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))

# package -> its ROS-free folders, relative to the package. "dir/" is the whole tree below dir; "dir/*"
# is only the files directly in dir (rig_sim keeps its core headers at the top of include/rig_sim and
# the adapter's in include/rig_sim/ros).
CORE_FOLDERS = {
    "aravis_camera": ["src/core/", "include/aravis_camera/core/"],
    "ar_overlay": ["src/core/", "include/ar_overlay/core/"],
    "cone_tracker": ["src/pose/", "src/vision/", "include/cone_tracker/pose/", "include/cone_tracker/vision/"],
    "cone_survey": ["src/*", "include/cone_survey/*"],
    "imu_driver": ["src/core/", "include/imu_driver/core/"],
    "pose_ekf": ["src/core/", "include/pose_ekf/core/"],
    "rig_sim": ["src/core/", "include/rig_sim/*"],
}

# Headers of the ROS runtime, its messages and its tools: none of them belongs in a core.
ROS_INCLUDE = re.compile(
    r'^\s*#\s*include\s*[<"]\s*('
    r"ros/|nodelet/|pluginlib/|tf2_ros/|tf2_eigen/|tf2_geometry_msgs/|tf2_msgs/|sensor_msgs/|geometry_msgs/|"
    r"nav_msgs/|std_msgs/|std_srvs/|visualization_msgs/|diagnostic_msgs/|diagnostic_updater/|image_transport/|"
    r"cv_bridge/|camera_info_manager/|dynamic_reconfigure/|rosbag/|rosgraph_msgs/|message_filters/|"
    r"[a-z_]+/[A-Z]\w*\.h[\">]|cone_tracker/node/|\w+/ros/)")  # [A-Z]: generated messages and Config.h
TEST_INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^">]*\btest/[^">]*)[">]')
SOURCE_EXT = (".h", ".hpp", ".cpp", ".cc", ".c")
RIG_SIM_INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]rig_sim/')
# The layout's top-level key, quoted as a parser reads it: only rig_model's parser may.
LAYOUT_KEY = re.compile(r'["\']equilateral["\']')
LAYOUT_PARSER = "rig_model/src/layout.cpp"
MAX_ON_INIT_LINES = 40
ON_INIT = re.compile(r"\bonInit\(\)\s*(override\s*)?\{")


def on_init_lengths(path):
    """(first line, lines from the signature to the closing brace) of every onInit() definition in path."""
    with open(path, encoding="utf-8", errors="replace") as f:
        lines = f.read().split("\n")
    found = []
    for i, line in enumerate(lines):
        if not ON_INIT.search(line):
            continue
        depth, j = 0, i
        while j < len(lines):
            depth += lines[j].count("{") - lines[j].count("}")
            if depth == 0:
                break
            j += 1
        found.append((i + 1, j - i + 1))
    return found


def core_files(package):
    root = os.path.join(SRC, package)
    for folder in CORE_FOLDERS[package]:
        if folder.endswith("/*"):
            base = os.path.join(root, folder[:-2])
            names = sorted(os.listdir(base)) if os.path.isdir(base) else []
            yield base, [os.path.join(base, n) for n in names if n.endswith(SOURCE_EXT)]
        else:
            base = os.path.join(root, folder)
            found = []
            for dirpath, _, names in os.walk(base):
                found += [os.path.join(dirpath, n) for n in names if n.endswith(SOURCE_EXT)]
            yield base, sorted(found)


def grep(path, pattern):
    """(line number, include) for every line of path that matches pattern."""
    with open(path, encoding="utf-8", errors="replace") as f:
        return [(i, line.strip()) for i, line in enumerate(f, 1) if pattern.search(line)]


class CoreLayers(unittest.TestCase):
    def test_every_core_folder_exists_and_holds_sources(self):
        for package in sorted(CORE_FOLDERS):
            for base, files in core_files(package):
                self.assertTrue(os.path.isdir(base), f"{package}: core folder {base} is missing")
                self.assertTrue(files, f"{package}: core folder {base} holds no source file")

    def test_core_folders_include_no_ros_header(self):
        bad = []
        for package in sorted(CORE_FOLDERS):
            for _, files in core_files(package):
                for path in files:
                    bad += [f"{os.path.relpath(path, SRC)}:{n}: {line}" for n, line in grep(path, ROS_INCLUDE)]
        self.assertEqual(bad, [], "ROS headers in core folders (move the code to node/ or ros/):\n" + "\n".join(bad))

    def test_the_check_sees_a_ros_include(self):
        # The pattern itself: what a core must not include, and what it may.
        for line in ("#include <ros/ros.h>", '#include "sensor_msgs/Image.h"', "#include <nodelet/nodelet.h>",
                     "#include <tf2_ros/buffer.h>", "#include <image_transport/image_transport.h>",
                     "#include <dynamic_reconfigure/server.h>", '#include "rig_sim/ros/messages.h"',
                     '#include "pose_ekf/PoseEkfConfig.h"', '#include "cone_tracker/ConeDetections.h"'):
            self.assertTrue(ROS_INCLUDE.search(line), line)
        for line in ("#include <Eigen/Core>", '#include "pose_math/pose.h"', '#include "imu_driver/core/gyro_bias.h"',
                     "#include <opencv2/core.hpp>", "#include <tf2/LinearMath/Quaternion.h>"):
            self.assertFalse(ROS_INCLUDE.search(line), line)


class BenchesUseTestingLibraries(unittest.TestCase):
    def test_no_bench_includes_a_test_source(self):
        bad = []
        for package in sorted(os.listdir(SRC)):
            bench = os.path.join(SRC, package, "bench")
            for dirpath, _, names in os.walk(bench):
                for name in sorted(names):
                    path = os.path.join(dirpath, name)
                    if name.endswith(SOURCE_EXT):
                        bad += [f"{os.path.relpath(path, SRC)}:{n}: {line}" for n, line in grep(path, TEST_INCLUDE)]
        self.assertEqual(bad, [], "benchmarks including test sources (use the package's testing library):\n" +
                         "\n".join(bad))

    def test_no_bench_target_has_test_on_its_include_path(self):
        bad = []
        for package in sorted(os.listdir(SRC)):
            cmake = os.path.join(SRC, package, "CMakeLists.txt")
            if not os.path.isfile(cmake):
                continue
            with open(cmake, encoding="utf-8") as f:
                text = f.read()
            for m in re.finditer(r"target_include_directories\(\s*(\S*bench\S*)([^)]*)\)", text):
                if re.search(r"(^|[\s/])test(/|\s|$)", m.group(2)):
                    line = text.count("\n", 0, m.start()) + 1
                    bad.append(f"{package}/CMakeLists.txt:{line}: {m.group(0).split()[0]} ... test")
        self.assertEqual(bad, [], "benchmark targets with test/ on their include path:\n" + "\n".join(bad))



class RigDescription(unittest.TestCase):
    """Issue 17's checks: the tracker does not need the simulator, the layout is parsed in one place,
    nodelets are thin."""

    def test_cone_tracker_needs_rig_sim_only_for_tests(self):
        with open(os.path.join(SRC, "cone_tracker", "package.xml"), encoding="utf-8") as f:
            deps = re.findall(r"<(\w*depend)>\s*rig_sim\s*</", f.read())
        self.assertEqual([d for d in deps if d != "test_depend"], [],
                         "cone_tracker/package.xml: rig_sim may only be a test_depend")
        bad = []
        root = os.path.join(SRC, "cone_tracker")
        for dirpath, _, names in os.walk(root):
            if os.path.relpath(dirpath, root).split(os.sep)[0] == "test":
                continue
            for name in sorted(names):
                path = os.path.join(dirpath, name)
                if name.endswith(SOURCE_EXT):
                    bad += [f"{os.path.relpath(path, SRC)}:{n}: {line}" for n, line in grep(path, RIG_SIM_INCLUDE)]
        self.assertEqual(bad, [], "rig_sim headers outside cone_tracker/test:\n" + "\n".join(bad))

    def test_the_layout_is_parsed_in_one_place(self):
        parsers = []
        for dirpath, _, names in os.walk(SRC):
            if "/test" in dirpath.replace(os.sep, "/"):
                continue
            for name in sorted(names):
                path = os.path.join(dirpath, name)
                if name.endswith(SOURCE_EXT + (".py",)) and grep(path, LAYOUT_KEY):
                    parsers.append(os.path.relpath(path, SRC))
        self.assertEqual(parsers, [LAYOUT_PARSER], "files that read the layout's keys (use rig_model/layout.h)")

    def test_every_nodelet_oninit_is_at_most_40_lines(self):
        long = []
        for dirpath, _, names in os.walk(SRC):
            for name in sorted(names):
                if not name.endswith(".cpp"):
                    continue
                path = os.path.join(dirpath, name)
                for line, length in on_init_lengths(path):
                    if length > MAX_ON_INIT_LINES:
                        long.append(f"{os.path.relpath(path, SRC)}:{line}: onInit() is {length} lines")
        self.assertEqual(long, [], f"onInit() longer than {MAX_ON_INIT_LINES} lines:\n" + "\n".join(long))

    def test_the_oninit_count_sees_a_long_one(self):
        body = "void X::onInit() {\n" + "  a();\n" * 45 + "}\n"
        path = os.path.join(os.environ.get("TMPDIR", "/tmp"), f"on_init_{os.getpid()}.cpp")
        with open(path, "w", encoding="utf-8") as f:
            f.write(body)
        try:
            self.assertEqual(on_init_lengths(path), [(1, 47)])
        finally:
            os.remove(path)

def write_junit(result, tests, path):
    """A JUnit file for catkin_test_results (unittest has no writer of its own)."""
    failed = {id(t): msg for t, msg in result.failures + result.errors}
    suite = ET.Element("testsuite", name="core_layers", tests=str(len(tests)),
                       failures=str(len(result.failures)), errors=str(len(result.errors)))
    for t in tests:
        case = ET.SubElement(suite, "testcase", classname=type(t).__name__, name=t._testMethodName)
        if id(t) in failed:
            ET.SubElement(case, "failure", message="failed").text = failed[id(t)]
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    ET.ElementTree(suite).write(path, encoding="utf-8", xml_declaration=True)


def main():
    global SRC
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--src", default=SRC, help="the folder holding the packages (default: %(default)s)")
    parser.add_argument("--xml", help="also write a JUnit result file here")
    args = parser.parse_args()
    SRC = os.path.realpath(args.src)
    if not os.path.isdir(SRC):
        print(f"test_core_layers.py: --src {args.src}: not a folder", file=sys.stderr)
        return 2
    loader = unittest.TestLoader()
    suite = unittest.TestSuite([loader.loadTestsFromTestCase(c) for c in (CoreLayers, BenchesUseTestingLibraries, RigDescription)])
    tests = [t for case_suite in suite for t in case_suite]
    result = unittest.TextTestRunner(verbosity=2).run(suite)
    if args.xml:
        write_junit(result, tests, args.xml)
    return 0 if result.wasSuccessful() else 1


if __name__ == "__main__":
    sys.exit(main())
