// The sim node's parameters against a parameter server: every field through the table, wrong
// types and misspelt names refused naming them, and the parameters both sim.launch files give it.
#include <gtest/gtest.h>
#include <ros/ros.h>

#include "rig_model/ros/launch_params.h"
#include "rig_sim/ros/sim_publisher.h"

namespace rig_sim {
namespace {

std::string Error(const std::string& ns, SimPublisherConfig* c = nullptr) {
  SimPublisherConfig out;
  std::string error;
  if (!LoadSimPublisherConfig(ros::NodeHandle(ns), c ? c : &out, &error)) return error;
  return "";
}

TEST(SimPublisherParams, ReadsEveryParameter) {
  ros::NodeHandle nh("~every");
  nh.setParam("scenario", "look_away");
  nh.setParam("look", "low_sun");
  nh.setParam("seed", 7);
  nh.setParam("image_scale", 0.5);
  nh.setParam("duration_s", 3);  // an integer where a double is wanted
  nh.setParam("realtime_factor", 2.0);
  nh.setParam("camera_delay_ms", 12.5);
  nh.setParam("start_time_s", 100.0);
  nh.setParam("loop", true);
  nh.setParam("publish_clock", false);
  nh.setParam("serial_pty", true);
  nh.setParam("serial_link", "/tmp/link");
  nh.setParam("layouts_dir", "/tmp/layouts");
  nh.setParam("wait_for_manager", "ar_manager");
  nh.setParam("wait_for_nodelets", "cone_tracker pose_ekf");
  EXPECT_EQ(SimPublisherParams().Names().size(), 15u);
  SimPublisherConfig c;
  ASSERT_EQ(Error("~every", &c), "");
  EXPECT_EQ(c.scenario, "look_away");
  EXPECT_EQ(c.look, "low_sun");
  EXPECT_EQ(c.seed, 7);
  EXPECT_DOUBLE_EQ(c.image_scale, 0.5);
  EXPECT_DOUBLE_EQ(c.duration_s, 3.0);
  EXPECT_DOUBLE_EQ(c.realtime_factor, 2.0);
  EXPECT_DOUBLE_EQ(c.camera_delay_ms, 12.5);
  EXPECT_DOUBLE_EQ(c.start_time_s, 100.0);
  EXPECT_TRUE(c.loop);
  EXPECT_FALSE(c.publish_clock);
  EXPECT_TRUE(c.serial_pty);
  EXPECT_EQ(c.serial_link, "/tmp/link");
  EXPECT_EQ(c.layouts_dir, "/tmp/layouts");
  EXPECT_EQ(c.wait_for_manager, "ar_manager");
  EXPECT_EQ(c.wait_for_nodelets, "cone_tracker pose_ekf");
}

TEST(SimPublisherParams, RefusesNodeletsToWaitForWithoutTheirManager) {
  ros::NodeHandle("~no_manager").setParam("wait_for_nodelets", "pose_ekf");
  EXPECT_EQ(Error("~no_manager"), "~wait_for_nodelets needs ~wait_for_manager (the manager they load into)");
}

TEST(SimPublisherParams, DefaultLayoutsAreRigModels) {
  SimPublisherConfig c;
  ASSERT_EQ(Error("~defaults", &c), "");
  EXPECT_EQ(c.layouts_dir, RIG_SIM_LAYOUTS_DIR);
  EXPECT_EQ(c.seed, 1);
}

TEST(SimPublisherParams, RefusesAnUnknownLookNamingTheKnownOnes) {
  ros::NodeHandle("~bad_look").setParam("look", "foggy");
  const std::string e = Error("~bad_look");
  EXPECT_NE(e.find("~look: unknown look 'foggy'; known: plain sunny"), std::string::npos) << e;
}

TEST(SimPublisherParams, RefusesAWrongTypeNamingIt) {
  ros::NodeHandle("~wrong_type").setParam("seed", 1.5);
  EXPECT_EQ(Error("~wrong_type"), "parameter ~seed must be an integer");
  ros::NodeHandle("~wrong_bool").setParam("loop", "yes");
  EXPECT_EQ(Error("~wrong_bool"), "parameter ~loop must be true or false");
}

TEST(SimPublisherParams, RefusesAMisspeltNameNamingTheNearest) {
  ros::NodeHandle("~misspelt").setParam("image_scal", 0.5);
  EXPECT_EQ(Error("~misspelt"), "parameter ~image_scal is unknown (did you mean ~image_scale?)");
}

TEST(SimPublisherParams, StillRefusesOutOfRangeValues) {
  ros::NodeHandle("~range").setParam("image_scale", 5.0);
  EXPECT_EQ(Error("~range"), "~image_scale must be in (0, 4]");
}

TEST(SimPublisherParams, EveryShippedLaunchParameterLoads) {
  int i = 0;
  // rig_sim's own sim.launch also passes ~look; the root one leaves it to the scenario, and adds the
  // graph's manager and nodelets to wait for (the nodelets by an $(eval) of its args: not resolved here).
  for (const auto& [file, count] : {std::make_pair(std::string(RIG_SIM_DIR) + "/launch/sim.launch", 10u),
                                    std::make_pair(std::string(RIG_SIM_DIR) + "/../../launch/sim.launch", 11u)}) {
    const auto params = rig_model::LaunchParams(file, "sim_node");
    EXPECT_EQ(params.size(), count) << file;
    const std::string ns = "~launch" + std::to_string(i++);
    rig_model::SetLaunchParams(ros::NodeHandle(ns), params);
    for (const auto& p : params) {
      EXPECT_TRUE(SimPublisherParams().Has(p.name)) << file << ": " << p.name;
      EXPECT_TRUE(p.resolved || p.name == "wait_for_nodelets") << file << ": " << p.name;
    }
    EXPECT_EQ(Error(ns), "") << file;
  }
}

}  // namespace
}  // namespace rig_sim

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_sim_params");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
