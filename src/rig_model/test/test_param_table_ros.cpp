// The dynamic_reconfigure side of a parameter table, on messages (no master needed).
#include "rig_model/ros/param_table_ros.h"

#include <gtest/gtest.h>

namespace rig_model {
namespace {

struct Config {
  double sigma_px = 1.0;
  int border_px = 4;
  bool tint = true;
  int refinement = 0;
  std::string frame = "cones";
};

const ParamTable<Config>& Table() {
  static const ParamTable<Config> table =
      ParamTable<Config>()
          .Add("sigma_px", [](Config& c) -> double& { return c.sigma_px; })
          .Add("border_px", [](Config& c) -> int& { return c.border_px; })
          .Add("tint", [](Config& c) -> bool& { return c.tint; })
          .AddEnum("refinement", [](Config& c) -> int& { return c.refinement; }, {"outline", "templates", "none"})
          .Add("frame", [](Config& c) -> std::string& { return c.frame; });
  return table;
}

template <class P>
P Named(const std::string& name) {
  P p;
  p.name = name;
  return p;
}

dynamic_reconfigure::Config ReconfigureMessage() {
  dynamic_reconfigure::Config msg;
  msg.doubles.push_back(Named<dynamic_reconfigure::DoubleParameter>("sigma_px"));
  msg.ints.push_back(Named<dynamic_reconfigure::IntParameter>("border_px"));
  msg.ints.push_back(Named<dynamic_reconfigure::IntParameter>("refinement"));
  msg.bools.push_back(Named<dynamic_reconfigure::BoolParameter>("tint"));
  msg.strs.push_back(Named<dynamic_reconfigure::StrParameter>("frame"));
  return msg;
}

TEST(ParamTableRos, RoundTripsThroughAReconfigureMessage) {
  Config c;
  c.sigma_px = 2.5, c.border_px = 9, c.tint = false, c.refinement = 2, c.frame = "map";
  dynamic_reconfigure::Config msg = ReconfigureMessage();
  WriteReconfigureMessage([&](const std::string& name) { return Table().Get(c, name); }, &msg);
  EXPECT_DOUBLE_EQ(msg.doubles[0].value, 2.5);
  EXPECT_EQ(msg.ints[1].value, 2);  // the enum as its index, as dynamic_reconfigure keeps it

  Config back;
  ReadReconfigureMessage(msg, [&](const std::string& name, const ParamValue& v) { Table().Set(&back, name, v); });
  EXPECT_DOUBLE_EQ(back.sigma_px, 2.5);
  EXPECT_EQ(back.border_px, 9);
  EXPECT_FALSE(back.tint);
  EXPECT_EQ(back.refinement, 2);
  EXPECT_EQ(back.frame, "map");
}

TEST(ParamTableRos, AReconfigureNameMissingFromTheTableIsNamed) {
  dynamic_reconfigure::Config msg = ReconfigureMessage();
  msg.doubles.push_back(Named<dynamic_reconfigure::DoubleParameter>("sigma_pix"));
  Config c;
  try {
    WriteReconfigureMessage([&](const std::string& name) { return Table().Get(c, name); }, &msg);
    FAIL() << "no error for a name the table lacks";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "sigma_pix is unknown (did you mean sigma_px?)");
  }
}

}  // namespace
}  // namespace rig_model
