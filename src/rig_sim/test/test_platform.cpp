// The overlay test platform (7.2): parsed from its layout, dots where
// DotCentres says, blue on a white board, and bad entries refused.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <Eigen/Geometry>

#include "rig_sim/renderer.h"
#include "rig_sim/scene.h"
#include "test_util.h"

namespace rig_sim {
namespace {

// Camera at eye looking at target, optical frame (z forward, y down).
TruePose CameraLookingAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  TruePose pose;
  pose.R_cones_camera << x, z.cross(x), z;
  pose.p_camera_in_cones_m = eye;
  return pose;
}

TEST(Platform, LayoutParsesAndDotsAreOnTheTopFace) {
  Scene s;
  std::string err;
  ASSERT_TRUE(LoadSceneYaml(LayoutsDir() + "/platform.yaml", &s, &err)) << err;
  ASSERT_EQ(s.platforms.size(), 1u);
  const PlatformSpec& p = s.platforms[0];
  EXPECT_EQ(p.rows, 5);
  EXPECT_EQ(p.cols, 5);
  const std::vector<Eigen::Vector3d> dots = p.DotCentres();
  ASSERT_EQ(dots.size(), 25u);
  EXPECT_TRUE(dots[0].isApprox(Eigen::Vector3d(-0.2, -0.2, 0.05), 1e-12));
  EXPECT_TRUE(dots[24].isApprox(Eigen::Vector3d(0.2, 0.2, 0.05), 1e-12));
  EXPECT_NEAR((dots[1] - dots[0]).norm(), 0.1, 1e-12);

  PlatformSpec turned = p;  // yaw turns the grid about the board's centre
  turned.center_m = Eigen::Vector2d(1.0, 2.0);
  turned.yaw_rad = M_PI / 2;
  EXPECT_TRUE(turned.DotCentres()[0].isApprox(Eigen::Vector3d(1.2, 1.8, 0.05), 1e-12));
}

TEST(Platform, BadPlatformsAreRefusedWithTheEntry) {
  Scene s;
  std::string err;
  const std::string cones = "equilateral: {side_m: 1.5, height_m: 0.71}\n";
  EXPECT_FALSE(ParseSceneYaml(cones + "platforms:\n  - {sx_m: -1}\n", &s, &err));
  EXPECT_NE(err.find("platforms[0]"), std::string::npos) << err;
  EXPECT_FALSE(ParseSceneYaml(cones + "platforms:\n  - {rows: 9, spacing_m: 0.1}\n", &s, &err));
  EXPECT_NE(err.find("does not fit"), std::string::npos) << err;
  EXPECT_FALSE(ParseSceneYaml(cones + "platforms:\n  - {dot_radius_m: 0.06, spacing_m: 0.1}\n", &s, &err));
  EXPECT_NE(err.find("dot_radius_m"), std::string::npos) << err;
}

TEST(Platform, RenderedDotsAreBlueWhereProjectedAndTheBoardIsWhiteBetween) {
  Scene scene;
  std::string err;
  ASSERT_TRUE(LoadSceneYaml(LayoutsDir() + "/platform.yaml", &scene, &err)) << err;
  const Scenario sc = TestScenario("handheld", 1, 2, 0.5);
  const rig_model::CameraModel& camera = sc.camera.model;
  RenderConfig rc = sc.render;
  rc.noise_sigma_dn = 0;
  const Renderer r(camera, scene, rc);
  const TruePose pose = CameraLookingAt({0.9, -1.1, 1.3}, {0.0, 0.0, 0.05});
  std::vector<uint8_t> rgb(static_cast<size_t>(r.width()) * r.height() * 3);
  std::vector<int16_t> labels(static_cast<size_t>(r.width()) * r.height());
  r.Render(pose, 1.0, 0, rgb.data(), labels.data());
  const auto pixel = [&](const Eigen::Vector3d& p_in_cones, int* index) {
    Eigen::Vector2d uv;
    const Eigen::Vector3d p_c = pose.R_cones_camera.transpose() * (p_in_cones - pose.p_camera_in_cones_m);
    if (!camera.Project(p_c, &uv)) return false;
    const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
    if (u < 0 || v < 0 || u >= r.width() || v >= r.height()) return false;
    *index = v * r.width() + u;
    return true;
  };
  int blue = 0, white = 0, seen = 0;
  for (const Eigen::Vector3d& d : scene.platforms[0].DotCentres()) {
    int i = 0;
    ASSERT_TRUE(pixel(d, &i)) << "dot off screen: " << d.transpose();
    ++seen;
    const uint8_t* c = &rgb[3 * static_cast<size_t>(i)];
    EXPECT_GE(labels[static_cast<size_t>(i)], kLabelFirstDistractor);
    blue += c[2] > c[0] + 60 && c[2] > c[1] + 40;
    // Half a spacing along x and y: the white board between four dots.
    ASSERT_TRUE(pixel(d + Eigen::Vector3d(0.05, 0.05, 0.0), &i));
    const uint8_t* w = &rgb[3 * static_cast<size_t>(i)];
    white += w[0] > 150 && w[1] > 150 && w[2] > 140;
  }
  EXPECT_EQ(seen, 25);
  EXPECT_EQ(blue, 25);
  EXPECT_EQ(white, 25);
}

}  // namespace
}  // namespace rig_sim
