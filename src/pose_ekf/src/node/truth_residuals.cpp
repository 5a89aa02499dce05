#include "pose_ekf/node/truth_residuals.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <ostream>
#include <sstream>

#include "pose_ekf/core/process_model.h"
#include "pose_math/quaternion.h"

namespace pose_ekf {

void TruthResiduals::AddTruth(double stamp_s, const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  if (!std::isfinite(stamp_s) || !p.allFinite() || !q.coeffs().allFinite()) return;
  if (!truth_.empty() && stamp_s <= truth_.back().t) return;
  truth_.push_back({stamp_s, p, q.normalized()});
}

bool TruthResiduals::PoseAt(double stamp_s, StateVector* x, Eigen::Matrix3d* R_cones_camera) const {
  // The samples around the stamp: linear in position, slerp in orientation.
  const auto after =
      std::lower_bound(truth_.begin(), truth_.end(), stamp_s, [](const Sample& s, double t) { return s.t < t; });
  const bool exact = after != truth_.end() && after->t == stamp_s;
  const bool bracketed = after != truth_.end() && after != truth_.begin() && after->t - stamp_s <= kMaxTruthGapS &&
                         stamp_s - (after - 1)->t <= kMaxTruthGapS;
  if (!exact && !bracketed) return false;
  const Sample& b = *after;
  const Sample& a = exact ? b : *(after - 1);
  const double w = b.t > a.t ? (stamp_s - a.t) / (b.t - a.t) : 1.0;
  const Eigen::Quaterniond q = a.q.slerp(w, b.q);
  *x = StateVector::Zero(kBaseStates);
  x->segment<4>(kQ) = pose_math::ThesisFromEigen(q);
  x->segment<3>(kP) = (1.0 - w) * a.p + w * b.p;
  *R_cones_camera = q.toRotationMatrix();
  return true;
}

namespace {

// h(x) of each of the frame's cones (NaN for one not in front of the camera).
std::vector<ConeVector> ProjectAll(const StateVector& x, const ConeFrame& f) {
  std::vector<ConeVector> h(f.cones.size());
  for (size_t i = 0; i < f.cones.size(); ++i)
    if (!ProjectCone(x, f.cones[i].cone, f.K, &h[i], nullptr))
      h[i].setConstant(std::numeric_limits<double>::quiet_NaN());
  return h;
}

}  // namespace

bool TruthResiduals::TruthPixels(const ConeFrame& f, std::vector<ConeVector>* h) const {
  StateVector x;
  Eigen::Matrix3d R;
  if (!PoseAt(f.stamp_s, &x, &R)) return false;
  *h = ProjectAll(x, f);
  return true;
}

bool TruthResiduals::AddFrame(const ConeFrame& f, std::ostream* lines, std::vector<ConeVector>* truth_px) {
  ++frames_;
  StateVector x;
  Eigen::Matrix3d R_cones_camera;
  if (!PoseAt(f.stamp_s, &x, &R_cones_camera)) {
    ++frames_without_truth_;
    return false;
  }
  const std::vector<ConeVector> h = ProjectAll(x, f);
  for (size_t i = 0; i < f.cones.size(); ++i) {
    const ConeObservation& o = f.cones[i];
    if (!h[i].allFinite()) continue;            // not in front of the true camera
    const ConeVector r = ConePixels(o) - h[i];  // peak u v, base u v (kConeMeasuredPoints)
    for (int k = 0; k < kConeDof; ++k) sum_[size_t(k)] += r[k], sum2_[size_t(k)] += r[k] * r[k];
    ++cones_;
    if (lines) {
      const double depth_m = (R_cones_camera.transpose() * (o.cone.base_m - x.segment<3>(kP))).z();
      *lines << std::fixed << std::setprecision(6) << f.stamp_s << ' ' << o.cone_id << ' ' << std::setprecision(3)
             << depth_m << std::setprecision(4) << ' ' << r[0] << ' ' << r[1] << ' ' << r[2] << ' ' << r[3] << '\n';
    }
  }
  if (truth_px) *truth_px = h;
  return true;
}

const char* TruthResiduals::Header() { return "# stamp_s cone_id depth_m peak_du peak_dv base_du base_dv"; }

std::string TruthResiduals::Summary() const {
  std::ostringstream s;
  s << std::fixed << std::setprecision(3) << "residuals against the truth of " << cones_ << " cones in "
    << frames_ - frames_without_truth_ << " frames (" << frames_without_truth_ << " frames without truth)";
  if (cones_ == 0) return s.str();
  static const char* const kNames[4] = {"peak u", "peak v", "base u", "base v"};
  for (size_t k = 0; k < 4; ++k) {
    const double mean = sum_[k] / double(cones_);
    const double sd = std::sqrt(std::max(0.0, sum2_[k] / double(cones_) - mean * mean));
    s << (k == 0 ? ": " : ", ") << kNames[k] << ' ' << std::showpos << mean << std::noshowpos << " sd " << sd;
  }
  s << " px";
  return s.str();
}

}  // namespace pose_ekf
