// calibrate_camera_imu: the camera–IMU rotation of thesis 3.2.2 from a YAML of
// static poses, written as the YAML that camera_imu_tf.launch publishes as a
// static tf (and that the driver reads for publish_in_camera_frame).
//
// Input (one entry per static pose of the camera calibration):
//   up_in_grid: [0, 0, -1]          # accelerometer-at-rest direction in the grid frame
//   poses:
//     - accel_mean_m_s2: [0.1, -0.2, 9.8]         # from gyro_bias_report.py --segments
//       R_camera_grid_rvec: [0.1, 0.2, 0.3]       # OpenCV calibrateCamera rvec (Rodrigues)
//     - accel_mean_m_s2: [...]
//       q_camera_grid_xyzw: [0, 0, 0, 1]          # or a quaternion
// Usage: calibrate_camera_imu input.yaml output.yaml [parent_frame child_frame]
#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>

#include "imu_driver/core/camera_imu_rotation.h"
#include "pose_math/rotation.h"
#include "rig_model/strict_yaml.h"

namespace {

// The i-th element of a list, a finite number.
double Element(const rig_model::StrictReader& r, const YAML::Node& list, const std::string& field, size_t i) {
  double v = NAN;
  try {
    v = list[i].as<double>();
  } catch (const YAML::Exception&) {
  }
  if (!std::isfinite(v)) r.Fail(list[i], field + "[" + std::to_string(i) + "]", "must be a finite number");
  return v;
}

Eigen::Vector3d Vec3(const rig_model::StrictReader& r, const YAML::Node& map, const std::string& where,
                     const std::string& key) {
  const YAML::Node n = map[key];
  if (!n) r.Fail(map, rig_model::FieldPath(where, key), "is missing");
  if (!n.IsSequence() || n.size() != 3) r.Fail(n, rig_model::FieldPath(where, key), "must be [x, y, z]");
  Eigen::Vector3d v;
  for (size_t i = 0; i < 3; ++i) v(i) = Element(r, n, rig_model::FieldPath(where, key), i);
  return v;
}

Eigen::Matrix3d CameraFromGrid(const rig_model::StrictReader& r, const YAML::Node& pose, const std::string& where) {
  r.CheckKeys(pose, {"accel_mean_m_s2", "R_camera_grid_rvec", "q_camera_grid_xyzw"}, where);
  if (pose["R_camera_grid_rvec"]) {
    const Eigen::Vector3d v = Vec3(r, pose, where, "R_camera_grid_rvec");
    return pose_math::RotationFromAngleAxis({v.norm(), v.norm() > 0 ? v.normalized() : Eigen::Vector3d::UnitX()});
  }
  const YAML::Node q = pose["q_camera_grid_xyzw"];
  if (!q) r.Fail(pose, where, "needs R_camera_grid_rvec or q_camera_grid_xyzw");
  if (!q.IsSequence() || q.size() != 4) r.Fail(q, where + ".q_camera_grid_xyzw", "must be [x, y, z, w]");
  double c[4];
  for (size_t i = 0; i < 4; ++i) c[i] = Element(r, q, where + ".q_camera_grid_xyzw", i);
  const Eigen::Quaterniond quat(c[3], c[0], c[1], c[2]);
  if (!(quat.norm() > 0.5)) r.Fail(q, where + ".q_camera_grid_xyzw", "must be a unit quaternion");
  return quat.normalized().toRotationMatrix();
}

void WriteQuat(std::ostream& out, const char* key, const Eigen::Matrix3d& R) {
  const Eigen::Quaterniond q(R);
  out << "  " << key << ": [" << q.x() << ", " << q.y() << ", " << q.z() << ", " << q.w() << "]\n";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 && argc != 5) {
    std::fprintf(stderr, "usage: calibrate_camera_imu input.yaml output.yaml [parent_frame child_frame]\n");
    return 2;
  }
  const std::string parent = argc == 5 ? argv[3] : "camera_optical";
  const std::string child = argc == 5 ? argv[4] : "imu";
  std::vector<imu_driver::GravityPair> pairs;
  try {
    const rig_model::StrictReader r(argv[1]);
    const YAML::Node in = rig_model::LoadYamlFile(argv[1]);
    r.CheckKeys(in, {"up_in_grid", "poses"}, "");
    const Eigen::Vector3d up_in_grid = in["up_in_grid"] ? Vec3(r, in, "", "up_in_grid") : Eigen::Vector3d(0, 0, -1);
    const YAML::Node poses = in["poses"];
    if (!poses || !poses.IsSequence()) r.Fail(in, "poses", "must be a list of static poses");
    for (size_t i = 0; i < poses.size(); ++i) {
      const std::string where = "poses[" + std::to_string(i) + "]";
      const Eigen::Matrix3d R_camera_grid = CameraFromGrid(r, poses[i], where);
      pairs.push_back(
          imu_driver::MakeGravityPair(Vec3(r, poses[i], where, "accel_mean_m_s2"), R_camera_grid, up_in_grid));
    }
  } catch (const rig_model::FileError& e) {  // names the file, line and field
    std::fprintf(stderr, "calibrate_camera_imu: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "calibrate_camera_imu: %s: %s\n", argv[1], e.what());
    return 1;
  }
  const imu_driver::RotationFit svd = imu_driver::FitRotationSvd(pairs);
  if (!svd.ok) {
    std::fprintf(stderr, "calibrate_camera_imu: %s\n", svd.message.c_str());
    return 1;
  }
  const imu_driver::RotationFit euler = imu_driver::FitRotationEuler(pairs);
  const double disagreement_deg =
      pose_math::AngleAxisFromRotation(svd.R_camera_imu.transpose() * euler.R_camera_imu).angle_rad * 180.0 / M_PI;
  std::ofstream out(argv[2]);
  out << std::setprecision(10);
  out << "# Camera-IMU rotation (thesis 3.2.2) from " << pairs.size() << " static poses, by calibrate_camera_imu.\n"
      << "# The translation is set to zero as in the thesis (coincident origins).\n"
      << "camera_imu:\n"
      << "  parent_frame: " << parent << "\n  child_frame: " << child << "\n"
      << "  translation_m: [0.0, 0.0, 0.0]\n";
  WriteQuat(out, "rotation_xyzw", svd.R_camera_imu);
  out << "  method: svd_of_moment_matrix  # thesis (3.32) (3.33) (3.34)\n"
      << "  rms_residual_deg: " << svd.rms_residual_deg << "\n";
  WriteQuat(out, "euler_minimisation_rotation_xyzw", euler.R_camera_imu);
  out << "  euler_minimisation_rms_residual_deg: " << euler.rms_residual_deg << "  # thesis (3.31)\n"
      << "  svd_vs_euler_deg: " << disagreement_deg << "\n"
      << "  poses: " << pairs.size() << "\n";
  if (!out) {
    std::fprintf(stderr, "calibrate_camera_imu: cannot write %s\n", argv[2]);
    return 1;
  }
  std::printf(
      "R_camera_imu by SVD: rms residual %.4f deg; by Euler minimisation: %.4f deg (%d iterations); "
      "the two differ by %.5f deg\n",
      svd.rms_residual_deg, euler.rms_residual_deg, euler.iterations, disagreement_deg);
  return 0;
}
