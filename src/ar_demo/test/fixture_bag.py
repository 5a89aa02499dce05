"""Writes a small bag shaped like what launch/demo.launch records, with known errors.

The camera circles the cones at 3 m looking at the origin. The EKF's pose is the truth moved by
OFFSET_M and turned by OFFSET_DEG about z (in `cones`), with a fixed covariance; the tracker's pose
is the truth, except in an outage where it publishes nothing; one gate counter in /diagnostics
grows by GATE_REJECTIONS; the overlay frames are small grey images.
"""
import numpy as np
import rosbag
import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import PoseStamped, PoseWithCovarianceStamped
from scipy.spatial.transform import Rotation
from sensor_msgs.msg import CameraInfo, Image

T0 = 100.0
DURATION_S = 3.0
OUTAGE_S = (1.0, 1.6)
OFFSET_M = np.array([0.010, 0.0, 0.0])
OFFSET_DEG = 0.5
SIGMA_POS_M = 0.005
SIGMA_ROT_RAD = 0.004
GATE_REJECTIONS = 2
FX = 192.0  # 256x192, the sample bags' scaled thesis camera (roughly)
CONES = ((0.5, 0.0, 0.7), (-0.25, 0.43, 0.7), (-0.25, -0.43, 0.7))  # x, y, height: always in view


def truth_pose(t):
    """T_cones_camera at time t: on a 3 m circle at 1.2 m height, optical axis at the origin."""
    a = 0.3 * t
    p = np.array([3.0 * np.cos(a), 3.0 * np.sin(a), 1.2])
    z = -p / np.linalg.norm(p)
    x = np.cross(z, [0.0, 0.0, 1.0])
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    return Rotation.from_matrix(np.column_stack([x, y, z])), p


def _fill(pose, R, p):
    pose.position.x, pose.position.y, pose.position.z = p
    q = R.as_quat()
    pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w = q


def camera_info(stamp):
    info = CameraInfo()
    info.header.stamp, info.header.frame_id = stamp, "camera_optical"
    info.width, info.height = 256, 192
    info.distortion_model = "plumb_bob"
    info.D = [-0.05, 0.01, 0.0, 0.0, 0.0]
    info.K = [FX, 0.0, 128.0, 0.0, FX, 96.0, 0.0, 0.0, 1.0]
    info.P = [FX, 0.0, 128.0, 0.0, 0.0, FX, 96.0, 0.0, 0.0, 0.0, 1.0, 0.0]
    return info


def cone_markers(stamp):
    """rig_sim/cones as rig_sim draws it: per cone a TRIANGLE_LIST of (ring point, ring point, apex)."""
    from geometry_msgs.msg import Point
    from visualization_msgs.msg import Marker, MarkerArray
    out = MarkerArray()
    for i, (x, y, h) in enumerate(CONES):
        m = Marker()
        m.header.stamp, m.header.frame_id, m.ns, m.id = stamp, "cones", "cones", i
        for k in range(12):
            for j in (k, k + 1):
                a = 2 * np.pi * j / 12
                m.points.append(Point(x + 0.15 * np.cos(a), y + 0.15 * np.sin(a), 0.0))
            m.points.append(Point(x, y, h))
        out.markers.append(m)
    return out


def write(path, ekf_offset=True):
    offset_R = Rotation.from_euler("z", OFFSET_DEG if ekf_offset else 0.0, degrees=True)
    offset_p = OFFSET_M if ekf_offset else np.zeros(3)
    with rosbag.Bag(path, "w") as bag:
        bag.write("rig_sim/cones", cone_markers(rospy.Time.from_sec(T0)), rospy.Time.from_sec(T0))
        for k in range(int(DURATION_S * 300) + 1):  # truth at 300 Hz
            t = k / 300.0
            stamp = rospy.Time.from_sec(T0 + t)
            R, p = truth_pose(t)
            msg = PoseStamped()
            msg.header.stamp, msg.header.frame_id = stamp, "cones"
            _fill(msg.pose, R, p)
            bag.write("rig_sim/ground_truth", msg, stamp)
            if k % 3 == 0:  # EKF at 100 Hz
                ekf = PoseWithCovarianceStamped()
                ekf.header = msg.header
                _fill(ekf.pose.pose, offset_R * R, p + offset_p)
                ekf.pose.covariance = list(np.diag([SIGMA_POS_M ** 2] * 3 + [SIGMA_ROT_RAD ** 2] * 3).ravel())
                bag.write("pose_ekf/pose", ekf, stamp)
            if k % 10 == 0:  # camera rate: camera_info, overlay frame, tracker pose
                bag.write("camera/camera_info", camera_info(stamp), stamp)
                img = Image()
                img.header.stamp, img.header.frame_id = stamp, "camera_optical"
                img.height, img.width, img.encoding, img.step = 48, 64, "rgb8", 64 * 3
                img.data = bytes(np.full((48, 64, 3), 40 + k % 200, np.uint8).tobytes())
                bag.write("ar_overlay/image", img, stamp)
                if not OUTAGE_S[0] < t < OUTAGE_S[1]:
                    tracker = PoseWithCovarianceStamped()
                    tracker.header = msg.header
                    _fill(tracker.pose.pose, R, p)
                    bag.write("cone_tracker/pose", tracker, stamp)
            if k % 150 == 0:  # diagnostics at 2 Hz; the gate counter steps at 2.0 s
                diag = DiagnosticArray()
                diag.header.stamp = stamp
                count = GATE_REJECTIONS if t >= 2.0 else 0
                diag.status = [DiagnosticStatus(name="cone_tracker: pose", values=[
                    KeyValue(key="chi-square gate rejections", value=str(count)),
                    KeyValue(key="frames", value=str(k // 10))])]
                bag.write("/diagnostics", diag, stamp)
    return path
