// The two-cone start (two_cone_pose.h): two cones, gravity and the layout.
#include "cone_tracker/vision/two_cone_pose.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "cone_tracker/pose/associate.h"
#include "pose_math/covariance.h"
#include "pose_math/pose.h"
#include "pose_math/quaternion.h"
#include "pose_math/rotation.h"
#include "rig_model/cone_view.h"

namespace cone_tracker {
namespace {

constexpr int kTwoConeDof = 2 * 6 - 6 + 2;  // six image points less the pose, plus gravity's two components

// The base of a cone standing along `up`, its peak height_m above: s_p r_p - s_b r_b = height_m up in least
// squares over the ray lengths; none when either lies behind the camera. pinhole: the undistorted pixels' camera.
std::optional<Eigen::Vector3d> BaseOnRays(const ConeDetection& d, double height_m, const CameraModel& pinhole,
                                          const Eigen::Vector3d& up) {
  const Eigen::Vector3d r_base = pinhole.PixelRay(d.base_undist_px.x(), d.base_undist_px.y());
  Eigen::Matrix<double, 3, 2> A;
  A << pinhole.PixelRay(d.peak_undist_px.x(), d.peak_undist_px.y()), -r_base;
  const Eigen::Vector2d s = A.colPivHouseholderQr().solve(height_m * up);
  if (!(s(0) > 0.0 && s(1) > 0.0)) return std::nullopt;
  return s(1) * r_base;
}

// A start with layout cone a at detection 0 and b at detection 1: gravity gives the tilt, the line joining the two
// bases the heading, their mean the position. T_camera_cones.
std::optional<pose_math::Pose> GravityStart(const std::vector<ConeDetection>& dets, const ConeModel& a,
                                            const ConeModel& b, const CameraModel& pinhole, const Eigen::Vector3d& up) {
  const auto base_a = BaseOnRays(dets[0], a.height_m, pinhole, up),
             base_b = BaseOnRays(dets[1], b.height_m, pinhole, up);
  if (!base_a || !base_b) return std::nullopt;
  Eigen::Vector3d across_camera = *base_b - *base_a, across_cones = b.base_m - a.base_m;
  across_camera -= up * up.dot(across_camera);
  across_cones.z() = 0.0;
  if (!(across_camera.norm() > 1e-6 && across_cones.norm() > 1e-6)) return std::nullopt;
  across_camera.normalize(), across_cones.normalize();
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  Eigen::Matrix3d in_camera, in_cones;
  in_camera << across_camera, up.cross(across_camera), up;
  in_cones << across_cones, z.cross(across_cones), z;
  const Eigen::Matrix3d R = in_camera * in_cones.transpose();
  pose_math::Pose T;
  T.q = pose_math::QuatFromRotation(R);
  T.t = 0.5 * (*base_a - R * a.base_m + *base_b - R * b.base_m);
  return T;
}

// Gravity's residual at a pose: "up" measured against R_camera_cones e_z, its two components across the latter.
Eigen::Vector2d GravityResidual(const Eigen::Matrix3d& R_camera_cones, const Eigen::Vector3d& up,
                                Eigen::Matrix<double, 3, 2>* across = nullptr) {
  const Eigen::Vector3d h = R_camera_cones.col(2), e1 = h.unitOrthogonal(), e2 = h.cross(e1);
  Eigen::Matrix<double, 3, 2> B;
  B << e1, e2;
  if (across) *across = B;
  return B.transpose() * (up - h);
}

// Gravity fused into the image-only solution as a measurement of its tilt: h = R_camera_cones e_z, which a left
// rotation perturbation (ROS's, pose_math/covariance.h) moves by -S(h) dtheta. One Kalman update of T_camera_cones
// and its covariance (Joseph form). The residuals are then those at the fused pose (the solution's model points
// and image points), and the returned chi-square is the cost there, image and gravity, not its linearisation:
// an "up" far off (the rig accelerating) cannot pass by pulling the pose along a weak direction.
double FuseGravity(const GravityPrior& g, const std::vector<Eigen::Vector3d>& model_points, const CameraModel& pinhole,
                   double sigma_px, PnpResult* r) {
  const Eigen::Matrix3d R = pose_math::RotationFromQuat(r->T_camera_model.q);
  Eigen::Matrix<double, 3, 2> B;
  const Eigen::Vector2d y = GravityResidual(R, g.up_camera, &B);
  Eigen::Matrix<double, 2, 6> H = Eigen::Matrix<double, 2, 6>::Zero();
  H.rightCols<3>() = -B.transpose() * pose_math::Skew(R.col(2));
  const pose_math::Matrix6d& P = r->cov6_ros;
  const Eigen::Matrix2d noise = g.sigma_rad * g.sigma_rad * Eigen::Matrix2d::Identity();
  const Eigen::Matrix<double, 6, 2> K = P * H.transpose() * (H * P * H.transpose() + noise).inverse();
  const Eigen::Matrix<double, 6, 1> dx = K * y;
  const pose_math::Matrix6d I_KH = pose_math::Matrix6d::Identity() - K * H;
  const pose_math::Matrix6d P_new = I_KH * P * I_KH.transpose() + K * noise * K.transpose();
  const Eigen::Matrix3d R_new = pose_math::RotationFromQuat(pose_math::QuatFromRotationVector(dx.tail<3>())) * R;
  const Eigen::Vector3d t_new = r->T_camera_model.t + dx.head<3>();
  double chi2 = GravityResidual(R_new, g.up_camera).squaredNorm() / (g.sigma_rad * g.sigma_rad), sum2 = 0.0;
  for (size_t i = 0; i < model_points.size() && i < r->residuals_px.size(); ++i) {
    const Eigen::Vector3d before = R * model_points[i] + r->T_camera_model.t, after = R_new * model_points[i] + t_new;
    Eigen::Vector2d uv_after, uv_before;
    pinhole.Project(after, &uv_after), pinhole.Project(before, &uv_before);  // in front: the solver checked
    r->residuals_px[i] += uv_after - uv_before;
    chi2 += r->residuals_px[i].squaredNorm() / (sigma_px * sigma_px);
    sum2 += r->residuals_px[i].squaredNorm();
  }
  r->reproj_rms_px = std::sqrt(sum2 / double(std::max<size_t>(1, r->residuals_px.size())));  // as SolvePnp: per point
  r->T_camera_model.q = pose_math::QuatFromRotation(R_new);
  r->T_camera_model.t = t_new;
  r->cov6_ros = P_new;
  r->cov7 = pose_math::CovarianceThesisFromRos(r->T_camera_model.q, P_new);
  return chi2;
}

// Layout cones other than a and b that the pose puts in plain view with no blob over them, accepted or refused (a
// refused blob is a cone the gates turned down, not a miss): rig_model::MissedInView, the association's rule, in plain
// view only.
int Misses(const pose_math::Pose& T_camera_cones, int a, int b, const std::vector<ConeModel>& cones,
           const CameraModel& cam, const std::vector<ConeDetection>& rejected) {
  const auto silhouettes =
      LayoutSilhouettes(LayoutSeenFrom(cones), cones.size(), pose_math::RotationFromQuat(T_camera_cones.q),
                        pose_math::Invert(T_camera_cones).t, cam, AssociationConfig().min_depth_m);
  std::vector<bool> seen(cones.size(), false);
  seen[size_t(a)] = seen[size_t(b)] = true;
  for (size_t k = 0; k < cones.size(); ++k)
    for (const ConeDetection& d : rejected) {
      const Blob& o = d.blob;
      const rig_model::ImageBox blob{double(o.bbox_x), double(o.bbox_y), double(o.bbox_x + o.bbox_w),
                                     double(o.bbox_y + o.bbox_h)};
      seen[k] = seen[k] || (silhouettes[k] && blob.Overlaps(silhouettes[k]->Box()));
    }
  return rig_model::MissedInView(silhouettes, seen, {}, cam.width_px, cam.height_px);
}

}  // namespace

ConePoseResult EstimateTwoConePose(const std::vector<ConeDetection>& dets, const std::vector<ConeDetection>& rejected,
                                   const std::vector<ConeModel>& cones, const CameraModel& cam,
                                   const ConePoseConfig& cfg, const GravityPrior& gravity) {
  ConePoseResult out;
  out.cone_of_detection.assign(dets.size(), -1);
  out.chi2_dof = kTwoConeDof;
  out.chi2_threshold = Chi2Threshold(kTwoConeDof, cfg.chi2_probability);
  if (dets.size() != 2 || cones.size() < 2 || cones.size() > kTwoConeMaxLayout) {
    out.rejected_by = kPoseTooFewCones;
    out.error = "the two-cone start takes exactly two cones and a layout of up to " +
                std::to_string(kTwoConeMaxLayout) + " cones";
    return out;
  }
  GravityPrior g = gravity;
  if (!(g.up_camera.allFinite() && g.up_camera.norm() > 0.0 && g.sigma_rad > 0.0)) {
    out.rejected_by = kPoseSolverFailed;
    out.error = "the two-cone start has no usable gravity";
    return out;
  }
  g.up_camera.normalize();
  CameraModel pinhole = cam;  // the detections' points are undistorted already (3.1.2)
  pinhole.distortion.clear();
  struct Hypothesis {
    std::vector<int> a;
    PnpResult pnp;
    double chi2;
  };
  std::vector<Hypothesis> passed;
  int solved = 0, missing = 0;
  double best_refused = INFINITY;
  for (int a = 0; a < int(cones.size()); ++a) {
    for (int b = 0; b < int(cones.size()); ++b) {
      if (a == b) continue;
      const auto start = GravityStart(dets, cones[size_t(a)], cones[size_t(b)], pinhole, g.up_camera);
      if (!start) continue;
      Hypothesis h{{a, b}, SolveAssignment(dets, cones, {a, b}, cam, cfg, start), INFINITY};
      if (!h.pnp.ok) continue;
      ++solved;
      // The model points the solution fitted: its eye's surface points (3.1.4), peak, mid and base per cone.
      const Eigen::Vector3d eye = pose_math::Invert(h.pnp.T_camera_model).t;
      std::vector<Eigen::Vector3d> model;
      for (int c : h.a)
        for (const Eigen::Vector3d& p : CorrectedModelPoints(cones[size_t(c)], eye)) model.push_back(p);
      h.chi2 = FuseGravity(g, model, pinhole, cfg.sigma_px, &h.pnp);
      if (!(h.chi2 <= out.chi2_threshold)) {
        best_refused = std::min(best_refused, h.chi2);
      } else if (Misses(h.pnp.T_camera_model, a, b, cones, cam, rejected) > 0) {
        ++missing;
      } else {
        passed.push_back(std::move(h));
      }
    }
  }
  if (passed.empty()) {
    out.rejected_by = solved == 0 ? kPoseSolverFailed : kPoseChi2;
    out.chi2 = best_refused;
    out.error = "two cones and gravity: no pair of layout cones fits (" + std::to_string(solved) + " solved, " +
                std::to_string(missing) + " would leave another cone unseen in plain view)";
    return out;
  }
  const auto heading = [](const Hypothesis& h) {
    const Eigen::Vector3d eye = pose_math::Invert(h.pnp.T_camera_model).t;
    return std::atan2(eye.y(), eye.x());
  };
  std::sort(passed.begin(), passed.end(), [](const Hypothesis& x, const Hypothesis& y) { return x.chi2 < y.chi2; });
  size_t best = 0;
  if (passed.size() > 1 && passed[1].chi2 < passed[0].chi2 + cfg.ambiguity_margin) {
    if (std::isfinite(cfg.initial_heading_rad)) {  // the heading prior picks among the near-ties
      const auto off = [&](const Hypothesis& h) {
        return std::abs(std::remainder(heading(h) - cfg.initial_heading_rad, 2.0 * M_PI));
      };
      for (size_t k = 1; k < passed.size() && passed[k].chi2 < passed[0].chi2 + cfg.ambiguity_margin; ++k)
        if (off(passed[k]) < off(passed[best])) best = k;
    } else {
      out.rejected_by = kPoseAmbiguous;
      out.rival_chi2 = passed[1].chi2, out.rival_cone_of_detection = passed[1].a;
      out.chi2 = passed[0].chi2;
      out.error = "two cones and gravity: cones " + std::to_string(passed[0].a[0]) + "," +
                  std::to_string(passed[0].a[1]) + " and " + std::to_string(passed[1].a[0]) + "," +
                  std::to_string(passed[1].a[1]) + " fit alike (chi2 " + std::to_string(passed[0].chi2) + ", " +
                  std::to_string(passed[1].chi2) + ")";
      return out;
    }
  }
  const size_t rival = best == 0 ? 1 : 0;
  if (passed.size() > 1) out.rival_chi2 = passed[rival].chi2, out.rival_cone_of_detection = passed[rival].a;
  out.pnp = passed[best].pnp;
  out.cone_of_detection = passed[best].a;
  out.chi2 = passed[best].chi2;
  out.ok = true;
  return out;
}

bool GravityWindow::Add(double stamp_s, const Eigen::Vector3d& f_camera) {
  if (!std::isfinite(stamp_s) || !f_camera.allFinite()) return false;
  if (!samples_.empty() && stamp_s < samples_.back().first) samples_.clear();  // time jumped back
  samples_.emplace_back(stamp_s, f_camera);
  while (samples_.size() > 1 && stamp_s - samples_.front().first > keep_s_) samples_.pop_front();
  return true;
}

std::optional<Eigen::Vector3d> GravityWindow::UpAt(double stamp_s, double half_window_s, double gravity_m_s2) const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int n = 0;
  for (const auto& [t, f] : samples_)
    if (std::abs(t - stamp_s) <= half_window_s) sum += f, ++n;
  if (n == 0) return std::nullopt;
  const Eigen::Vector3d mean = sum / double(n);
  if (!(mean.norm() >= 0.5 * gravity_m_s2 && mean.norm() <= 1.5 * gravity_m_s2)) return std::nullopt;
  return mean.normalized();
}

}  // namespace cone_tracker
