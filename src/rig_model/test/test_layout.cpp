#include "rig_model/layout.h"

#include <glob.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "rig_model/layout_yaml.h"
#include "rig_model/strict_yaml.h"
#include "rig_model/surveyed_layout.h"
#include "test_util.h"

namespace rig_model {
namespace {

std::vector<std::string> ShippedLayouts() {
  glob_t g;
  std::vector<std::string> out;
  if (glob(RIG_MODEL_LAYOUTS_DIR "/*.yaml", 0, nullptr, &g) == 0) {
    for (size_t i = 0; i < g.gl_pathc; ++i) out.emplace_back(g.gl_pathv[i]);
  }
  globfree(&g);
  return out;
}

std::string Cones(int n) {
  std::string text = "cones:\n";
  for (int i = 0; i < n; ++i) text += "  - {x_m: " + std::to_string(0.5 * i) + ", y_m: 0.3}\n";
  return text;
}

TEST(Layout, EveryShippedLayoutLoads) {
  const std::vector<std::string> files = ShippedLayouts();
  ASSERT_GE(files.size(), 6u) << "layouts missing from " RIG_MODEL_LAYOUTS_DIR;
  for (const std::string& f : files) {
    Layout layout;
    EXPECT_EQ(ErrorOf([&] { layout = LoadLayoutFile(f); }), "") << f;
    EXPECT_GE(layout.cones.size(), 3u) << f;
  }
}

TEST(Layout, CorrectedModelPointsFaceTheCamera) {
  const auto p = CorrectedModelPoints(Eigen::Vector3d(1, 0, 0), 0.7, 1.0 / 7.0, Eigen::Vector3d(5, 0, 1.5));
  EXPECT_TRUE(p[0].isApprox(Eigen::Vector3d(1, 0, 0.7)));
  EXPECT_TRUE(p[1].isApprox(Eigen::Vector3d(1.05, 0, 0.35)));
  EXPECT_TRUE(p[2].isApprox(Eigen::Vector3d(1.1, 0, 0)));
  // A camera straight above the axis: no side faces it, the points stay on the axis.
  const auto q = CorrectedModelPoints(Eigen::Vector3d(1, 0, 0), 0.7, 1.0 / 7.0, Eigen::Vector3d(1, 0, 3));
  EXPECT_TRUE(q[2].isApprox(Eigen::Vector3d(1, 0, 0)));
}

TEST(Layout, DefaultFileIsTheThesisTriangle) {
  const Layout file = LoadLayoutFile(RIG_MODEL_LAYOUTS_DIR "/default.yaml");
  const Layout built = DefaultLayout();
  ASSERT_EQ(file.cones.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(file.cones[i].base_m, built.cones[i].base_m);  // bit for bit: one construction
    EXPECT_EQ(file.cones[i].height_m, 0.71);
    EXPECT_EQ(file.cones[i].style, ConeStyle::kRoad);
    EXPECT_NEAR((built.cones[i].base_m - built.cones[(i + 1) % 3].base_m).norm(), 1.5, 1e-12);  // 3.1.3
  }
  EXPECT_NEAR(built.ConeCentroid().norm(), 0.0, 1e-12);
  EXPECT_NEAR(built.cones[0].base_m.y(), 0.0, 1e-15);  // cone 1 on +x
  EXPECT_GT(built.cones[0].base_m.x(), 0.0);
}

TEST(Layout, ExplicitConesAndScenery) {
  const Layout s = ParseLayout(
      "cones:\n"
      "  - {x_m: 1.0, y_m: 0.0, height_m: 0.46, style: plain, tau: 0.2}\n"
      "  - {x_m: -0.5, y_m: 0.8, z_m: 0.12, albedo: [0.5, 0.2, 0.1], collars: [[0.1, 0.2]], base_plate_m: 0.3}\n"
      "  - {x_m: -0.5, y_m: -0.8}\n"
      "boxes: [{x_m: 3, y_m: 1, yaw_deg: 90, sx_m: 0.6, sy_m: 0.4, sz_m: 0.4}]\n"
      "patches: [{x_m: 1, sx_m: 0.3}]\n"
      "people: [{x_m: -3, y_m: 2, height_m: 1.8}]\n"
      "platforms: [{rows: 3, cols: 4}]\n"
      "ground: grass\n",
      "t.yaml");
  ASSERT_EQ(s.cones.size(), 3u);
  EXPECT_EQ(s.cones[0].style, ConeStyle::kPlain);
  EXPECT_TRUE(s.cones[0].collars.empty());
  EXPECT_DOUBLE_EQ(s.cones[0].tau, 0.2);
  EXPECT_DOUBLE_EQ(s.cones[1].base_m.z(), 0.12);
  ASSERT_EQ(s.cones[1].collars.size(), 1u);
  EXPECT_DOUBLE_EQ(s.cones[1].base_plate_m, 0.3);
  EXPECT_DOUBLE_EQ(s.cones[1].albedo.x(), 0.5);
  EXPECT_DOUBLE_EQ(s.cones[2].height_m, 0.71);
  ASSERT_EQ(s.boxes.size(), 1u);
  EXPECT_DOUBLE_EQ(s.boxes[0].center_m.z(), 0.2);
  EXPECT_NEAR(s.boxes[0].yaw_rad, M_PI / 2, 1e-15);
  EXPECT_EQ(s.patches.size(), 1u);
  EXPECT_DOUBLE_EQ(s.people[0].height_m, 1.8);
  EXPECT_EQ(s.platforms[0].DotCentres().size(), 12u);
  EXPECT_EQ(s.ground, GroundStyle::kGrass);
}

TEST(Layout, MisspeltKeysAreRefusedAndNamed) {
  // The case: a typo inside a cone used to be ignored and the default height used.
  const std::string path = WriteTestFile("cones.yaml",
                                         "# three cones\n"
                                         "cones:\n"
                                         "  - {x_m: 1.0, y_m: 0.0, height_m: 0.71}\n"
                                         "  - {x_m: -0.5, y_m: 0.8, height_m: 0.71}\n"
                                         "  - x_m: -0.5\n"
                                         "    y_m: -0.8\n"
                                         "    hieght_m: 0.71\n");
  const std::string e = ErrorOf([&] { LoadLayoutFile(path); });
  EXPECT_NE(e.find("cones.yaml:7: unknown key 'cones[2].hieght_m' (did you mean 'height_m'?)"), std::string::npos) << e;
  EXPECT_EQ(e.find(path), 0u) << e;  // the whole path, so the user finds the file

  const std::string top = ErrorOf([] { ParseLayout("equilateal: {side_m: 1.5}\n", "l.yaml"); });
  EXPECT_NE(top.find("l.yaml:1: unknown key 'equilateal' (did you mean 'equilateral'?)"), std::string::npos) << top;
  const std::string eq = ErrorOf([] { ParseLayout("equilateral: {side_m: 1.5, stlye: road}\n", "l.yaml"); });
  EXPECT_NE(eq.find("unknown key 'equilateral.stlye' (did you mean 'style'?)"), std::string::npos) << eq;
  const std::string box = ErrorOf([] { ParseLayout("equilateral: {}\nboxes:\n  - {x_m: 1, sx: 0.4}\n", "l.yaml"); });
  EXPECT_NE(box.find("l.yaml:3: unknown key 'boxes[0].sx'"), std::string::npos) << box;
  const std::string plat =
      ErrorOf([] { ParseLayout("equilateral: {}\nplatforms:\n  - {rows: 3, colls: 3}\n", "l.yaml"); });
  EXPECT_NE(plat.find("unknown key 'platforms[0].colls' (did you mean 'cols'?)"), std::string::npos) << plat;
}

TEST(Layout, ConeCountIsThreeToThirty) {
  const std::string two = ErrorOf([] { ParseLayout(Cones(2), "c.yaml"); });
  EXPECT_NE(two.find("c.yaml:1: cones: the layout has 2 cones; 3 to 30 are supported"), std::string::npos) << two;
  const std::string many = ErrorOf([] { ParseLayout(Cones(31), "c.yaml"); });
  EXPECT_NE(many.find("the layout has 31 cones; 3 to 30 are supported"), std::string::npos) << many;
  EXPECT_EQ(ParseLayout(Cones(30), "c.yaml").cones.size(), 30u);
  EXPECT_EQ(ParseLayout(Cones(3), "c.yaml").cones.size(), 3u);
  const std::string none = ErrorOf([] { ParseLayout("ground: asphalt\n", "c.yaml"); });
  EXPECT_NE(none.find("no cones"), std::string::npos) << none;
}

TEST(Layout, HeightsAre4To36Inches) {
  EXPECT_EQ(ParseLayout("cones:\n  - {x_m: 1, height_m: 0.10}\n  - {x_m: 2, height_m: 0.92}\n  - {x_m: 3}\n", "h")
                .cones.size(),
            3u);
  const std::string low =
      ErrorOf([] { ParseLayout("cones:\n  - {x_m: 1}\n  - {x_m: 2}\n  - {x_m: 3, height_m: 0.05}\n", "h.yaml"); });
  EXPECT_NE(low.find("h.yaml:4: cones[2].height_m: 0.05 is outside [0.1, 0.92] m"), std::string::npos) << low;
  const std::string eq = ErrorOf([] { ParseLayout("equilateral: {height_m: 1.2}\n", "h.yaml"); });
  EXPECT_NE(eq.find("equilateral.height_m: 1.2 is outside"), std::string::npos) << eq;
}

TEST(Layout, SurveyedSigmaIsOptionalAndChecked) {
  const std::string two = "  - {x_m: 1}\n  - {x_m: 2}\n";
  const std::string path = "/tmp/rig_model_test_sigmas_" + std::to_string(getpid()) + ".yaml";
  std::ofstream(path) << "equilateral: {side_m: 2}\ncones:\n" + two + "  - {x_m: 3, sigma_m: [0.004, 0.005, 0.01]}\n";
  const Layout surveyed = LoadLayoutFile(path);
  const std::vector<Eigen::Vector3d> sigmas = LoadConeSigmas(path);
  std::remove(path.c_str());
  ASSERT_EQ(sigmas.size(), 6u);
  EXPECT_DOUBLE_EQ(sigmas[5].y(), 0.005);
  EXPECT_DOUBLE_EQ(surveyed.cones[5].base_m.x(), 3.0);
  for (int i = 0; i < 5; ++i) EXPECT_TRUE(sigmas[i].array().isNaN().all()) << i;
  // Written back by ConesYaml and read again: the same cones and sigmas.
  std::ofstream(path) << ConesYaml(surveyed.cones, sigmas);
  const Layout again = LoadLayoutFile(path);
  const std::vector<Eigen::Vector3d> sigmas_again = LoadConeSigmas(path);
  std::remove(path.c_str());
  ASSERT_EQ(again.cones.size(), 6u);
  for (int i = 0; i < 6; ++i) {
    EXPECT_LT((again.cones[i].base_m - surveyed.cones[i].base_m).norm(), 1e-4) << i;
    EXPECT_EQ(again.cones[i].height_m, surveyed.cones[i].height_m) << i;
    EXPECT_EQ(again.cones[i].style, surveyed.cones[i].style) << i;
  }
  EXPECT_DOUBLE_EQ(sigmas_again[5].z(), 0.01);
  EXPECT_TRUE(sigmas_again[0].array().isNaN().all());
  auto error = [&](const std::string& sigma) {
    return ErrorOf([&] { ParseLayout("cones:\n" + two + "  - {x_m: 3, sigma_m: " + sigma + "}\n", "s.yaml"); });
  };
  EXPECT_NE(error("[0.1, 0.1]").find("s.yaml:4: cones[2].sigma_m: must be [x, y, z] in metres"), std::string::npos);
  EXPECT_NE(error("[0.1, -0.1, 0]").find("cones[2].sigma_m: components must be finite and >= 0"), std::string::npos);
  EXPECT_NE(error("[0.1, abc, 0]").find("cones[2].sigma_m: components must be finite"), std::string::npos);
}

TEST(Layout, BadValuesNameTheField) {
  auto error = [](const std::string& text) { return ErrorOf([&] { ParseLayout(text, "v.yaml"); }); };
  const std::string three = "  - {x_m: 1}\n  - {x_m: 2}\n";
  EXPECT_NE(error("cones:\n" + three + "  - {x_m: abc}\n").find("cones[2].x_m: must be a number"), std::string::npos);
  EXPECT_NE(error("cones:\n" + three + "  - {x_m: .nan}\n").find("cones[2].x_m: must be finite"), std::string::npos);
  EXPECT_NE(error("cones:\n" + three + "  - {x_m: 3, style: tall}\n").find("cones[2].style: must be 'road' or 'plain'"),
            std::string::npos);
  EXPECT_NE(error("cones:\n" + three + "  - {x_m: 3, tau: 2}\n").find("cones[2].tau: must be in (0.02, 1)"),
            std::string::npos);
  EXPECT_NE(error("cones:\n" + three + "  - {x_m: 2}\n").find("cones[2]: is identical to cones[1]"), std::string::npos);
  EXPECT_NE(error("cones:\n" + three + "  - {x_m: 3, albedo: [1, 2]}\n").find("cones[2].albedo: must be [r, g, b]"),
            std::string::npos);
  EXPECT_NE(error("cones: 3\n").find("cones: must be a list"), std::string::npos);
  EXPECT_NE(error("equilateral: {side_m: -1}\n").find("equilateral.side_m: must be > 0"), std::string::npos);
  EXPECT_NE(error("equilateral: {}\nground: snow\n").find("ground: must be asphalt, grass or concrete"),
            std::string::npos);
  EXPECT_NE(error("equilateral: {}\nplatforms: [{rows: 9}]\n").find("platforms[0]: the dot grid does not fit"),
            std::string::npos);
  EXPECT_NE(error("equilateral: {}\nplatforms: [{rows: 2.5}]\n").find("platforms[0].rows: must be a whole number"),
            std::string::npos);
  EXPECT_EQ(error("cones: [\n").find("v.yaml:"), 0u);
  EXPECT_NE(error("cones: [\n").find("not valid YAML"), std::string::npos) << error("cones: [\n");
  EXPECT_NE(error("").find("v.yaml: empty"), std::string::npos);
  EXPECT_NE(ErrorOf([] { LoadLayoutFile("/nonexistent/layout.yaml"); }).find("/nonexistent/layout.yaml: cannot open"),
            std::string::npos);
}

// A file of the layout schema without positions (cone_survey's inventory): the same cone fields and
// checks, positions and scenery refused, heights required, the caller's own keys let through.
TEST(Layout, SchemaWithoutPositions) {
  LayoutSchema schema;
  schema.positions = false;
  schema.no_positions_why = "no positions here";
  schema.height_required = true;
  schema.what = "inventory";
  schema.extra_top_keys = {"origin"};
  auto parse = [&](const std::string& text) { return ParseLayoutRoot(YAML::Load(text), "i.yaml", schema); };
  auto error = [&](const std::string& text) { return ErrorOf([&] { parse(text); }); };
  const Layout l = parse(
      "cones:\n  - {height_m: 0.71}\n  - {height_m: 0.71, style: plain, tau: 0.2}\n"
      "  - {height_m: 0.3}\norigin: 1\n");
  ASSERT_EQ(l.cones.size(), 3u);  // two of one height: not "identical" without positions
  EXPECT_EQ(l.cones[1].style, ConeStyle::kPlain);
  EXPECT_DOUBLE_EQ(l.cones[1].tau, 0.2);
  EXPECT_EQ(l.cones[0].base_m, Eigen::Vector3d::Zero());
  const std::string three = "  - {height_m: 0.71}\n  - {height_m: 0.46}\n";
  EXPECT_NE(
      error("cones:\n" + three + "  - {height_m: 0.3, y_m: 1}\n").find("i.yaml:4: cones[2].y_m: no positions here"),
      std::string::npos);
  EXPECT_NE(
      error("cones:\n" + three + "  - {height_m: 0.3, sigma_m: [0, 0, 0]}\n").find("cones[2].sigma_m: no positions"),
      std::string::npos);
  EXPECT_NE(error("cones:\n" + three + "  - {style: road}\n").find("cones[2].height_m"), std::string::npos);
  EXPECT_NE(error("cones:\n" + three + "  - {height_m: 0.3, stlye: road}\n").find("(did you mean 'style'?)"),
            std::string::npos);
  EXPECT_NE(error("cones:\n" + three + "  - {height_m: 1.3}\n").find("cones[2].height_m: 1.3 is outside"),
            std::string::npos);
  EXPECT_NE(error("cones:\n" + three + "boxes: []\n").find("unknown key 'boxes'"), std::string::npos);
  EXPECT_NE(error("equilateral: {}\n").find("unknown key 'equilateral'"), std::string::npos);
  EXPECT_NE(error("cones:\n" + three).find("the inventory has 2 cones"), std::string::npos);
  // The layout's own rules are unchanged: a position is read, two cones at one place of one height refused.
  EXPECT_NE(ErrorOf([&] {
              ParseLayoutRoot(YAML::Load("cones:\n" + three + "  - {height_m: 0.46}\n"), "l.yaml", LayoutSchema());
            }).find("is identical to cones[1]"),
            std::string::npos);
}

}  // namespace
}  // namespace rig_model
