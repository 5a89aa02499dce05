// The layout file through rig_model's parser: the tracker's model points, its own cone limit, and
// rig_model's messages (file, line, field) passed on.
#include <gtest/gtest.h>

#include <glob.h>

#include "cone_tracker/node/layout.h"
#include "pose_math/rotation.h"

namespace cone_tracker {
namespace {

std::string ParseError(const std::string& text) {
  std::vector<ConeModel> cones;
  std::string error;
  EXPECT_FALSE(ParseLayout(text, "test.yaml", &cones, &error)) << text;
  return error;
}

}  // namespace

TEST(Layout, EveryShippedLayoutLoads) {
  glob_t g;
  ASSERT_EQ(glob(RIG_MODEL_LAYOUTS_DIR "/*.yaml", 0, nullptr, &g), 0);
  ASSERT_GE(g.gl_pathc, 6u);
  for (size_t i = 0; i < g.gl_pathc; ++i) {
    std::vector<ConeModel> cones;
    std::string error;
    EXPECT_TRUE(LoadLayoutFile(g.gl_pathv[i], &cones, &error)) << error;
    EXPECT_GE(cones.size(), 3u) << g.gl_pathv[i];
  }
  globfree(&g);
}

TEST(Layout, EquilateralIsTheThesisTriangle) {
  std::vector<ConeModel> cones;
  std::string error;
  ASSERT_TRUE(LoadLayoutFile(RIG_MODEL_LAYOUTS_DIR "/default.yaml", &cones, &error)) << error;
  ASSERT_EQ(cones.size(), 3u);
  const double r = 1.5 / std::sqrt(3.0);
  EXPECT_NEAR(cones[0].base_m.x(), r, 1e-12);  // cone 1 on +x
  EXPECT_NEAR(cones[0].base_m.y(), 0.0, 1e-12);
  EXPECT_NEAR(cones[1].base_m.x(), -0.5 * r, 1e-12);
  EXPECT_NEAR(cones[1].base_m.y(), r * std::sqrt(3.0) / 2.0, 1e-12);
  EXPECT_NEAR((cones[1].base_m - cones[2].base_m).norm(), 1.5, 1e-12);
  EXPECT_DOUBLE_EQ(cones[2].height_m, 0.71);
  EXPECT_DOUBLE_EQ(cones[2].tau, 1.0 / 7.0);
  EXPECT_TRUE(LayoutHasRotationalSymmetry(cones));
  const std::vector<ConeModel> built = ConeModels(rig_model::DefaultLayout());
  for (size_t i = 0; i < 3; ++i) EXPECT_EQ(built[i].base_m, cones[i].base_m);  // one construction
}

TEST(Layout, ExplicitConesWithStackedCone) {
  std::vector<ConeModel> cones;
  std::string error;
  ASSERT_TRUE(LoadLayoutFile(RIG_MODEL_LAYOUTS_DIR "/stacked.yaml", &cones, &error)) << error;
  ASSERT_EQ(cones.size(), 4u);
  EXPECT_DOUBLE_EQ(cones[3].base_m.z(), 0.12);
  EXPECT_DOUBLE_EQ(cones[1].height_m, 0.46);
  EXPECT_FALSE(LayoutHasRotationalSymmetry(cones));
}

TEST(Layout, ErrorsNameTheFileLineAndField) {
  EXPECT_NE(ParseError("cones:\n  - {x_m: 1.0, y_m: oops, height_m: 0.7}\n  - {x_m: 2}\n  - {x_m: 3}\n")
                .find("layout test.yaml:2: cones[0].y_m: must be a number"),
            std::string::npos);
  // A misspelt key is refused, not replaced by the default height.
  const std::string typo = ParseError("cones:\n  - {x_m: 1}\n  - {x_m: 2}\n  - {x_m: 3, hieght_m: 0.46}\n");
  EXPECT_NE(typo.find("test.yaml:4: unknown key 'cones[2].hieght_m' (did you mean 'height_m'?)"), std::string::npos)
      << typo;
  EXPECT_NE(ParseError("cones:\n  - {x_m: 1}\n  - {x_m: 2}\n").find("2 cones; 3 to 30"), std::string::npos);
  std::string many = "cones:\n";  // the schema's maximum is the tracker's (kMaxTrackedCones)
  for (int i = 0; i < 31; ++i) many += "  - {x_m: " + std::to_string(i) + "}\n";
  EXPECT_NE(ParseError(many).find("31 cones; 3 to 30"), std::string::npos) << ParseError(many);
  EXPECT_NE(ParseError("equilateral: {side_m: 1.5, height_m: 1.2}\n").find("equilateral.height_m: 1.2 is outside"),
            std::string::npos);
  EXPECT_NE(ParseError("equilateral: {side_m: 1.5, height_m: 0.05}\n").find("outside [0.1, 0.92]"), std::string::npos);
  EXPECT_NE(ParseError("equilateral: {side_m: 1.5, style: stripy}\n").find("equilateral.style"), std::string::npos);
  EXPECT_NE(ParseError("cone:\n  - {x_m: 1}\n").find("unknown key 'cone' (did you mean 'cones'?)"), std::string::npos);
  EXPECT_NE(ParseError("cones: [1, 2, 3]\n").find("cones[0]: must be a mapping"), std::string::npos);
  EXPECT_NE(ParseError("cones: {x_m: 1}\n").find("cones: must be a list"), std::string::npos);
  EXPECT_NE(ParseError("equilateral: {side_m: 1.5\n").find("not valid YAML"), std::string::npos);
  EXPECT_NE(ParseError("cones:\n  - {x_m: 1}\n  - {x_m: 1}\n  - {x_m: 3}\n").find("identical"), std::string::npos);
  EXPECT_NE(ParseError("- 1\n- 2\n").find("mapping"), std::string::npos);
  EXPECT_NE(ParseError("equilateral: {side_m: .nan}\n").find("finite"), std::string::npos);

  std::vector<ConeModel> cones;
  std::string error;
  EXPECT_FALSE(LoadLayoutFile("/nonexistent/layout.yaml", &cones, &error));
  EXPECT_NE(error.find("/nonexistent/layout.yaml: cannot open"), std::string::npos) << error;
  EXPECT_TRUE(cones.empty());  // untouched on error
}

TEST(Layout, LimitsAreInclusive) {
  std::vector<ConeModel> cones;
  std::string error;
  EXPECT_TRUE(ParseLayout("cones:\n  - {x_m: 1, height_m: 0.10}\n  - {x_m: 2, height_m: 0.92}\n  - {x_m: 3}\n", "t",
                          &cones, &error))
      << error;
  std::string eight = "cones:\n";
  for (int i = 0; i < 8; ++i) eight += "  - {x_m: " + std::to_string(i) + ", y_m: -5.0}\n";
  EXPECT_TRUE(ParseLayout(eight, "t", &cones, &error)) << error;
  EXPECT_EQ(cones.size(), 8u);
  std::string thirty = "cones:\n";
  for (int i = 0; i < 30; ++i)
    thirty += "  - {x_m: " + std::to_string(i % 6) + ", y_m: " + std::to_string(i / 6) + ", height_m: 0.46}\n";
  EXPECT_TRUE(ParseLayout(thirty, "t", &cones, &error)) << error;
  EXPECT_EQ(cones.size(), size_t(kMaxTrackedCones));
}

TEST(Layout, TheSiteLayoutLoads) {  // rig_sim's 14-cone site: refused while the tracker took 8
  std::vector<ConeModel> cones;
  std::string error;
  ASSERT_TRUE(LoadLayoutFile(RIG_MODEL_LAYOUTS_DIR "/site.yaml", &cones, &error)) << error;
  EXPECT_EQ(cones.size(), 14u);
}

}  // namespace cone_tracker

namespace cone_tracker {

// A frame of rig_sim's `site` walk (make_bag --scenario site --scale 0.5 --seed 1, t = 2.13 s): four
// detections at 512x384, three of them far cones 25-35 px tall, one past the image's left edge after
// undistortion. From a cold start the 14-cone layout's ids are the renderer's (checked against the
// truth pose: 13 12 0 3).
TEST(Layout, SiteFrameColdStartIds) {
  std::vector<ConeModel> cones;
  std::string error;
  ASSERT_TRUE(LoadLayoutFile(RIG_MODEL_LAYOUTS_DIR "/site.yaml", &cones, &error)) << error;
  CameraModel cam;
  cam.width_px = 512, cam.height_px = 384, cam.fx_px = 385.0, cam.fy_px = 388.0, cam.cx_px = 255.5, cam.cy_px = 191.5;
  const double px[4][6] = {{-11.654, 165.384, -11.601, 183.300, -11.548, 201.215},
                           {189.535, 164.235, 188.517, 176.392, 187.499, 188.550},
                           {273.985, 187.307, 270.175, 242.763, 266.365, 298.219},
                           {438.005, 204.162, 436.481, 216.183, 434.957, 228.205}};
  std::vector<ConeDetection> dets(4);
  for (size_t i = 0; i < 4; ++i) {
    dets[i].peak_undist_px = {px[i][0], px[i][1]}, dets[i].mid_undist_px = {px[i][2], px[i][3]};
    dets[i].base_undist_px = {px[i][4], px[i][5]};
  }
  const ConePoseResult r = EstimateConePose(dets, cones, cam, ConePoseConfig(), std::nullopt);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.cone_of_detection, (std::vector<int>{13, 12, 0, 3}));
  const Eigen::Vector3d eye =
      -(pose_math::RotationFromQuat(r.pnp.T_camera_model.q).transpose() * r.pnp.T_camera_model.t);
  EXPECT_LT((eye - Eigen::Vector3d(3.966, 4.100, 1.212)).norm(), 0.1);  // the truth's camera position
}

}  // namespace cone_tracker
