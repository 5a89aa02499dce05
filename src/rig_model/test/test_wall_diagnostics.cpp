// WallDiagnostics with a master: /diagnostics keep arriving after sim time jumps back (where
// diagnostic_updater's own update() stops until sim time passes its old deadline), and a refused
// configuration is published as ERROR. The test drives /clock itself; every wait is bounded by a
// number of loop iterations, not by an amount of wall time that must pass.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>

#include <functional>
#include <map>

#include "rig_model/ros/diagnostics.h"

namespace rig_model {
namespace {

struct Listener {
  std::map<std::string, diagnostic_msgs::DiagnosticStatus> last;  // by status name
  std::map<std::string, int> count;
  void OnDiagnostics(const diagnostic_msgs::DiagnosticArrayConstPtr& msg) {
    for (const auto& s : msg->status) {
      last[s.name] = s;
      ++count[s.name];
    }
  }
};

class WallDiagnosticsTest : public ::testing::Test {
 protected:
  ros::NodeHandle nh_;
  ros::Publisher clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
  Listener listener_;
  ros::Subscriber sub_ = nh_.subscribe("/diagnostics", 100, &Listener::OnDiagnostics, &listener_);

  void SetClock(double t_s) {
    rosgraph_msgs::Clock c;
    c.clock = ros::Time(t_s);
    for (int i = 0; i < 2000 && ros::Time::now() != c.clock; ++i) {
      clock_pub_.publish(c);
      ros::WallDuration(0.005).sleep();
      ros::spinOnce();
    }
    ASSERT_EQ(ros::Time::now(), c.clock) << "/clock did not reach the test's own time";
  }
  // Spins until pred holds; at most `iterations` rounds of 10 ms, each first calling `each`.
  bool SpinUntil(const std::function<bool()>& pred, int iterations = 6000, const std::function<void()>& each = {}) {
    for (int i = 0; i < iterations && !pred(); ++i) {
      if (each) each();
      ros::WallDuration(0.01).sleep();
      ros::spinOnce();
    }
    return pred();
  }
  // Sim time running on: +step_s per call.
  std::function<void()> Advance(double* t_s, double step_s) {
    return [this, t_s, step_s] {
      *t_s += step_s;
      rosgraph_msgs::Clock c;
      c.clock = ros::Time(*t_s);
      clock_pub_.publish(c);
    };
  }
};

TEST_F(WallDiagnosticsTest, KeepsPublishingAfterSimTimeJumpsBack) {
  SetClock(100.0);
  ros::NodeHandle pnh("~looping");
  WallDiagnostics diagnostics(nh_, pnh, "/looping", "test", 0.05);
  int ticks = 0;
  diagnostics.Add("counter", [&](diagnostic_updater::DiagnosticStatusWrapper& s) {
    s.summary(diagnostic_msgs::DiagnosticStatus::OK, "ok");
    s.add("ticks", ++ticks);
  });
  double t_s = 100.0;
  ASSERT_TRUE(SpinUntil([&] { return listener_.count["looping: counter"] >= 3; }, 6000, Advance(&t_s, 0.01)));

  // 90 s back, then sim time runs on but stays below 100 s within the bound (1000 x 0.05 s): the
  // Updater's own update() would publish nothing here, its deadline being past 100 s.
  SetClock(10.0);
  t_s = 10.0;
  const int before = listener_.count["looping: counter"];
  EXPECT_TRUE(SpinUntil([&] { return listener_.count["looping: counter"] >= before + 5; }, 1000, Advance(&t_s, 0.05)))
      << "no /diagnostics after the jump back: " << listener_.count["looping: counter"] - before;
  EXPECT_EQ(listener_.last["looping: counter"].level, diagnostic_msgs::DiagnosticStatus::OK);
}

TEST_F(WallDiagnosticsTest, RefusedConfigStaysAsErrorNamingTheParameter) {
  ros::NodeHandle pnh("~refusing");
  WallDiagnostics diagnostics(nh_, pnh, "/refusing", "test", 0.05);
  diagnostics.Add("filter", [](diagnostic_updater::DiagnosticStatusWrapper& s) {
    s.summary(diagnostic_msgs::DiagnosticStatus::OK, "tracking");
  });
  diagnostics.Add("other task", [](diagnostic_updater::DiagnosticStatusWrapper& s) {
    s.summary(diagnostic_msgs::DiagnosticStatus::OK, "fine");
  });
  const std::string message =
      diagnostics.RefuseConfig("filter", "pose_ekf", "invalid parameter: sigma_gyro_rad_s must be > 0 (got -0.01); ");
  EXPECT_EQ(message, "pose_ekf not started: invalid parameter: sigma_gyro_rad_s must be > 0 (got -0.01)");
  // The placeholders Updater::add() published before the refusal are in the queue ahead of it.
  ASSERT_TRUE(SpinUntil([&] {
    return listener_.last.count("refusing: filter") &&
           listener_.last["refusing: filter"].level == diagnostic_msgs::DiagnosticStatus::ERROR;
  }));
  listener_.count.clear();
  ASSERT_TRUE(SpinUntil([&] { return listener_.count["refusing: filter"] >= 3; }));
  const auto& s = listener_.last["refusing: filter"];
  EXPECT_EQ(s.level, diagnostic_msgs::DiagnosticStatus::ERROR);
  EXPECT_EQ(s.message, message);
  ASSERT_FALSE(s.values.empty());
  EXPECT_EQ(s.values[0].value, pnh.getNamespace());
  EXPECT_EQ(listener_.count.count("refusing: other task"), 0u) << "the refused component's other tasks went on";
}

}  // namespace
}  // namespace rig_model

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "wall_diagnostics_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
