#include "synthetic.h"

#include <opencv2/calib3d.hpp>

#include "pose_math/rotation.h"

namespace cone_tracker {
namespace sim {

CameraModel ThesisCamera() {
  CameraModel c;
  c.fx_px = 770.0;
  c.fy_px = 776.0;
  c.cx_px = 512.0;
  c.cy_px = 384.0;
  return c;
}

pose_math::Pose RandomRotationPose(std::mt19937& rng, const Eigen::Vector3d& t) {
  std::normal_distribution<double> g(0.0, 1.0);
  pose_math::Pose T;
  T.q = pose_math::CanonicalSign(pose_math::Quat(g(rng), g(rng), g(rng), g(rng)).normalized());
  T.t = t;
  return T;
}

bool Project(const CameraModel& camera, const pose_math::Pose& T, const std::vector<Eigen::Vector3d>& model,
             std::vector<Eigen::Vector2d>* image) {
  image->clear();
  std::vector<cv::Point3d> object;
  for (const Eigen::Vector3d& m : model) {
    const Eigen::Vector3d p = pose_math::Transform(T, m);
    if (p.z() <= 0.0) return false;
    image->emplace_back(camera.fx_px * p.x() / p.z() + camera.cx_px, camera.fy_px * p.y() / p.z() + camera.cy_px);
    object.emplace_back(m.x(), m.y(), m.z());
  }
  if (!camera.HasDistortion()) return true;
  const Eigen::Vector3d r = pose_math::RotationVectorFromQuat(T.q);
  const cv::Vec3d rvec(r.x(), r.y(), r.z()), tvec(T.t.x(), T.t.y(), T.t.z());
  const cv::Matx33d K(camera.fx_px, 0, camera.cx_px, 0, camera.fy_px, camera.cy_px, 0, 0, 1);
  std::vector<cv::Point2d> projected;
  cv::projectPoints(object, rvec, tvec, K, camera.distortion, projected);
  for (size_t i = 0; i < projected.size(); ++i) (*image)[i] = Eigen::Vector2d(projected[i].x, projected[i].y);
  return true;
}

std::vector<Eigen::Vector2d> AddNoise(std::mt19937& rng, const std::vector<Eigen::Vector2d>& image, double sigma_px) {
  std::normal_distribution<double> g(0.0, sigma_px);
  std::vector<Eigen::Vector2d> out = image;
  for (Eigen::Vector2d& p : out) p += Eigen::Vector2d(g(rng), g(rng));
  return out;
}

Case RandomCloud(std::mt19937& rng, int points) {
  std::uniform_real_distribution<double> u(-0.5 * kOneFootM, 0.5 * kOneFootM);
  Case c;
  c.camera = ThesisCamera();
  c.T_camera_model = RandomRotationPose(rng, Eigen::Vector3d(u(rng), u(rng), kFiveFeetM));
  for (int i = 0; i < points; ++i) c.model.emplace_back(u(rng), u(rng), u(rng));
  Project(c.camera, c.T_camera_model, c.model, &c.image);
  return c;
}

Case ConeLayout(std::mt19937& rng) {
  constexpr double kHeightM = 0.7, kRadiusM = 1.0, kPi = 3.14159265358979323846;
  Case c;
  c.camera = ThesisCamera();
  for (int k = 0; k < 3; ++k) {
    const double a = 2.0 * kPi * k / 3.0;
    const Eigen::Vector3d base(kRadiusM * std::cos(a), kRadiusM * std::sin(a), 0.0);  // x toward cone 1
    for (const double h : {kHeightM, 0.5 * kHeightM, 0.0}) c.model.push_back(base + Eigen::Vector3d(0, 0, h));
  }
  std::uniform_real_distribution<double> azimuth(-kPi, kPi), elevation(10.0 * kPi / 180, 40.0 * kPi / 180),
      distance(3.0, 5.0), jitter(-0.2, 0.2);
  for (;;) {
    // Camera centre on a sphere around the layout, looking at a point near
    // its middle, image x axis level (z down in the image is world down).
    const double az = azimuth(rng), el = elevation(rng), d = distance(rng);
    const Eigen::Vector3d centre =
        d * Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    const Eigen::Vector3d target(jitter(rng), jitter(rng), 0.35 + jitter(rng));
    const Eigen::Vector3d z = (target - centre).normalized();
    const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
    const Eigen::Vector3d y = z.cross(x);
    Eigen::Matrix3d R_model_camera;
    R_model_camera << x, y, z;
    pose_math::Pose T_model_camera;
    T_model_camera.q = pose_math::QuatFromRotation(R_model_camera);
    T_model_camera.t = centre;
    c.T_camera_model = pose_math::Invert(T_model_camera);
    if (!Project(c.camera, c.T_camera_model, c.model, &c.image)) continue;
    bool inside = true;
    for (const Eigen::Vector2d& p : c.image) inside = inside && p.x() > 0 && p.x() < 1024 && p.y() > 0 && p.y() < 768;
    if (inside) return c;
  }
}

}  // namespace sim
}  // namespace cone_tracker
