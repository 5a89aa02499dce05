// The tightly coupled camera measurement: the image points of ONE cone (cone_tracker/observations,
// cone_tracker/ConeObservation.msg), fused per cone so that one or two visible cones still correct
// the filter, where the single-frame pose (5.24) needs three. No ROS types.
//
// The message carries the cone's peak, mid and base (3.1.5.4); z = the undistorted pixels of the peak
// and the base, 4 rows. The tracker's mid is the image midpoint of those two (its segmenter and its
// DNN detector both set it so), not a measurement of its own: fused as a third independent point it
// counted the peak and base one and a half times, and its model, the projection of the 3-D midpoint,
// lies up to 2.5 px off that image midpoint on rig_sim's cones (perspective), a bias the filter
// believed to 1 px (README, "Status"). The mid is still checked (a malformed message is refused).
// h(x) = the pinhole projection (fx, fy, cx, cy) of the cone's model points
// (rig_model::CorrectedModelPoints: the peak, and the base on the surface facing the camera, (3.18),
// the definition the tracker's pose uses) through the camera pose in the state, T_cones_camera =
// (q, p) (5.18).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "pose_ekf/core/process_model.h"
#include "rig_model/cone_view.h"

namespace rig_model {
struct Layout;
}

namespace pose_ekf {

// Ideal pinhole intrinsics of undistorted pixels (ConeObservations' fx fy cx cy).
struct PinholeIntrinsics {
  double fx_px = 0.0, fy_px = 0.0, cx_px = 0.0, cy_px = 0.0;
};

// A layout cone, as the tracker models it (rig_model::ConeSpec's base, height and tau).
struct ConeGeometry {
  Eigen::Vector3d base_m = Eigen::Vector3d::Zero();  // centre of the base circle in `cones`
  double height_m = 0.71;
  double tau = 1.0 / 7.0;
};
// The layout's cones in file order: index = ConeObservation::cone_id.
std::vector<ConeGeometry> ConeGeometries(const rig_model::Layout& layout);

constexpr int kConePoints = 3;  // peak, mid, base: the message's points (ConeObservation::px)
// The measured ones: the peak and the base (the mid is their image midpoint), in z, h and R.
constexpr std::array<int, 2> kConeMeasuredPoints = {0, 2};
constexpr int kConeDof = 2 * static_cast<int>(kConeMeasuredPoints.size());
using ConeVector = Eigen::Matrix<double, kConeDof, 1>;
using ConeMatrix = Eigen::Matrix<double, kConeDof, kConeDof>;
using ConeJacobian = Eigen::Matrix<double, kConeDof, Eigen::Dynamic, 0, kConeDof, kMaxStates>;

// One associated cone in one image.
struct ConeObservation {
  int cone_id = -1;                             // layout index (for diagnostics; the geometry travels with it)
  ConeGeometry cone;                            // the layout cone it was associated with
  std::array<Eigen::Vector2d, kConePoints> px;  // peak, mid, base (undistorted, u right, v down)
  std::array<Eigen::Matrix2d, kConePoints> cov_px2;
};

// Every associated cone of one image, stamped at exposure like the camera pose.
struct ConeFrame {
  double stamp_s = 0.0;
  PinholeIntrinsics K;
  std::vector<ConeObservation> cones;
  // Every layout cone (index = cone_id), for the lone-cone ambiguity test (EkfConfig::cone_ambiguity_margin);
  // empty: not tested.
  std::vector<ConeGeometry> layout;
  // The image's size (px), for the test's negative information (EkfConfig::cone_miss_cost); 0: unknown.
  double width_px = 0.0, height_px = 0.0;
  // Where the image is orange (undistorted px, cone_tracker/observations' `orange`): a layout cone partly in view
  // where none lies is missed too; empty: unknown, plain view only.
  std::vector<rig_model::ImageBox> orange_px;
};

// "" when the frame can be fused (finite stamp and pixels, fx, fy > 0, symmetric positive definite
// 2x2 covariances), otherwise what is wrong, naming the field (e.g. "cones[1].mid_px is not finite").
std::string CheckConeFrame(const ConeFrame& f);

// Points nearer than this in front of the camera are not projected (the linearisation breaks down).
constexpr double kConeMinDepthM = 0.05;

// h(x) and H = ∂h/∂x (kConeDof × n, non-zero in the q and p columns only) of one cone. The quaternion
// enters through the general rotation of (2.36), like the accelerometer model, so H is exact for
// a non-unit q too; the model points move with p (3.16)-(3.18), which H includes. False when a
// point is not at least kConeMinDepthM in front of the camera.
bool ProjectCone(const StateVector& x, const ConeGeometry& cone, const PinholeIntrinsics& K, ConeVector* h,
                 ConeJacobian* H);

// R: the peak's and the base's 2x2 covariances on the diagonal; z: their pixels.
ConeMatrix ConeCovariance(const ConeObservation& o);
ConeVector ConePixels(const ConeObservation& o);

// The pixels of the last fused cone frame, for EkfConfig::cone_repeat_px: a fixed array, as it is part of the
// filter's state, which the measurement buffer copies at every IMU sample. A frame with more fused cones keeps the
// first kMaxViewCones; a later frame with any of the others then never repeats it.
constexpr int kMaxViewCones = 16;
struct FusedConeView {
  double stamp_s = 0.0;
  int count = 0;  // 0: none since the filter (re-)initialised
  std::array<int, kMaxViewCones> cone_id{};
  std::array<std::array<double, kConeDof>, kMaxViewCones> z{};  // ConePixels (plain doubles: zero-initialised)
};
// Whether f shows only cones of `view`, each measured point (ConePixels) less than max_px from where `view` had it,
// less than max_s after it: the same view again, whose pixel errors are the view's own (README, "Repeated views").
bool RepeatsView(const FusedConeView& view, const ConeFrame& f, double max_px, double max_s);
// `view` := the cones `fused` (indices into f.cones) of f.
void NoteFusedView(const ConeFrame& f, const std::vector<int>& fused, FusedConeView* view);

// What EkfCore::UpdateCones did with one frame.
struct ConeFrameResult {
  int fused = 0;          // cones fused
  int gated = 0;          // cones outside the per-cone chi-square gate
  int joint_dropped = 0;  // cones dropped because the frame's joint NIS failed
  int behind_camera = 0;  // a model point not in front of the predicted camera
  int numerical = 0;      // S not positive definite
  int too_few = 0;        // cones that passed but were fewer than min_cones (re-acquisition): not fused
  int ambiguous = 0;      // a lone cone that another layout cone explains nearly as well: not fused
  bool repeated = false;  // the same view as the last fused frame (EkfConfig::cone_repeat_px): not fused
  double nis = 0.0;       // the fused cones' joint NIS (the sum of the sequential ones)
  double joint_threshold = 0.0;
  double worst_gate_chi2 = 0.0;  // the largest per-cone statistic of the frame
  // The lone-cone ambiguity test (EkfConfig::cone_ambiguity_margin), when it ran: the fit statistic of the
  // cone the tracker named and of the best other layout cone (-1: none could be projected).
  double ambiguity_own_chi2 = 0.0;
  // Rivals are fitted unless ConeFitLowerBound rules them out (`ambiguity_screened` of them, iterated test only):
  // the best fitted one (infinite and -1 when none was fitted).
  double ambiguity_rival_chi2 = 0.0;
  int ambiguity_rival_id = -1;
  int ambiguity_screened = 0;
  // Layout cones the own and the best rival's fitted poses miss (ConesMissedAt; EkfConfig::cone_miss_cost each,
  // included in the two statistics above).
  int ambiguity_own_missed = 0;
  int ambiguity_rival_missed = 0;
  // The orange boxes they leave unexplained (OrangeUnexplainedAt; EkfConfig::cone_unexplained_cost each, included).
  int ambiguity_own_unexplained = 0;
  int ambiguity_rival_unexplained = 0;
};

// The smallest cost J(x) = (x - x0)ᵀ P⁻¹ (x - x0) + (z - h(x))ᵀ R⁻¹ (z - h(x)) with which `cone` explains
// the pixels z: the prior's Mahalanobis distance of the state correction plus the pixel fit, minimised by
// `iterations` Gauss-Newton steps (those of the iterated EKF update, with step halving). 0 iterations: the
// first-order statistic yᵀ S⁻¹ y at x0, which the first step reaches when h is linear. Infinite when the
// cone cannot be projected at x0. x_fit, when given: the state of the returned J (x0 for first order).
double ConeFitCost(const StateVector& x0, const StateMatrix& P, const ConeGeometry& cone, const PinholeIntrinsics& K,
                   const ConeVector& z, const ConeMatrix& R, int iterations, StateVector* x_fit = nullptr);

// How many layout cones, other than `seen`, the state x puts in plain view in the frame's image, or partly in view
// where it has no orange (rig_model::MissedInView; silhouettes from the projected peak and base, tau times their
// distance wide). 0 without an image size.
int ConesMissedAt(const StateVector& x, const ConeFrame& f, const std::vector<int>& seen);

// How many of the frame's orange boxes (ConeFrame::orange_px) the state x puts no layout cone near, nor any of the
// frame's cones as measured (rig_model::UnexplainedOrange): orange left to clutter. 0 without orange boxes.
int OrangeUnexplainedAt(const StateVector& x, const ConeFrame& f);

// A lower bound on ConeFitCost's J(x) at every x, hence on what it returns with iterations > 0: min(t2, the least
// peak pixel term of a pose whose prior term is below t2). So a result equal to t2 proves J ≥ t2 everywhere
// (cone_update.cpp gives the proof). Costs a rotation and a few square roots, against up to 5 Gauss-Newton steps.
double ConeFitLowerBound(const StateVector& x0, const StateMatrix& P, const ConeGeometry& cone,
                         const PinholeIntrinsics& K, const ConeVector& z, const ConeMatrix& R, double t2);

}  // namespace pose_ekf
