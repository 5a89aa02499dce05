// Layout files written by programs: cone_survey's survey_layout (surveyed positions with each
// cone's 1-sigma per axis as `sigma_m: [sx, sy, sz]`, metres, in the layout's frame) and rig_sim's
// make_layout (random layouts). The layout parser (layout.h) reads `sigma_m` into ConeSpec::sigma_m;
// this collects them, and writes the `cones:` list. ROS-free.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "rig_model/layout.h"

namespace rig_model {

// ConeSpec::sigma_m of each cone of LoadLayoutFile(path), in its order; NaN for a cone without
// `sigma_m` (and for the equilateral cones). Throws FileError as LoadLayoutFile does.
std::vector<Eigen::Vector3d> LoadConeSigmas(const std::string& path);

// The `cones:` list of a layout file, one flow mapping per cone: x_m, y_m, z_m, height_m, style, and
// tau when it is not the default; sigma_m when sigmas_m has an entry for the cone with no NaN.
// ParseLayout reads it back (positions to 0.1 mm).
std::string ConesYaml(const std::vector<ConeSpec>& cones, const std::vector<Eigen::Vector3d>& sigmas_m = {});

}  // namespace rig_model
