"""rig_check's checks, on plain inputs (no ROS here): each returns a Result with PASS/WARN/FAIL, what
was measured and, when not PASS, the fix. scripts/rig_check gathers the inputs from a running graph;
test/test_rig_check.py feeds synthetic ones.
"""
import ipaddress
import math
from collections import namedtuple

PASS, WARN, FAIL = "PASS", "WARN", "FAIL"
Result = namedtuple("Result", "level name detail fix")

# Defaults of the thresholds (issue 18): camera within 10 % of its rate, IMU 100 Hz +- 5 %, >= 3 cones,
# stamps within 20 ms of the host clock.
CAMERA_RATE_TOLERANCE = 0.10
IMU_RATE_HZ = 100.0
IMU_RATE_TOLERANCE = 0.05
MIN_CONES = 3
MAX_CLOCK_OFFSET_S = 0.020
# EKF NIS mean per degree of freedom (the camera pose's over its 6, or the cones' in cones mode): PASS within
# [0.25, 2], WARN outside, FAIL above 4.
NIS_DOF = 6
NIS_LOW_FACTOR, NIS_HIGH_FACTOR, NIS_FAIL_FACTOR = 0.25, 2.0, 4.0


def ok(name, detail):
    return Result(PASS, name, detail, "")


def rate_from_stamps(stamps_s):
    """Messages per second of sensor time: (n - 1) / span of the header stamps (None below 2 stamps).
    Dropped messages lower it; a slow receiver does not."""
    if len(stamps_s) < 2:
        return None
    s = sorted(stamps_s)
    span = s[-1] - s[0]
    return (len(s) - 1) / span if span > 0 else None


def check_rate(name, topic, stamps_s, expected_hz, tolerance, fix):
    rate = rate_from_stamps(stamps_s)
    if rate is None:
        return Result(FAIL, name, "%d message(s) on %s, too few for a rate" % (len(stamps_s), topic), fix)
    detail = "%.1f Hz on %s (expected %.1f Hz +- %.0f %%)" % (rate, topic, expected_hz, tolerance * 100)
    if abs(rate - expected_hz) > tolerance * expected_hz:
        return Result(FAIL, name, detail, fix)
    return ok(name, detail)


def check_camera_found(n_images, topic):
    if n_images == 0:
        return Result(FAIL, "camera found", "no image on %s" % topic,
                      "check the camera's power and cable, `arv-tool-0.8` lists it, and the camera driver's "
                      "diagnostics (rostopic echo /diagnostics)")
    return ok("camera found", "%d image(s) on %s" % (n_images, topic))


def check_camera_info(info):
    """info: dict with K (9 floats), D (list), distortion_model, width, height; None: none received."""
    name = "camera calibrated"
    fix = ("calibrate the camera (rosrun camera_calibration cameracalibrator.py) and pass its YAML: "
           "roslaunch launch/rig.launch camera_info_url:=file:///path/camera.yaml")
    if info is None:
        return Result(FAIL, name, "no camera_info received",
                      "start the camera driver (see camera found); it publishes camera/camera_info with the images")
    K = list(info["K"])
    if len(K) != 9 or K[0] <= 0 or K[4] <= 0 or not all(math.isfinite(k) for k in K):
        return Result(FAIL, name, "camera_info has the default (uncalibrated) intrinsics K = %s" % K, fix)
    if K[2] <= 0 or K[5] <= 0 or K[2] >= info["width"] or K[5] >= info["height"]:
        return Result(FAIL, name, "principal point (%.1f, %.1f) outside the %dx%d image" %
                      (K[2], K[5], info["width"], info["height"]), fix)
    if not info["distortion_model"]:
        return Result(WARN, name, "camera_info has no distortion model", fix)
    return ok(name, "fx %.1f fy %.1f, %s" % (K[0], K[4], info["distortion_model"]))


def counter_growth(first, last, key):
    """Growth of a diagnostics counter between two status dicts (None if either lacks it)."""
    try:
        return int(float(last[key])) - int(float(first[key]))
    except (KeyError, TypeError, ValueError):
        return None


def check_counter(name, statuses, key, what, fix, missing_level=WARN, missing_detail=""):
    """statuses: the driver's diagnostics (dicts of key -> value) in arrival order within the window."""
    if not statuses:
        return Result(missing_level, name, missing_detail or "no diagnostics with '%s' received" % key,
                      "" if missing_level == PASS else "start the driver, or check that it publishes /diagnostics")
    growth = counter_growth(statuses[0], statuses[-1], key)
    if growth is None:
        return Result(WARN, name, "diagnostics lack '%s'" % key, "update the driver")
    if growth > 0:
        return Result(FAIL, name, "%d %s in the window (%s %s -> %s)" % (growth, what, key, statuses[0][key],
                                                                         statuses[-1][key]), fix)
    return ok(name, "no %s (%s = %s)" % (what, key, statuses[-1][key]))


def check_gyro_calibrated(is_calibrated):
    name = "gyro calibrated"
    fix = "hold the rig still and run: rosservice call /imu/calibrate"
    if is_calibrated is None:
        return Result(FAIL, name, "nothing on imu/is_calibrated (is imu_driver running?)", fix)
    if not is_calibrated:
        return Result(FAIL, name, "imu/is_calibrated is false", fix)
    return ok(name, "imu/is_calibrated is true")


def check_tf(found, parent, child, error=""):
    if not found:
        return Result(FAIL, "camera-IMU tf", "no tf %s -> %s%s" % (parent, child, (": " + error) if error else ""),
                      "start the static publisher (launch/include/pipeline.launch includes imu_driver's "
                      "camera_imu_tf.launch) with calibrate_camera_imu's YAML: camera_imu:=/path/camera_imu.yaml")
    return ok("camera-IMU tf", "%s -> %s present" % (parent, child))


def check_layout(n_layout_cones):
    name = "layout loaded"
    if n_layout_cones is None:
        return Result(FAIL, name, "nothing on cone_tracker/cones (the tracker publishes the layout it loaded)",
                      "check cone_tracker's diagnostics for the layout file's error; pass layout:=/path/layout.yaml")
    if n_layout_cones < MIN_CONES:
        return Result(FAIL, name, "the layout has %d cone(s), the tracker needs %d" % (n_layout_cones, MIN_CONES),
                      "use a layout with at least %d cones" % MIN_CONES)
    return ok(name, "%d cones in the layout" % n_layout_cones)


def check_cones_detected(accepted_counts, frames=10):
    """accepted_counts: cone_tracker/detections' accepted_count of the frames in the window, in order.
    "Now" is the median of the last `frames` frames: one frame's miss is not a missing cone."""
    name = "cones detected"
    fix = "point the camera at the cones (at least %d in view, 2-15 m away) and check the exposure" % MIN_CONES
    if not accepted_counts:
        return Result(FAIL, name, "nothing on cone_tracker/detections", "check that cone_tracker runs and gets images")
    last = sorted(accepted_counts[-frames:])
    now = last[len(last) // 2]
    detail = "%d cones (median of the last %d frames)" % (now, len(last))
    if now < MIN_CONES:
        return Result(FAIL, name, detail + ", %d needed" % MIN_CONES, fix)
    return ok(name, detail)


def check_ekf(status):
    """status: the last 'pose_ekf: filter' diagnostics (dict with level, message and the counters)."""
    name = "EKF"
    if status is None:
        return Result(FAIL, name, "no pose_ekf diagnostics", "check that pose_ekf runs (rosnode list)")
    try:
        updates = int(float(status.get("camera updates", 0)))
    except ValueError:
        updates = 0
    if updates == 0 or "waiting" in status.get("message", ""):
        return Result(FAIL, name, "not initialised: %s" % status.get("message", ""),
                      "it starts on the first camera pose: get 3 cones in view")
    # camera_update cones: the frames' cones are fused, their poses mostly not (only the first, and those that reach
    # it before their cones): the cones' NIS per degree of freedom is the filter's consistency. The camera pose is a
    # 6-dof measurement. Either way a consistent filter's NIS per dof averages 1 (chi-square mean / dof).
    cones = status.get("camera update path") == "cones"
    try:
        fused = int(float(status.get("cone frames fused", 0))) if cones else 0
        per_dof = float(status["cone NIS mean per dof"]) if fused else float(status["camera NIS mean"]) / NIS_DOF
    except (KeyError, ValueError):
        return Result(WARN, name, "initialised, %d camera updates; no NIS in its diagnostics" % updates, "")
    if fused:
        detail = "initialised, %d cone frames fused, cone NIS mean per dof %.2f (expected about 1)" % (fused, per_dof)
    else:
        detail = "initialised, %d camera updates, camera NIS mean %.2f (expected about %d)" % (
            updates, per_dof * NIS_DOF, NIS_DOF)
    if not math.isfinite(per_dof) or per_dof > NIS_FAIL_FACTOR:
        return Result(FAIL, name, detail, "the camera noise is underestimated or a calibration is off: check the "
                      "camera and camera-IMU calibrations, then cone_tracker's sigma_px")
    if per_dof < NIS_LOW_FACTOR or per_dof > NIS_HIGH_FACTOR:
        return Result(WARN, name, detail, "tune cone_tracker's sigma_px (NIS low: noise overestimated; high: "
                      "underestimated)")
    return ok(name, detail)


def check_clock(name, offsets_s, limit_s=MAX_CLOCK_OFFSET_S):
    """offsets_s: host clock at arrival minus the header stamp, per message. The smallest is the clock
    offset plus the shortest transport delay: a load spike cannot push it up, an offset clock can."""
    fix = ("the stamps do not follow this host's clock: sync the clocks (chronyc tracking), and check the "
           "driver's time stamping")
    if not offsets_s:
        return Result(FAIL, name, "no stamps received", "nothing to compare: see the rate check above")
    best = min(offsets_s, key=abs)
    detail = "stamp %+.1f ms from the host clock (closest of %d)" % (-best * 1e3, len(offsets_s))
    if abs(best) > limit_s:
        return Result(FAIL, name, detail + ", limit %.0f ms" % (limit_s * 1e3), fix)
    return ok(name, detail)


def check_master(ros_ip, master_host, reachable, error="", local_addresses=()):
    """ros_ip: $ROS_IP (None if unset); reachable: whether a TCP connection from ROS_IP to the master worked."""
    name = "master reachable"
    if not reachable:
        return Result(FAIL, name, "cannot reach the master at %s from %s: %s" % (master_host, ros_ip or "this host",
                                                                              error),
                      "check ROS_MASTER_URI and that ROS_IP is this machine's address on the rig's network")
    if not ros_ip:
        return Result(WARN, name, "master %s reachable; ROS_IP is not set" % master_host,
                      "export ROS_IP=<this machine's address on the rig network> (README: Rig and base station)")
    if local_addresses and ros_ip not in local_addresses:
        return Result(FAIL, name, "ROS_IP %s is not an address of this machine (%s)" % (ros_ip,
                                                                                      ", ".join(local_addresses)),
                      "export ROS_IP=<one of this machine's addresses>")
    return ok(name, "master %s reachable from ROS_IP %s" % (master_host, ros_ip))


def is_local_address(host):
    """True for loopback, RFC 1918 private, link-local (v4 and v6) and IPv6 unique-local addresses."""
    try:
        ip = ipaddress.ip_address(host.strip("[]"))
    except ValueError:
        return None  # a host name: not decidable without resolving it
    # Explicit ranges: Python's is_private also counts documentation and reserved blocks.
    private = ("10.0.0.0/8", "172.16.0.0/12", "192.168.0.0/16") if ip.version == 4 else ("fc00::/7",)
    return ip.is_loopback or ip.is_link_local or any(ip in ipaddress.ip_network(n) for n in private)


def format_line(r):
    line = "%-4s %-22s %s" % (r.level, r.name, r.detail)
    return line + ("  -> fix: " + r.fix if r.fix and r.level != PASS else "")


def exit_code(results):
    return 1 if any(r.level == FAIL for r in results) else 0
