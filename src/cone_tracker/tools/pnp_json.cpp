// JSON-lines conversion for pnp_solve.
#include "pnp_json.h"

#include <chrono>
#include <optional>

namespace cone_tracker {
namespace {

using nlohmann::json;

nlohmann::ordered_json Solve(const json& in, PnpOptions options, const RansacOptions* ransac) {
  CameraModel camera;
  const auto K = in.at("K").get<std::vector<double>>();
  if (K.size() != 4) throw std::invalid_argument("K must be [fx, fy, cx, cy]");
  camera.fx_px = K[0], camera.fy_px = K[1], camera.cx_px = K[2], camera.cy_px = K[3];
  if (in.contains("dist")) camera.distortion = in.at("dist").get<std::vector<double>>();
  std::vector<Eigen::Vector3d> model;
  for (const auto& p : in.at("model")) {
    const auto v = p.get<std::vector<double>>();
    if (v.size() != 3) throw std::invalid_argument("model points must be [X, Y, Z]");
    model.emplace_back(v[0], v[1], v[2]);
  }
  std::vector<Eigen::Vector2d> image;
  for (const auto& p : in.at("image")) {
    const auto v = p.get<std::vector<double>>();
    if (v.size() != 2) throw std::invalid_argument("image points must be [u, v]");
    image.emplace_back(v[0], v[1]);
  }
  if (in.contains("sigma_px")) options.sigma_px = in.at("sigma_px").get<double>();
  std::optional<pose_math::Pose> init;
  if (in.contains("init")) {
    const auto q = in.at("init").at("q").get<std::vector<double>>();
    const auto t = in.at("init").at("t").get<std::vector<double>>();
    if (q.size() != 4 || t.size() != 3) throw std::invalid_argument("init needs q[4] and t[3]");
    init = pose_math::Pose{pose_math::Quat(q[0], q[1], q[2], q[3]).normalized(), Eigen::Vector3d(t[0], t[1], t[2])};
  }
  if (init && ransac) throw std::invalid_argument("init is not used with RANSAC: give one or the other");
  const auto start = std::chrono::steady_clock::now();
  RansacPnpResult robust;
  if (ransac) robust = SolvePnpRansac(camera, model, image, options, *ransac);
  const PnpResult r = ransac ? robust.pnp : SolvePnp(camera, model, image, options, init);
  const double time_us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
  nlohmann::ordered_json out;
  out["ok"] = r.ok;
  if (!r.ok) {
    out["error"] = r.error;
    out["time_us"] = time_us;
    return out;
  }
  const pose_math::Quat& q = r.T_camera_model.q;
  out["q"] = {q[0], q[1], q[2], q[3]};
  out["t"] = {r.T_camera_model.t.x(), r.T_camera_model.t.y(), r.T_camera_model.t.z()};
  // ROS order is (x y z rx ry rz); the tool's is rotation vector then translation.
  Eigen::Matrix<double, 6, 6> P = Eigen::Matrix<double, 6, 6>::Zero();
  P.topRightCorner<3, 3>().setIdentity();
  P.bottomLeftCorner<3, 3>().setIdentity();
  const Eigen::Matrix<double, 6, 6> cov = P * r.cov6_ros * P.transpose();
  std::vector<double> cov6;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) cov6.push_back(cov(i, j));
  out["cov6"] = cov6;
  out["iterations"] = r.iterations;
  out["reproj_rms_px"] = r.reproj_rms_px;
  if (ransac) {
    out["inliers"] = robust.num_inliers;
    std::vector<int> outliers;
    for (size_t i = 0; i < robust.inlier.size(); ++i)
      if (!robust.inlier[i]) outliers.push_back(int(i));
    out["outliers"] = outliers;
  }
  out["time_us"] = time_us;
  return out;
}

}  // namespace

nlohmann::ordered_json SolveJsonCase(const json& in, PnpOptions options, const RansacOptions* ransac) {
  try {
    return Solve(in, options, ransac);
  } catch (const std::exception& e) {
    nlohmann::ordered_json out;
    out["ok"] = false;
    out["error"] = std::string("bad input: ") + e.what();
    return out;
  }
}

}  // namespace cone_tracker
