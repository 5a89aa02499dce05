#include "cone_tracker/testing/large_layout.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "cone_tracker/testing/vision_frames.h"

namespace cone_tracker {
namespace testing {

std::vector<ConeModel> LargeLayout(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-1.0, 1.0);
  const double heights[] = {0.30, 0.46, 0.71, 0.91};
  const int cols = int(std::ceil(std::sqrt(double(n))));
  std::vector<ConeModel> cones;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    ConeModel c;
    c.base_m = Eigen::Vector3d(3.5 * (i % cols) + jitter(rng), 3.5 * (i / cols) + jitter(rng), 0.0);
    c.height_m = heights[rng() % 4];
    centroid += c.base_m / n;
    cones.push_back(c);
  }
  for (ConeModel& c : cones) c.base_m -= centroid;
  return cones;
}

rig_sim::Scene LargeLayoutScene(const std::vector<ConeModel>& cones) {
  rig_sim::Scene scene;
  for (size_t i = 0; i < cones.size(); ++i)
    scene.cones.push_back(rig_model::MakeCone(cones[i].base_m, cones[i].height_m,
                                              i % 2 ? rig_model::ConeStyle::kPlain : rig_model::ConeStyle::kRoad));
  return scene;
}

CameraModel LargeLayoutCamera() {
  CameraModel cam;
  cam.width_px = 1024, cam.height_px = 768;
  cam.fx_px = cam.fy_px = 512.0 / std::tan(M_PI / 6.0);
  cam.cx_px = 511.5, cam.cy_px = 383.5;
  return cam;
}

SyntheticView RandomView(const std::vector<ConeModel>& cones, const CameraModel& cam, int min_in_view, int max_in_view,
                         double noise_px, std::mt19937* rng) {
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (int attempt = 0; attempt < 100000; ++attempt) {
    const ConeModel& aim = cones[size_t(rng->operator()() % cones.size())];
    const double az = 2.0 * M_PI * uni(*rng), dist = 2.5 + 4.5 * uni(*rng);
    SyntheticView v;
    v.eye_m = aim.base_m + Eigen::Vector3d(dist * std::cos(az), dist * std::sin(az), 1.3 + 0.5 * uni(*rng));
    v.target_m = aim.base_m + Eigen::Vector3d(1.5 * (uni(*rng) - 0.5), 1.5 * (uni(*rng) - 0.5), 0.3);
    const rig_sim::TruePose pose = LookAt(v.eye_m, v.target_m);
    const Eigen::Matrix3d R = pose.R_cones_camera.transpose();
    std::vector<std::pair<double, int>> seen;  // (peak u, cone)
    std::vector<ConeDetection> dets(cones.size());
    for (size_t c = 0; c < cones.size(); ++c) {
      const auto pts = CorrectedModelPoints(cones[c], v.eye_m);
      Eigen::Vector2d uv[3];
      bool inside = true;
      for (int i = 0; i < 3 && inside; ++i) {
        const Eigen::Vector3d p = R * (pts[size_t(i)] - v.eye_m);
        uv[i] = Eigen::Vector2d(cam.fx_px * p.x() / p.z() + cam.cx_px, cam.fy_px * p.y() / p.z() + cam.cy_px);
        inside = p.z() > 0.5 && uv[i].x() > 5 && uv[i].y() > 5 && uv[i].x() < cam.width_px - 5 &&
                 uv[i].y() < cam.height_px - 5;
      }
      if (!inside || (uv[0] - uv[2]).norm() < 20.0) continue;
      ConeDetection& d = dets[c];
      d.peak_undist_px = uv[0], d.mid_undist_px = uv[1], d.base_undist_px = uv[2];
      for (Eigen::Vector2d* q : {&d.peak_undist_px, &d.mid_undist_px, &d.base_undist_px})
        *q += noise_px * Eigen::Vector2d(noise(*rng), noise(*rng));
      d.peak_px = d.peak_undist_px, d.mid_px = d.mid_undist_px, d.base_px = d.base_undist_px;
      seen.emplace_back(d.peak_undist_px.x(), int(c));
    }
    if (int(seen.size()) < min_in_view || int(seen.size()) > max_in_view) continue;
    std::sort(seen.begin(), seen.end());
    for (const auto& [u, c] : seen) v.detections.push_back(dets[size_t(c)]), v.cone_of_detection.push_back(c);
    return v;
  }
  throw std::runtime_error("RandomView: no view with the requested number of cones");
}

}  // namespace testing
}  // namespace cone_tracker
