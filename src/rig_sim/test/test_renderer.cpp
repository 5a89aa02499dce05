#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "rig_sim/renderer.h"
#include "test_util.h"

namespace rig_sim {
namespace {

struct Frame {
  std::vector<uint8_t> rgb;
  std::vector<int16_t> labels;
};

Frame RenderAt(const Renderer& r, const TruePose& pose, double t, uint64_t index) {
  Frame f;
  f.rgb.resize(static_cast<size_t>(r.width()) * r.height() * 3);
  f.labels.resize(static_cast<size_t>(r.width()) * r.height());
  r.Render(pose, t, index, f.rgb.data(), f.labels.data());
  return f;
}

// Independent check: distance of the ray to the cone axis against the cone's
// radius at that height, in double precision, from CameraModel directly.
// Returns the signed margin in metres (positive inside), sampled along the ray.
double ConeMargin(const ConeSpec& c, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double best = -1e9;
  for (double t = 0.0; t < 20.0; t += 0.0005) {
    const Eigen::Vector3d p = o + t * d;
    if (p.z() < c.base_m.z() || p.z() > c.base_m.z() + c.height_m) continue;
    const double radius = c.tau * (c.base_m.z() + c.height_m - p.z());
    best = std::max(best, radius - (p.head<2>() - c.base_m.head<2>()).norm());
  }
  return best;
}

// The handheld scenario's frame at t = 4 s and what drew it, for the geometry tests.
class RendererHandheldFrame : public ::testing::Test {
 protected:
  const Scenario s = TestScenario("handheld", 2, 5, 0.25);
  const Trajectory traj{s.trajectory};
  const rig_model::CameraModel& cam = s.camera.model;
  const Renderer r{cam, s.scene, s.render};
  const TruePose pose = traj.At(4.0);
  const Frame f = RenderAt(r, pose, 4.0, 0);
};

TEST_F(RendererHandheldFrame, HitPointsOfConePixelsReprojectWithinOneHundredthPixel) {
  int cone_pixels = 0;
  double worst = 0.0;
  for (int v = 0; v < r.height(); ++v)
    for (int u = 0; u < r.width(); ++u) {
      if (f.labels[v * r.width() + u] < kLabelFirstCone || f.labels[v * r.width() + u] >= kLabelFirstDistractor)
        continue;
      const RayHit hit = r.TracePixel(pose, u, v);
      ASSERT_EQ(hit.label, f.labels[v * r.width() + u]);
      Eigen::Vector2d uv;
      ASSERT_TRUE(cam.Project(pose.R_cones_camera.transpose() * (hit.p_in_cones_m - pose.p_camera_in_cones_m), &uv));
      worst = std::max(worst, (uv - Eigen::Vector2d(u, v)).norm());
      ++cone_pixels;
    }
  EXPECT_GT(cone_pixels, 200);
  EXPECT_LT(worst, 0.01);
}

TEST_F(RendererHandheldFrame, ConeModelPointsLandOnTheirConeAndSilhouettesAreExact) {
  // Model points (3.12) moved onto the visible surface (3.18): their distorted
  // projections fall on pixels the renderer labels as that cone.
  for (size_t i = 0; i < s.scene.cones.size(); ++i) {
    const ConeSpec& c = s.scene.cones[i];
    Eigen::Vector3d toward = pose.p_camera_in_cones_m - c.base_m;
    toward.z() = 0;
    toward.normalize();
    const Eigen::Vector3d base_on_surface = c.base_m + 0.9 * c.radius_m() * toward + Eigen::Vector3d(0, 0, 0.01);
    const Eigen::Vector3d mid_on_surface = 0.5 * (c.peak_m() + base_on_surface);
    for (const Eigen::Vector3d& p : {mid_on_surface, base_on_surface}) {
      Eigen::Vector2d uv;
      ASSERT_TRUE(cam.Project(pose.R_cones_camera.transpose() * (p - pose.p_camera_in_cones_m), &uv));
      const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
      ASSERT_TRUE(u >= 0 && v >= 0 && u < r.width() && v < r.height());
      EXPECT_EQ(f.labels[v * r.width() + u], kLabelFirstCone + static_cast<int>(i)) << "cone " << i;
    }
  }
  // Silhouettes: every pixel whose ray clearly passes through cone 0 is labelled
  // cone 0 and every pixel clearly missing all cones is not a cone.
  const ConeSpec& c0 = s.scene.cones[0];
  int inside = 0, mismatches = 0;
  for (int v = 0; v < r.height(); v += 2)
    for (int u = 0; u < r.width(); u += 2) {
      const Eigen::Vector3d d = pose.R_cones_camera * cam.PixelRay(u, v);
      const double margin = ConeMargin(c0, pose.p_camera_in_cones_m, d);
      const int16_t label = f.labels[v * r.width() + u];
      if (margin > 0.003) {
        ++inside;
        if (label != kLabelFirstCone && label < kLabelFirstCone) ++mismatches;  // may be hidden by another cone only
      } else if (margin < -0.003 && label == kLabelFirstCone) {
        ++mismatches;
      }
    }
  EXPECT_GT(inside, 20);
  EXPECT_EQ(mismatches, 0);
}

TEST(Renderer, ConesAreOrangeCollarsWhiteAndTheImageIsNotFlat) {
  const Scenario s = TestScenario("handheld", 2, 5, 0.5);
  const Trajectory traj(s.trajectory);
  RenderConfig rc = s.render;
  rc.noise_sigma_dn = 0;
  const Renderer r(s.camera.model, s.scene, rc);
  const TruePose pose = traj.At(4.0);
  const Frame f = RenderAt(r, pose, 4.0, 0);
  int orange = 0, white = 0, cone = 0;
  double min_r = 255, max_r = 0;
  for (size_t i = 0; i < f.labels.size(); ++i) {
    if (f.labels[i] < kLabelFirstCone || f.labels[i] >= kLabelFirstDistractor) continue;
    const uint8_t* p = &f.rgb[3 * i];
    ++cone;
    if (p[0] > 120 && p[0] > p[1] + 60 && p[1] > p[2])
      ++orange, min_r = std::min<double>(min_r, p[0]), max_r = std::max<double>(max_r, p[0]);
    if (p[0] > 170 && p[1] > 170 && p[2] > 170) ++white;
  }
  EXPECT_GT(orange, cone / 2);
  EXPECT_GT(white, cone / 10);     // road cones carry white collars
  EXPECT_GT(max_r - min_r, 30.0);  // shaded, not flat
}

TEST(Renderer, DeterministicPerSeedAndFrameAndIndependentOfThreads) {
  const Scenario s = TestScenario("clutter", 2, 5, 0.125);
  const Trajectory traj(s.trajectory);
  RenderConfig one = s.render, two = s.render;
  one.threads = 1;
  two.threads = 2;
  const Renderer a(s.camera.model, s.scene, one), b(s.camera.model, s.scene, two);
  const Frame fa = RenderAt(a, traj.At(1.0), 1.0, 3), fb = RenderAt(b, traj.At(1.0), 1.0, 3);
  EXPECT_EQ(fa.rgb, fb.rgb);
  const Frame fc = RenderAt(a, traj.At(1.0), 1.0, 4);  // another frame index: other noise
  EXPECT_NE(fa.rgb, fc.rgb);
  EXPECT_EQ(fa.labels, fc.labels);
}

}  // namespace
}  // namespace rig_sim
