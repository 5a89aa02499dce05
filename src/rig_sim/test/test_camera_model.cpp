#include <gtest/gtest.h>

#include <cmath>

#include "rig_sim/camera_model.h"

namespace rig_sim {

TEST(CameraModel, PrincipalPointAndPinholeKnownValues) {
  const CameraModel cam{CameraConfig()};
  Eigen::Vector2d uv;
  ASSERT_TRUE(cam.Project(Eigen::Vector3d(0, 0, 2), &uv));
  EXPECT_NEAR(uv.x(), 511.5, 1e-12);
  EXPECT_NEAR(uv.y(), 383.5, 1e-12);
  CameraConfig c;
  c.k1 = c.k2 = c.p1 = c.p2 = c.k3 = 0.0;
  const CameraModel pinhole(c);
  ASSERT_TRUE(pinhole.Project(Eigen::Vector3d(0.5, -0.25, 2.0), &uv));
  EXPECT_NEAR(uv.x(), 511.5 + 770.0 * 0.25, 1e-9);
  EXPECT_NEAR(uv.y(), 383.5 - 776.0 * 0.125, 1e-9);
}

TEST(CameraModel, DistortionMatchesEquation310ByHand) {
  const CameraModel cam{CameraConfig()};
  const CameraConfig& c = cam.config();
  const double x = 0.3, y = -0.2, r2 = x * x + y * y;
  const double radial = 1 + c.k1 * r2 + c.k2 * r2 * r2;
  const Eigen::Vector2d d = cam.Distort(Eigen::Vector2d(x, y));
  EXPECT_NEAR(d.x(), x * radial + 2 * c.p1 * x * y + c.p2 * (r2 + 2 * x * x), 1e-15);
  EXPECT_NEAR(d.y(), y * radial + c.p1 * (r2 + 2 * y * y) + 2 * c.p2 * x * y, 1e-15);
  EXPECT_LT(d.norm(), Eigen::Vector2d(x, y).norm());  // barrel
}

TEST(CameraModel, UndistortInvertsDistortOverTheWholeImage) {
  const CameraModel cam{CameraConfig()};
  double worst_px = 0.0;
  for (int v = 0; v < 768; v += 31)
    for (int u = 0; u < 1024; u += 29) {
      const Eigen::Vector3d ray = cam.PixelRay(u, v);
      Eigen::Vector2d uv;
      ASSERT_TRUE(cam.Project(3.0 * ray, &uv));
      worst_px = std::max(worst_px, (uv - Eigen::Vector2d(u, v)).norm());
    }
  EXPECT_LT(worst_px, 1e-8);
}

TEST(CameraModel, BehindTheCameraIsRejected) {
  const CameraModel cam{CameraConfig()};
  Eigen::Vector2d uv;
  EXPECT_FALSE(cam.Project(Eigen::Vector3d(0, 0, -1), &uv));
  EXPECT_FALSE(cam.Project(Eigen::Vector3d(0, 0, std::nan("")), &uv));
}

TEST(CameraModel, ScaledKeepsTheFieldOfViewAndValidateNamesTheField) {
  const CameraConfig c = CameraConfig().Scaled(0.25);
  EXPECT_EQ(c.width_px, 256);
  EXPECT_EQ(c.height_px, 192);
  EXPECT_NEAR(c.cu_px, 127.5, 1e-12);
  EXPECT_NEAR(c.fu_px, 192.5, 1e-12);
  EXPECT_EQ(c.Validate(), "");
  CameraConfig bad;
  bad.fu_px = -1;
  EXPECT_NE(bad.Validate().find("fu_px"), std::string::npos);
  bad = CameraConfig();
  bad.k2 = std::nan("");
  EXPECT_NE(bad.Validate().find("distortion"), std::string::npos);
}

}  // namespace rig_sim
