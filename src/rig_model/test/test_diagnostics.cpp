// StampRateTask and CleanReason without a master: the wall clock is injected.
#include <gtest/gtest.h>

#include <map>

#include "rig_model/ros/diagnostics.h"

namespace rig_model {
namespace {

using diagnostic_msgs::DiagnosticStatus;

struct Report {
  int level = -1;
  std::string message;
  std::map<std::string, std::string> values;
};

Report Evaluate(StampRateTask& task) {
  diagnostic_updater::DiagnosticStatusWrapper stat;
  task.run(stat);
  Report r;
  r.level = stat.level;
  r.message = stat.message;
  for (const auto& kv : stat.values) r.values[kv.key] = kv.value;
  return r;
}

class RateTest : public ::testing::Test {
 protected:
  double wall_s_ = 100.0;
  RateCheckConfig config_ = RateCheckConfig::Around(100.0, 0.1);
  StampRateTask task_{"imu", config_, [this] { return wall_s_; }};

  // n messages at hz (stamp time) starting at stamp t0, delivered at wall_rate times real time.
  void Feed(double t0, int n, double hz, double wall_per_stamp_s = 1.0) {
    for (int i = 0; i < n; ++i) {
      task_.Tick(t0 + i / hz);
      wall_s_ += wall_per_stamp_s / hz;
    }
  }
};

TEST(CleanReason, DropsEmptyClausesAndTrailingSeparators) {
  EXPECT_EQ(CleanReason("sigma_gyro_rad_s must be > 0 (got -0.01); "), "sigma_gyro_rad_s must be > 0 (got -0.01)");
  EXPECT_EQ(CleanReason("a must be > 0; ; b must be set;  ;"), "a must be > 0; b must be set");
  EXPECT_EQ(CleanReason("  plain reason \n"), "plain reason");
  EXPECT_EQ(CleanReason(""), "");
}

TEST_F(RateTest, NoMessageYetWarnsThenGoesStale) {
  EXPECT_EQ(Evaluate(task_).level, DiagnosticStatus::WARN);
  wall_s_ += config_.stale_after_s + 0.5;
  const Report r = Evaluate(task_);
  EXPECT_EQ(r.level, DiagnosticStatus::ERROR);
  EXPECT_NE(r.message.find("no message yet"), std::string::npos) << r.message;
}

TEST_F(RateTest, MeasuresTheRateOfStamps) {
  Feed(1.7e9, 300, 100.0);
  EXPECT_NEAR(task_.rate_hz(), 100.0, 1e-6);
  const Report r = Evaluate(task_);
  EXPECT_EQ(r.level, DiagnosticStatus::OK) << r.message;
  EXPECT_EQ(r.values.at("rate of stamps (Hz)"), "100.000");
}

TEST_F(RateTest, PlaybackSpeedDoesNotChangeTheStampRate) {
  Feed(50.0, 200, 100.0, /*wall_per_stamp_s=*/0.25);  // rosbag play -r 4: stamps still 100 Hz apart
  EXPECT_NEAR(task_.rate_hz(), 100.0, 1e-6);
  EXPECT_EQ(Evaluate(task_).level, DiagnosticStatus::OK);
}

TEST_F(RateTest, TooLowAndTooHigh) {
  Feed(10.0, 100, 50.0);
  Report r = Evaluate(task_);
  EXPECT_EQ(r.level, DiagnosticStatus::WARN);
  EXPECT_NE(r.message.find("too low"), std::string::npos) << r.message;
  StampRateTask fast("fast", config_, [this] { return wall_s_; });
  for (int i = 0; i < 100; ++i) fast.Tick(10.0 + i / 200.0);
  diagnostic_updater::DiagnosticStatusWrapper stat;
  fast.run(stat);
  EXPECT_EQ(stat.level, DiagnosticStatus::WARN);
  EXPECT_NE(stat.message.find("too high"), std::string::npos) << stat.message;
}

TEST_F(RateTest, OnlyTheLastWindowCounts) {
  Feed(10.0, 500, 20.0);   // 25 s at 20 Hz
  Feed(35.0, 500, 100.0);  // then 5 s at 100 Hz: the 5 s window holds only these
  EXPECT_NEAR(task_.rate_hz(), 100.0, 1.0);
}

TEST_F(RateTest, RecoversAfterAJumpBack) {
  Feed(1000.0, 500, 100.0);
  Feed(992.0, 50, 100.0);  // bag loop: 8 s back
  EXPECT_EQ(task_.jumps_back(), 1u);
  EXPECT_NEAR(task_.rate_hz(), 100.0, 1e-6);  // only the new time line's stamps
  const Report r = Evaluate(task_);
  EXPECT_EQ(r.level, DiagnosticStatus::OK) << r.message;
  EXPECT_EQ(r.values.at("stamp jumps back"), "1");
}

TEST_F(RateTest, SlightlyLateStampsAreNotAJump) {
  task_.Tick(10.00);
  task_.Tick(10.02);
  task_.Tick(10.01);  // a late frame, out of order
  task_.Tick(10.03);
  EXPECT_EQ(task_.jumps_back(), 0u);
  EXPECT_NEAR(task_.rate_hz(), 3.0 / 0.03, 1e-6);
}

TEST_F(RateTest, StaleWhenMessagesStopInWallTime) {
  config_.stale_level = DiagnosticStatus::WARN;
  StampRateTask optional("camera", config_, [this] { return wall_s_; });
  for (int i = 0; i < 20; ++i) optional.Tick(5.0 + i * 0.01);
  diagnostic_updater::DiagnosticStatusWrapper ok, stale;
  optional.run(ok);
  EXPECT_EQ(ok.level, DiagnosticStatus::OK) << ok.message;
  wall_s_ += 3.0;  // sim time may be paused; the input is silent all the same
  optional.run(stale);
  EXPECT_EQ(stale.level, DiagnosticStatus::WARN);
  EXPECT_NE(stale.message.find("no message for 3.0 s"), std::string::npos) << stale.message;
}

TEST_F(RateTest, UnstampedMessagesAreCountedNotRated) {
  task_.Tick(ros::Time(0));
  task_.Tick(0.0);
  const Report r = Evaluate(task_);
  EXPECT_EQ(r.level, DiagnosticStatus::WARN);
  EXPECT_EQ(r.values.at("messages without a stamp"), "2");
  EXPECT_EQ(r.values.at("rate measured"), "False");
}

TEST_F(RateTest, OneMessageIsNotARate) {
  task_.Tick(5.0);
  const Report r = Evaluate(task_);
  EXPECT_EQ(r.level, DiagnosticStatus::OK) << r.message;
  EXPECT_EQ(r.values.at("rate measured"), "False");
}

}  // namespace
}  // namespace rig_model
