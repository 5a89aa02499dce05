#pragma once
#include <Eigen/Core>
#include <vector>

#include "cone_tracker/pose/pnp.h"

namespace cone_tracker {
// Undistorted normalised points [(u−u0)/fu, (v−v0)/fv] (4.4). False if a result is not finite.
bool NormalizeImagePoints(const CameraModel& camera, const std::vector<Eigen::Vector2d>& image_points_px,
                          Eigen::Matrix2Xd* normalized);
}  // namespace cone_tracker
