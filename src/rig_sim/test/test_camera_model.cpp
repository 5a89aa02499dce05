#include <gtest/gtest.h>

#include <cmath>

#include "rig_sim/camera_model.h"

// The lens math (3.10, 3.11, Jacobians) is rig_model's and tested there; here the simulated
// camera's own settings.
namespace rig_sim {

TEST(CameraConfig, DefaultIsTheThesisRig) {
  const CameraConfig c;
  EXPECT_TRUE(c.model == rig_model::ThesisCamera());
  EXPECT_EQ(c.Validate(), "");
  Eigen::Vector2d uv;
  ASSERT_TRUE(c.model.Project(Eigen::Vector3d(0, 0, 2), &uv));
  EXPECT_NEAR(uv.x(), 511.5, 1e-12);
  EXPECT_NEAR(uv.y(), 383.5, 1e-12);
}

TEST(CameraConfig, ScaledKeepsTheFieldOfViewAndValidateNamesTheField) {
  const CameraConfig c = CameraConfig().Scaled(0.25);
  EXPECT_EQ(c.model.width_px, 256);
  EXPECT_EQ(c.model.height_px, 192);
  EXPECT_NEAR(c.model.cx_px, 127.5, 1e-12);
  EXPECT_NEAR(c.model.fx_px, 192.5, 1e-12);
  EXPECT_DOUBLE_EQ(c.rate_hz, 30.0);
  CameraConfig bad;
  bad.model.fx_px = -1;
  EXPECT_NE(bad.Validate().find("fx_px"), std::string::npos);
  bad = CameraConfig();
  bad.model.distortion[1] = std::nan("");
  EXPECT_NE(bad.Validate().find("distortion"), std::string::npos);
  bad = CameraConfig();
  bad.model.width_px = 4;
  EXPECT_NE(bad.Validate().find("width_px"), std::string::npos);
  bad = CameraConfig();
  bad.rate_hz = 0;
  EXPECT_NE(bad.Validate().find("rate_hz"), std::string::npos);
}

}  // namespace rig_sim
