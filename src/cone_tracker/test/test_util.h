#pragma once
#include <gtest/gtest.h>

#include <random>

#include "cone_tracker/pose/algorithms.h"
#include "pose_math/pose.h"
#include "synthetic.h"

namespace cone_tracker {

inline Correspondences ToCorrespondences(const sim::Case& k, const std::vector<Eigen::Vector2d>& image) {
  Correspondences c;
  c.fx_px = k.camera.fx_px;
  c.fy_px = k.camera.fy_px;
  c.model.resize(3, k.model.size());
  c.normalized.resize(2, k.model.size());
  for (size_t i = 0; i < k.model.size(); ++i) {
    c.model.col(i) = k.model[i];
    c.normalized.col(i) << (image[i].x() - k.camera.cx_px) / k.camera.fx_px,
        (image[i].y() - k.camera.cy_px) / k.camera.fy_px;
  }
  return c;
}
inline Correspondences ToCorrespondences(const sim::Case& k) { return ToCorrespondences(k, k.image); }

// Rotation error (rad) and translation error (m) both below tol.
inline ::testing::AssertionResult PoseNear(const pose_math::Pose& a, const pose_math::Pose& b, double tol) {
  const double r = pose_math::RotationErrorRad(a, b), t = pose_math::TranslationError(a, b);
  if (r <= tol && t <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "rotation error " << r << " rad, translation error " << t << " m (tol " << tol
                                       << ")";
}

// A handful of noise-free random clouds and cone layouts.
inline std::vector<sim::Case> NoiseFreeCases(unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<sim::Case> cases;
  for (int k = 0; k < 4; ++k) cases.push_back(sim::RandomCloud(rng, k % 2 ? 10 : 25));
  for (int k = 0; k < 3; ++k) cases.push_back(sim::ConeLayout(rng));
  return cases;
}

}  // namespace cone_tracker
