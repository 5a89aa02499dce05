// ekf_replay --truth-residuals: how far the tracker's cone points lie from where the filter's own measurement
// model (ProjectCone) puts them at the TRUE camera pose, on bags that carry one (rig_sim/ground_truth, the
// camera_optical pose in cones). The residual z - h(x_true) of each cone's peak and base is the tracker's error
// as the filter sees it: its mean is a bias that R does not describe, and a slowly varying one reads to the
// filter as rotation (README, "What still bounds"). Bags without the truth topic give no residuals.
#pragma once

#include <array>
#include <iosfwd>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "pose_ekf/core/cone_measurement.h"
#include "pose_ekf/core/process_model.h"

namespace pose_ekf {

class TruthResiduals {
 public:
  // Truth samples further than this from a frame's stamp leave the frame out (rig_sim writes 300 Hz).
  static constexpr double kMaxTruthGapS = 0.01;

  // In stamp order (a bag's order); out-of-order samples are ignored.
  void AddTruth(double stamp_s, const Eigen::Vector3d& p_cones_camera, const Eigen::Quaterniond& q_cones_camera);
  // One line per cone to *lines (when not null): stamp, cone id, the depth of its base centre, and the
  // residuals (px) of the peak (u v) and the base (u v); *truth_px (when not null) gets TruthPixels's result.
  // False when no truth brackets the stamp.
  bool AddFrame(const ConeFrame& f, std::ostream* lines, std::vector<ConeVector>* truth_px = nullptr);
  // The pixels h(x_true) of the frame's cones (peak u v, base u v; NaN for a cone not in front of the true
  // camera): what a tracker without error would have measured. False when no truth brackets the stamp.
  bool TruthPixels(const ConeFrame& f, std::vector<ConeVector>* h) const;
  static const char* Header();
  // "residuals against the truth of N cones in M frames (K frames without truth): peak u <mean> sd <sd>, peak v ...,
  // base u ..., base v ... px".
  std::string Summary() const;

 private:
  struct Sample {
    double t;
    Eigen::Vector3d p;
    Eigen::Quaterniond q;
  };
  bool PoseAt(double stamp_s, StateVector* x, Eigen::Matrix3d* R_cones_camera) const;

  std::vector<Sample> truth_;
  // Sums per coordinate (peak u, peak v, base u, base v) of the residual and its square.
  std::array<double, 4> sum_{}, sum2_{};
  size_t cones_ = 0, frames_ = 0, frames_without_truth_ = 0;
};

}  // namespace pose_ekf
