// What pose_math does for the pipeline, on the thesis's rig: the first-order
// uncertainty of a single-frame camera pose from three cones (5.6.2 with the
// quaternion constraint 5.74), carried from chapter 4's T_camera_cones to the
// EKF's T_cones_camera and into ROS's 6×6 PoseWithCovariance form and back.
// Prints a Markdown table; `make demo` saves it in out/.
#include <cmath>
#include <cstdio>
#include <vector>

#include "pose_math/covariance.h"
#include "pose_math/pose.h"
#include "pose_math/rotation.h"

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kFu = 770.0, kFv = 776.0, kU0 = 512.0, kV0 = 384.0;  // the thesis's camera (3.1.1)
constexpr double kSigmaPx = 1.0;

// Peak, middle and base of three 0.71 m (28") road cones, 1.5 m apart, in `cones`.
std::vector<Eigen::Vector3d> ConePoints() {
  std::vector<Eigen::Vector3d> pts;
  const double side = 1.5, height = 0.71, r = side / std::sqrt(3.0);
  for (int i = 0; i < 3; ++i) {
    const double a = 2.0 * kPi * i / 3.0;
    const Eigen::Vector3d base(r * std::cos(a), r * std::sin(a), 0.0);
    for (double z : {height, 0.5 * height, 0.0}) pts.push_back(base + Eigen::Vector3d(0, 0, z));
  }
  return pts;
}

// Camera `distance_m` from the cones' centroid, 20° above the ground, looking at it.
pose_math::Pose CameraInCones(double distance_m, double azimuth_rad) {
  const double elev = 20.0 * kPi / 180.0;
  const Eigen::Vector3d eye = distance_m * Eigen::Vector3d(std::cos(elev) * std::cos(azimuth_rad),
                                                           std::cos(elev) * std::sin(azimuth_rad), std::sin(elev));
  const Eigen::Vector3d z = (Eigen::Vector3d(0, 0, 0.3) - eye).normalized();  // optical axis
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();   // right
  Eigen::Matrix3d R_cones_camera;
  R_cones_camera << x, z.cross(x), z;  // y = z × x points down
  return {pose_math::QuatFromRotation(R_cones_camera), eye};
}

// Stacked image residuals u, v of (5.56) (5.57) (noise-free) as a function of Θ of T_camera_cones.
Eigen::VectorXd Project(const pose_math::Vector7d& theta, const std::vector<Eigen::Vector3d>& pts) {
  const pose_math::Pose T = pose_math::FromVector(theta);
  Eigen::VectorXd uv(2 * pts.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    const Eigen::Vector3d p = pose_math::Transform(T, pts[i]);
    uv[2 * i] = kFu * p.x() / p.z() + kU0;
    uv[2 * i + 1] = kFv * p.y() / p.z() + kV0;
  }
  return uv;
}

// A of (5.59) by central differences (the tracker's library has the analytic one).
Eigen::MatrixXd ImageJacobian(const pose_math::Pose& T, const std::vector<Eigen::Vector3d>& pts) {
  const pose_math::Vector7d theta = pose_math::ToVector(T);
  Eigen::MatrixXd A(2 * pts.size(), 7);
  const double h = 1e-7;
  for (int k = 0; k < 7; ++k) {
    pose_math::Vector7d tp = theta, tm = theta;
    tp[k] += h;
    tm[k] -= h;
    A.col(k) = (Project(tp, pts) - Project(tm, pts)) / (2 * h);
  }
  return A;
}

}  // namespace

int main() {
  const std::vector<Eigen::Vector3d> pts = ConePoints();
  const Eigen::MatrixXd noise = kSigmaPx * kSigmaPx * Eigen::MatrixXd::Identity(2 * pts.size(), 2 * pts.size());
  std::printf("# pose_math demo: single-frame camera pose uncertainty from three cones\n\n");
  std::printf("Three 28\" cones 1.5 m apart, peak/middle/base points, fu = %.0f, fv = %.0f, sigma = %.1f px.\n", kFu,
              kFv, kSigmaPx);
  std::printf("Covariance by 5.52 with the quaternion constraint 5.74, inverted to the camera in `cones` and\n");
  std::printf("converted to ROS's 6x6 (x y z rx ry rz); 'round trip' is |7x7 -> 6x6 -> 7x7 - 7x7| / |7x7|.\n\n");
  std::printf("| distance (m) | sigma x, y, z (mm) | sigma rx, ry, rz (deg) | round trip |\n");
  std::printf("|---|---|---|---|\n");
  for (double d : {1.5, 2.0, 3.0, 4.0}) {
    const pose_math::Pose T_cones_camera = CameraInCones(d, 0.4);
    const pose_math::Pose T_camera_cones = pose_math::Invert(T_cones_camera);
    pose_math::PoseWithCovariance chapter4{
        T_camera_cones,
        pose_math::ConstrainedPoseCovariance(T_camera_cones.q, ImageJacobian(T_camera_cones, pts), noise)};
    const pose_math::PoseWithCovariance ekf = pose_math::Invert(chapter4);
    const pose_math::Matrix6d ros = pose_math::CovarianceRosFromThesis(ekf.pose.q, ekf.cov);
    const pose_math::Matrix7d back = pose_math::CovarianceThesisFromRos(ekf.pose.q, ros);
    const Eigen::VectorXd s = ros.diagonal().cwiseSqrt();
    std::printf("| %.1f | %.2f, %.2f, %.2f | %.3f, %.3f, %.3f | %.1e |\n", d, 1e3 * s[0], 1e3 * s[1], 1e3 * s[2],
                s[3] * 180 / kPi, s[4] * 180 / kPi, s[5] * 180 / kPi, (back - ekf.cov).norm() / ekf.cov.norm());
  }
  return 0;
}
