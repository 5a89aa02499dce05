#include "rig_sim/random_layout.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

namespace rig_sim {

std::string RandomLayoutConfig::Validate() const {
  std::ostringstream err;
  if (cones < rig_model::LayoutLimits::kMinCones || cones > rig_model::LayoutLimits::kMaxCones)
    err << "cones: " << cones << " is not in " << rig_model::LayoutLimits::kMinCones << ".."
        << rig_model::LayoutLimits::kMaxCones;
  else if (!(min_spacing_m > 0.0 && min_spacing_m < 10.0))
    err << "min_spacing_m: " << min_spacing_m << " is not in (0, 10) m";
  else if (!(side_m == 0.0 || (side_m > 0.0 && side_m < 200.0)))
    err << "side_m: " << side_m << " is not 0 (automatic) or in (0, 200) m";
  return err.str();
}

Scene RandomLayout(const RandomLayoutConfig& config) {
  const std::string err = config.Validate();
  if (!err.empty()) throw std::invalid_argument("RandomLayout: " + err);
  const double kHeights[4] = {0.30, 0.46, 0.71, 0.91};
  std::mt19937_64 rng(config.seed);
  // Two heights for the unique cones 0 and 1, the other two for the rest.
  int order[4] = {0, 1, 2, 3};
  std::shuffle(order, order + 4, rng);
  const double side = config.side_m > 0.0 ? config.side_m : std::max(3.0, 1.3 * std::sqrt(config.cones));
  std::uniform_real_distribution<double> pos(-0.5 * side, 0.5 * side);
  Scene scene;
  for (int attempt = 0; static_cast<int>(scene.cones.size()) < config.cones; ++attempt) {
    if (attempt > 100000)
      throw std::invalid_argument("RandomLayout: " + std::to_string(config.cones) + " cones do not fit " +
                                  std::to_string(config.min_spacing_m) + " m apart in a square of " +
                                  std::to_string(side) + " m");
    const Eigen::Vector3d base(pos(rng), pos(rng), 0.0);
    bool free = true;
    for (const ConeSpec& c : scene.cones) free = free && (c.base_m - base).norm() >= config.min_spacing_m;
    if (!free) continue;
    const size_t i = scene.cones.size();
    const double h = kHeights[i < 2 ? order[i] : order[2 + std::uniform_int_distribution<int>(0, 1)(rng)]];
    scene.cones.push_back(MakeCone(base, h, h > 0.6 ? ConeStyle::kRoad : ConeStyle::kPlain));
  }
  const Eigen::Vector3d centroid = scene.ConeCentroid();
  for (ConeSpec& c : scene.cones) c.base_m -= Eigen::Vector3d(centroid.x(), centroid.y(), 0.0);
  return scene;
}

}  // namespace rig_sim
