// PnP for 3D-2D matches with outliers, for pnp_solve's cases. Not in the thesis: there the matches come
// from the cone association (3.1.6), whose gates keep wrong ones out, so SolvePnp (pnp.h) assumes none.
// The consensus set comes from OpenCV's solvePnPRansac (Fischler & Bolles 1981, on the P3P of 4.2.1
// over four-point samples); SolvePnp then solves on those inliers, from that pose, with its method and
// covariance. The inliers are counted again at SolvePnp's pose and, if they changed, solved once more.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "cone_tracker/pose/pnp.h"

namespace cone_tracker {

struct RansacOptions {
  double threshold_px = 3.0;  // an inlier's reprojection error (raw pixels) is below this
  double confidence = 0.999;  // OpenCV stops sampling once a better consensus is this unlikely
  int max_iterations = 10000;
};

struct RansacPnpResult {
  PnpResult pnp;             // SolvePnp on the inliers (its residuals are theirs, in order)
  std::vector<char> inlier;  // per input point
  int num_inliers = 0;
};

// Fails (pnp.ok false, pnp.error set) on fewer than 4 points, a bad option, no consensus of at least
// SolvePnp's method's minimum, or SolvePnp failing on the inliers.
RansacPnpResult SolvePnpRansac(const CameraModel& camera, const std::vector<Eigen::Vector3d>& model_points,
                               const std::vector<Eigen::Vector2d>& image_points_px, const PnpOptions& options,
                               const RansacOptions& ransac);

}  // namespace cone_tracker
