// The panel's description parsing and request building, without ROS or Qt.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "ar_overlay/rviz/reconfigure_model.h"

namespace ar_overlay {
namespace {

dynamic_reconfigure::ParamDescription Param(const std::string& name, const std::string& type) {
  dynamic_reconfigure::ParamDescription p;
  p.name = name;
  p.type = type;
  p.description = "about " + name;
  return p;
}

// A description shaped like pose_ekf's PoseEkf.cfg: an empty top level group, "noise", "switches".
dynamic_reconfigure::ConfigDescription EkfLike() {
  dynamic_reconfigure::ConfigDescription d;
  dynamic_reconfigure::Group top, noise, switches;
  top.name = "Default";
  noise.name = "noise";
  noise.parameters = {Param("sigma_gyro_rad_s", "double"), Param("window", "int"), Param("odd", "mystery")};
  switches.name = "switches";
  switches.parameters = {Param("use_gyro", "bool"), Param("frame", "str")};
  d.groups = {top, noise, switches};
  dynamic_reconfigure::DoubleParameter dmin, dmax, ddef;
  dmin.name = dmax.name = ddef.name = "sigma_gyro_rad_s";
  dmin.value = 1e-6, dmax.value = 10.0, ddef.value = 0.01;
  d.min.doubles.push_back(dmin);
  d.max.doubles.push_back(dmax);
  d.dflt.doubles.push_back(ddef);
  dynamic_reconfigure::IntParameter imin, imax, idef;
  imin.name = imax.name = idef.name = "window";
  imin.value = 1, imax.value = 50, idef.value = 5;
  d.min.ints.push_back(imin);
  d.max.ints.push_back(imax);
  d.dflt.ints.push_back(idef);
  dynamic_reconfigure::BoolParameter bdef;
  bdef.name = "use_gyro";
  bdef.value = true;
  d.dflt.bools.push_back(bdef);
  dynamic_reconfigure::StrParameter sdef;
  sdef.name = "frame";
  sdef.value = "imu";
  d.dflt.strs.push_back(sdef);
  return d;
}

TEST(ReconfigureModel, GroupsAndRangesFromDescription) {
  std::vector<std::string> skipped;
  const auto groups = GroupsFromDescription(EkfLike(), &skipped);
  ASSERT_EQ(groups.size(), 2u);  // the empty top level is left out
  EXPECT_EQ(groups[0].name, "noise");
  ASSERT_EQ(groups[0].params.size(), 2u);
  const ParamSpec& sigma = groups[0].params[0];
  EXPECT_EQ(sigma.kind, ParamKind::kDouble);
  EXPECT_DOUBLE_EQ(sigma.min, 1e-6);
  EXPECT_DOUBLE_EQ(sigma.max, 10.0);
  EXPECT_DOUBLE_EQ(sigma.default_value, 0.01);
  EXPECT_EQ(sigma.description, "about sigma_gyro_rad_s");
  EXPECT_EQ(groups[0].params[1].kind, ParamKind::kInt);
  EXPECT_DOUBLE_EQ(groups[0].params[1].default_value, 5.0);
  ASSERT_EQ(skipped.size(), 1u);
  EXPECT_NE(skipped[0].find("odd"), std::string::npos);
  EXPECT_EQ(groups[1].params[0].kind, ParamKind::kBool);
  EXPECT_DOUBLE_EQ(groups[1].params[0].default_value, 1.0);
  EXPECT_EQ(groups[1].params[1].default_string, "imu");
}

TEST(ReconfigureModel, SingleParameterRequests) {
  const auto groups = GroupsFromDescription(EkfLike());
  const ParamSpec &sigma = groups[0].params[0], &window = groups[0].params[1];
  const ParamSpec &gyro = groups[1].params[0], &frame = groups[1].params[1];

  auto c = SingleParameter(gyro, 0.0);
  ASSERT_EQ(c.bools.size(), 1u);
  EXPECT_TRUE(c.doubles.empty() && c.ints.empty() && c.strs.empty());
  EXPECT_EQ(c.bools[0].name, "use_gyro");
  EXPECT_FALSE(c.bools[0].value);

  c = SingleParameter(sigma, 0.5);
  ASSERT_EQ(c.doubles.size(), 1u);
  EXPECT_DOUBLE_EQ(c.doubles[0].value, 0.5);
  double v = 0;
  ASSERT_TRUE(NumberFromConfig(c, "sigma_gyro_rad_s", &v));
  EXPECT_DOUBLE_EQ(v, 0.5);
  EXPECT_FALSE(NumberFromConfig(c, "use_gyro", &v));
  EXPECT_DOUBLE_EQ(SingleParameter(sigma, 99.0).doubles[0].value, 10.0);  // clamped to the range

  c = SingleParameter(window, 7.6);
  ASSERT_EQ(c.ints.size(), 1u);
  EXPECT_EQ(c.ints[0].value, 8);
  EXPECT_EQ(SingleParameter(window, -3).ints[0].value, 1);

  c = SingleParameter(frame, std::string("camera"));
  std::string s;
  ASSERT_TRUE(StringFromConfig(c, "frame", &s));
  EXPECT_EQ(s, "camera");
}

TEST(ReconfigureModel, BadValuesAreRefusedWithTheName) {
  const auto groups = GroupsFromDescription(EkfLike());
  try {
    SingleParameter(groups[0].params[0], std::numeric_limits<double>::quiet_NaN());
    FAIL() << "NaN accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sigma_gyro_rad_s"), std::string::npos);
  }
  EXPECT_THROW(SingleParameter(groups[1].params[1], 1.0), std::invalid_argument);               // a string
  EXPECT_THROW(SingleParameter(groups[0].params[0], std::string("x")), std::invalid_argument);  // a number
}

}  // namespace
}  // namespace ar_overlay
