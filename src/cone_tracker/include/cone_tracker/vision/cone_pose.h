// From cone detections to a pose (3.1.4, 3.1.6, 6.4): model point correction,
// correspondence against a predicted pose (or a search over assignments with
// the linear algorithms when there is none; for large layouts a pair-hypothesis
// search, cone_pose_search.h), the single-frame pose through
// SolvePnp's `best`, and the outlier gates. ROS-free.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "cone_tracker/pose/associate.h"
#include "cone_tracker/pose/pnp.h"
#include "cone_tracker/vision/segmenter.h"
#include "rig_model/layout.h"

namespace cone_tracker {

struct ConeModel {
  Eigen::Vector3d base_m = Eigen::Vector3d::Zero();  // centre of the base circle in `cones`
  double height_m = 0.71;
  double tau = 1.0 / 7.0;                          // radius / height (3.1.4)
  std::vector<std::pair<double, double>> collars;  // white collars, (from, to) fractions of the height (rig_model)
};

// The cones of a layout (rig_model's, or rig_sim's scene), in file order (the equilateral cones first).
std::vector<ConeModel> ConeModels(const rig_model::Layout& layout);
// The collars every cone of the layout has alike (as fractions of its height), for reading a cut cone by them
// (collar_ruler.h); empty when the cones differ or have none.
std::vector<std::pair<double, double>> CommonCollars(const std::vector<ConeModel>& cones);

// Peak, mid and base model points (3.12) moved to the cone's surface on the
// side facing the centre of projection (3.1.4): the silhouette's mid and base
// points lie on the front of the cone, radius tau * (height above) off its axis.
std::array<Eigen::Vector3d, 3> CorrectedModelPoints(const ConeModel& cone, const Eigen::Vector3d& p_camera_in_cones_m);
// The layout's CorrectedModelPoints for any eye: the model AssociateCones fits. It refers to `cones`,
// which must outlive it.
ModelPointsAt LayoutSeenFrom(const std::vector<ConeModel>& cones);

// True when some rotation about z maps the layout onto itself with the cones
// permuted (the equilateral layout's 120 degrees): identical cones cannot tell
// those poses apart without a prediction or a heading prior.
bool LayoutHasRotationalSymmetry(const std::vector<ConeModel>& cones);

struct ConePoseConfig {
  double sigma_px = 1.0;                  // image noise of the peak/mid/base points (PnpOptions::sigma_px)
  double max_assignment_px = 30.0;        // 3.1.6: a cone farther than this from its prediction is not matched
  double chi2_probability = 0.999;        // 6.4.1: residual gate at this probability
  double max_translation_change_m = 0.5;  // 6.4.2: against the prediction
  double max_rotation_change_deg = 30.0;  // 6.4.2
  // Without a prediction: the camera's heading around the layout (atan2 of its
  // position's y, x in `cones`), to pick among symmetric solutions. NaN: none.
  double initial_heading_rad = NAN;
  // Large layouts without a prediction: a rival assignment that passes the chi-square gate and
  // whose chi2 is within this of the best's makes the frame ambiguous (no pose). Chi-square units,
  // like the association's association_margin.
  double ambiguity_margin = 9.0;
  std::string Validate() const;
  // 6.4.2: a camera pose within max_translation_change_m and max_rotation_change_deg of the prediction.
  bool WithinMotionGate(double translation_change_m, double rotation_change_deg) const {
    return translation_change_m <= max_translation_change_m && rotation_change_deg <= max_rotation_change_deg;
  }
};

enum PoseGateBits : uint32_t {
  kPoseTooFewCones = 1u << 0,  // fewer than 3 cones matched
  kPoseSolverFailed = 1u << 1,
  kPoseChi2 = 1u << 2,    // 6.4.1
  kPoseMotion = 1u << 3,  // 6.4.2
  // Large layouts without a prediction: another assignment of the same detections to other cones
  // also passed the 6.4.1 gate, its chi2 within ambiguity_margin of the best's (two self-consistent
  // poses; the frame cannot tell which is right).
  kPoseAmbiguous = 1u << 4,
};

struct ConePoseResult {
  bool ok = false;
  uint32_t rejected_by = 0;
  std::string error;
  std::vector<int> cone_of_detection;  // model cone index per detection, -1 unmatched
  PnpResult pnp;                       // T_camera_model = T_camera_cones with its covariance
  double chi2 = 0.0, chi2_threshold = 0.0;
  int chi2_dof = 0;  // 2N - 6 over the N matched points
  // The best rival assignment's chi2 (the pair-hypothesis search only; infinite: none passed 6.4.1).
  double rival_chi2 = INFINITY;
  std::vector<int> rival_cone_of_detection;
  // 6.4.2 against the prediction, set when there was one and the solver succeeded.
  bool motion_checked = false;
  double translation_change_m = 0.0, rotation_change_deg = 0.0;
};

ConePoseResult EstimateConePose(const std::vector<ConeDetection>& detections, const std::vector<ConeModel>& cones,
                                const CameraModel& camera, const ConePoseConfig& config,
                                const std::optional<pose_math::Pose>& predicted_T_camera_cones);

// The pieces EstimateConePose is made of, for the two-cone start (two_cone_pose.h).
// The single-frame pose of one assignment (model cone per detection, -1 none) from a start pose (none: the
// linear algorithms), the surface points and the image of the mid point corrected from the solution until
// the eye settles (3.1.4).
PnpResult SolveAssignment(const std::vector<ConeDetection>& detections, const std::vector<ConeModel>& cones,
                          const std::vector<int>& cone_of_detection, const CameraModel& camera,
                          const ConePoseConfig& config, const std::optional<pose_math::Pose>& initial_T_camera_cones);
// 6.4.1: chi2 of a solution's image residuals (6.2) at sigma_px, and the gate (6.3) at a probability.
double ResidualChi2(const PnpResult& r, double sigma_px);
double Chi2Threshold(int dof, double probability);

}  // namespace cone_tracker
