#include "rig_model/param_table.h"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

namespace rig_model {
namespace {

struct Inner {
  double max_tilt_deg = 50.0;
};
struct Config {
  Inner inner;
  int border_px = 4;
  bool reject = true;
  std::string frame = "cones";
  int refinement = 0;
  double heading_deg = NAN;
};

const ParamTable<Config>& Table() {
  static const ParamTable<Config> table =
      ParamTable<Config>()
          .Add("max_tilt_deg", [](Config& c) -> double& { return c.inner.max_tilt_deg; })
          .Add("border_px", [](Config& c) -> int& { return c.border_px; })
          .Add("reject", [](Config& c) -> bool& { return c.reject; })
          .Add("frame", [](Config& c) -> std::string& { return c.frame; })
          .AddEnum("refinement", [](Config& c) -> int& { return c.refinement; }, {"outline", "templates", "none"})
          .Add("heading_deg", [](Config& c) -> double& { return c.heading_deg; });
  return table;
}

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(ParamTable, SetsAndGetsThroughTheFields) {
  Config c;
  Table().Set(&c, "max_tilt_deg", 30.0);
  Table().Set(&c, "border_px", 7);
  Table().Set(&c, "reject", false);
  Table().Set(&c, "frame", std::string("map"));
  EXPECT_DOUBLE_EQ(c.inner.max_tilt_deg, 30.0);
  EXPECT_EQ(c.border_px, 7);
  EXPECT_FALSE(c.reject);
  EXPECT_EQ(std::get<std::string>(Table().Get(c, "frame")), "map");
  EXPECT_DOUBLE_EQ(std::get<double>(Table().Get(c, "max_tilt_deg")), 30.0);
  EXPECT_EQ(Table().Names().size(), 6u);
}

TEST(ParamTable, ConvertsWhatIsSafeAndRefusesTheRest) {
  Config c;
  Table().Set(&c, "max_tilt_deg", 20);  // an int written without a decimal point
  EXPECT_DOUBLE_EQ(c.inner.max_tilt_deg, 20.0);
  Table().Set(&c, "border_px", 3.0);
  EXPECT_EQ(c.border_px, 3);
  EXPECT_EQ(ErrorOf([&] { Table().Set(&c, "border_px", 2.5); }), "border_px must be an integer");
  EXPECT_EQ(ErrorOf([&] { Table().Set(&c, "border_px", 1e10); }), "border_px must be an integer");
  Table().Set(&c, "heading_deg", std::string(""));  // a launch file's empty argument: not set
  EXPECT_TRUE(std::isnan(c.heading_deg));
  EXPECT_EQ(ErrorOf([&] { Table().Set(&c, "reject", 1); }), "reject must be true or false");
  EXPECT_EQ(ErrorOf([&] { Table().Set(&c, "max_tilt_deg", std::string("x")); }), "max_tilt_deg must be a number");
  EXPECT_EQ(ErrorOf([&] { Table().Set(&c, "max_tlt_deg", 1.0); }),
            "max_tlt_deg is unknown (did you mean max_tilt_deg?)");
}

// dynamic_reconfigure writes an enum back as its index: a relaunch must read it again.
TEST(ParamTable, EnumsTakeTheirNameOrTheirIndex) {
  Config c;
  Table().Set(&c, "refinement", std::string("none"));
  EXPECT_EQ(c.refinement, 2);
  Table().Set(&c, "refinement", 1);
  EXPECT_EQ(c.refinement, 1);
  EXPECT_EQ(ErrorOf([&] { Table().Set(&c, "refinement", std::string("best")); }),
            "refinement must be one of outline, templates, none (got 'best')");
  EXPECT_EQ(ErrorOf([&] { Table().Set(&c, "refinement", 3); }), "refinement must be one of outline, templates, none");
}

TEST(ParamTable, ReadsYamlWithTheSameNamesAndRefusesTypos) {
  const YAML::Node doc = YAML::Load(
      "segmenter:\n  max_tilt_deg: 35\n  border_px: 2\n  reject: false\n  refinement: templates\n"
      "  frame: map\n  heading_deg: .nan\n");
  Config c;
  const StrictReader reader("photos.yaml");
  Table().FromYaml(doc["segmenter"], reader, "segmenter", &c);
  EXPECT_DOUBLE_EQ(c.inner.max_tilt_deg, 35.0);
  EXPECT_EQ(c.border_px, 2);
  EXPECT_FALSE(c.reject);
  EXPECT_EQ(c.refinement, 1);
  EXPECT_EQ(c.frame, "map");
  EXPECT_TRUE(std::isnan(c.heading_deg));

  const YAML::Node typo = YAML::Load("max_tilt_dg: 35\n");
  EXPECT_EQ(ErrorOf([&] { Table().FromYaml(typo, reader, "", &c); }),
            "photos.yaml:1: unknown key 'max_tilt_dg' (did you mean 'max_tilt_deg'?)");
  const YAML::Node wrong = YAML::Load("a: 1\nborder_px: 2.5\n");
  EXPECT_NE(ErrorOf([&] { Table().FromYaml(wrong, reader, "", &c); }).find("unknown key 'a'"), std::string::npos);
  const YAML::Node half = YAML::Load("border_px: 2.5\n");
  EXPECT_EQ(ErrorOf([&] { Table().FromYaml(half, reader, "", &c); }), "photos.yaml:1: border_px: must be an integer");
}

}  // namespace
}  // namespace rig_model
