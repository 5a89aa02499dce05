// The two-cone start: a pose from two cones and gravity, when no prediction exists and only two cones are in
// view (cone_tracker's README, "Two cones and gravity"). ROS-free.
//
// Two cones alone give six points on two parallel lines: their pose is weakly conditioned in the rotation
// about the line joining the cones. The accelerometer's direction of "up" in the camera fixes that rotation
// (and its twin, the tilt along the line), so the pair, the gravity and the layout give the whole pose:
//   1. for every ordered pair of layout cones (a, b) taken as the two detections, a start from gravity: each
//      cone's base from its peak and base rays and its known height along "up", the heading from the line
//      joining the two bases;
//   2. the image-only solution from that start (SolveAssignment, with the surface corrections of 3.1.4);
//   3. gravity fused into it as a measurement of the tilt (one Kalman update of the pose and its
//      covariance), the total chi-square that of the image residuals plus gravity's innovation, 2N - 6 + 2 =
//      8 dof, gated like 6.4.1;
//   4. a hypothesis that puts another layout cone in plain view (rig_model::InPlainView) where no blob,
//      accepted or refused, lies is dropped; of the rest, one with a rival within ambiguity_margin of its
//      chi-square makes the frame ambiguous (no pose), as the cold start of large layouts does, unless the
//      heading prior decides.
#pragma once

#include <deque>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "cone_tracker/vision/cone_pose.h"

namespace cone_tracker {

// Every ordered pair of layout cones is a hypothesis (n (n - 1), each a few refinements): up to this many cones.
// Larger layouts start from three cones (their pair-hypothesis search, cone_pose_search.h).
constexpr size_t kTwoConeMaxLayout = 8;

struct GravityPrior {
  Eigen::Vector3d up_camera = Eigen::Vector3d::UnitZ();  // unit "up" in the camera frame
  double sigma_rad = 0.05;                               // its error, 1-sigma about each horizontal axis
};

// detections: the frame's accepted cones (exactly two; otherwise, or with a layout of more than kTwoConeMaxLayout
// cones, refused as too few cones); rejected: the blobs the
// segmentation refused (a layout cone over one of them is not missed). The result's chi2_dof is 8.
ConePoseResult EstimateTwoConePose(const std::vector<ConeDetection>& detections,
                                   const std::vector<ConeDetection>& rejected, const std::vector<ConeModel>& cones,
                                   const CameraModel& camera, const ConePoseConfig& config,
                                   const GravityPrior& gravity);

// The accelerometer's mean direction over a short window around an image stamp: "up" in the camera (at rest
// the specific force is -g, i.e. it points up). Handheld motion adds its own acceleration: on rig_sim's
// look_away runs a 0.1 s window was about 1 deg off the true up in the median and 5 deg at the 95th percentile,
// more in fast swings (README, "Two cones and gravity").
class GravityWindow {
 public:
  explicit GravityWindow(double keep_s = 1.0) : keep_s_(keep_s) {}
  // f_camera: the specific force in the camera frame (m/s^2). A stamp before the newest clears the window
  // (time jumped back). Non-finite samples are refused (false).
  bool Add(double stamp_s, const Eigen::Vector3d& f_camera);
  // Mean of the samples within half_window_s of stamp_s, normalised; none when there is no sample there or
  // the mean's norm is outside [0.5, 1.5] g (a shock, free fall, or not an accelerometer).
  std::optional<Eigen::Vector3d> UpAt(double stamp_s, double half_window_s, double gravity_m_s2 = 9.80665) const;
  void Clear() { samples_.clear(); }

 private:
  double keep_s_;
  std::deque<std::pair<double, Eigen::Vector3d>> samples_;
};

}  // namespace cone_tracker
