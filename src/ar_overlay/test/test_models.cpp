// Generated models, assimp loading and its errors, scene YAML and kinematics.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>

#include "ar_overlay/core/mesh_generators.h"
#include "ar_overlay/core/model_loader.h"
#include "ar_overlay/core/overlay.h"
#include "ar_overlay/core/scene.h"

namespace ar_overlay {
namespace {

const std::string kDir = AR_OVERLAY_DIR;

std::string TempPath(const std::string& name) { return testing::TempDir() + "ar_overlay_" + name; }

std::string Slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

TEST(Generators, PeaksKnownValuesAndSize) {
  EXPECT_NEAR(Peaks(0, 0), (3 - 1.0 / 3) * std::exp(-1.0), 1e-12);  // MATLAB: peaks(0,0) = 0.9810
  EXPECT_NEAR(Peaks(0, 1.5), 8.0, 0.2);                             // the tallest peak, near (0, 1.6)
  const Mesh m = PeaksSurface(160);
  EXPECT_GE(m.TriangleCount(), 50000u);
  EXPECT_EQ(m.vertices.size(), 160u * 160u);
  EXPECT_THROW(PeaksSurface(1), std::invalid_argument);
}

TEST(Generators, AircraftAndArmShapes) {
  const Mesh plane = CargoAircraft();
  Eigen::AlignedBox3f box;
  for (const Vertex& v : plane.vertices) box.extend(Eigen::Vector3f(v.position[0], v.position[1], v.position[2]));
  EXPECT_NEAR(box.sizes().y(), 40.4, 0.1);  // span
  EXPECT_NEAR(box.sizes().x(), 30.0, 1.0);  // length
  const auto arm = Kr6Arm();
  ASSERT_EQ(arm.size(), 7u);
  for (size_t i = 1; i < arm.size(); ++i) EXPECT_EQ(arm[i].joint, "joint_a" + std::to_string(i));
}

TEST(Models, PlyRoundTripThroughAssimp) {
  const Mesh peaks = PeaksSurface(12);
  const std::string path = TempPath("peaks.ply");
  WritePly(peaks, path);
  const Mesh back = LoadModel(path);
  EXPECT_EQ(back.TriangleCount(), peaks.TriangleCount());
  ASSERT_EQ(back.vertices.size(), peaks.vertices.size());
  for (size_t i = 0; i < back.vertices.size(); i += 17) {
    EXPECT_NEAR(back.vertices[i].position[2], peaks.vertices[i].position[2], 1e-5);  // %.6g
    EXPECT_NEAR(back.vertices[i].color[0], peaks.vertices[i].color[0], 1.0 / 255);
  }
}

TEST(Models, LoadErrorsNameTheFileAndTheReason) {
  try {
    LoadModel("/nonexistent/arm.dae");
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/arm.dae: "), std::string::npos) << e.what();
    EXPECT_GT(std::string(e.what()).size(), std::string("/nonexistent/arm.dae: ").size() + 5) << e.what();
  }
  const std::string junk = TempPath("junk.obj");
  std::ofstream(junk) << "this is not a model\n";
  EXPECT_THROW(LoadModel(junk), std::runtime_error);
}

TEST(Models, BundledFilesMatchTheGenerator) {
  const std::string dir = testing::TempDir();
  ASSERT_EQ(std::system((std::string(AR_OVERLAY_MAKE_MODELS) + " " + dir).c_str()), 0);
  for (const std::string name : {"peaks", "c130", "kr6_link0", "kr6_link3", "kr6_link6", "platform_red_dots"}) {
    const std::string committed = Slurp(kDir + "/models/" + name + ".ply");
    EXPECT_FALSE(committed.empty()) << name;
    EXPECT_EQ(committed, Slurp(dir + "/" + name + ".ply")) << name << ".ply differs: run ar_overlay_make_models";
  }
}

TEST(Scene, BundledScenesLoadEveryModel) {
  for (const std::string name : {"peaks", "kr6", "c130", "platform"}) {
    const auto specs = LoadSceneYaml(kDir + "/config/scene_" + name + ".yaml");
    EXPECT_FALSE(specs.empty()) << name;
    for (const ModelSpec& s : specs) EXPECT_NO_THROW(LoadModel(s.file)) << s.file;
  }
}

TEST(Scene, RejectsBadYamlNamingTheEntry) {
  const std::string path = TempPath("bad.yaml");
  std::ofstream(path) << "models:\n  - {name: a, file: a.ply, scale: -1}\n";
  try {
    LoadSceneYaml(path);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":2: models[0].scale: must be > 0"), std::string::npos) << e.what();
  }
  std::ofstream(path) << "models:\n  - {name: b, file: b.ply, parent: nobody}\n";
  EXPECT_THROW(LoadSceneYaml(path), std::runtime_error);
}

TEST(Scene, MisspeltKeyIsRefusedWithFileLineAndNearestKey) {
  const std::string path = TempPath("misspelt.yaml");
  std::ofstream(path) << "models:\n  - name: a\n    file: a.ply\n    scael: 2\n";
  try {
    LoadSceneYaml(path);
    FAIL() << "a misspelt key was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), path + ":4: unknown key 'models[0].scael' (did you mean 'scale'?)");
  }
  std::ofstream(path) << "models:\n  - {name: a, file: a.ply, joint: {name: j, axes: [0, 0, 1]}}\n";
  try {
    LoadSceneYaml(path);
    FAIL() << "a misspelt joint key was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown key 'models[0].joint.axes' (did you mean 'axis'?)"),
              std::string::npos)
        << e.what();
  }
  std::ofstream(path) << "model:\n  - {name: a, file: a.ply}\n";
  EXPECT_THROW(LoadSceneYaml(path), std::runtime_error);
}

TEST(Scene, JointsMoveTheChain) {
  std::vector<ModelSpec> specs(2);
  specs[0].name = "upper";
  specs[0].T_parent_origin.translation() << 0, 0, 1;
  specs[0].joint_name = "j1";
  specs[0].joint_axis = Eigen::Vector3d::UnitY();
  specs[1].name = "lower";
  specs[1].parent = "upper";
  specs[1].T_parent_origin.translation() << 0, 0, 0.5;
  auto poses = ModelPoses(specs, {});
  EXPECT_TRUE(poses[1].translation().isApprox(Eigen::Vector3d(0, 0, 1.5)));
  poses = ModelPoses(specs, {{"j1", M_PI / 2}});
  EXPECT_TRUE(poses[1].translation().isApprox(Eigen::Vector3d(0.5, 0, 1)));  // +z rotated about y goes to +x
}

TEST(Scene, ModelThatFailsIsReportedAndTheRestStillDraw) {
  const std::string ply = TempPath("plate.ply"), yaml = TempPath("scene.yaml");
  WritePly(Box(1.0f, 1.0f, 0.01f, {0, 1, 0, 1}), ply);
  std::ofstream(yaml) << "models:\n"
                      << "  - {name: missing, file: /nonexistent/kr6.dae}\n"
                      << "  - {name: plate, file: " << ply << ", xyz: [0, 0, 2]}\n";
  Overlay overlay;
  const auto errors = overlay.LoadScene(yaml);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("missing: /nonexistent/kr6.dae: "), std::string::npos) << errors[0];
  const cv::Mat image(240, 320, CV_8UC3, cv::Scalar::all(0));
  std::string enc;
  cv::Mat out;
  overlay.Process(image, "rgb8", {320, 240, 300, 300, 160, 120, {}}, Eigen::Isometry3d::Identity(), out, enc);
  EXPECT_GT(out.at<cv::Vec3b>(120, 160)[1], 150);  // the green plate
}

}  // namespace
}  // namespace ar_overlay
