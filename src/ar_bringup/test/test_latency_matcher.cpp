#include <gtest/gtest.h>

#include "ar_bringup/latency_matcher.h"

namespace ar_bringup {
namespace {

TEST(Quantile, NearestRank) {
  EXPECT_DOUBLE_EQ(Quantile({}, 0.5), 0.0);
  EXPECT_DOUBLE_EQ(Quantile({3.0, 1.0, 2.0}, 0.5), 2.0);
  std::vector<double> v;
  for (int i = 1; i <= 100; ++i) v.push_back(i);
  EXPECT_DOUBLE_EQ(Quantile(v, 0.99), 99.0);
  EXPECT_DOUBLE_EQ(Quantile(v, 1.0), 100.0);
  EXPECT_DOUBLE_EQ(Quantile(v, 0.0), 1.0);
}

TEST(LatencyMatcher, FrameToFirstTfAfterItsPose) {
  LatencyMatcher m;
  m.OnImage(1000, 10.000);
  m.OnTf(900, 10.001);  // older state: not this frame
  EXPECT_TRUE(m.end_to_end_ms().empty());
  m.OnTf(1000, 10.0015);  // before the tracker's pose arrived: cannot contain the frame
  EXPECT_TRUE(m.end_to_end_ms().empty());
  m.OnPose(1000, 10.002);
  ASSERT_EQ(m.tracker_ms().size(), 1u);
  EXPECT_NEAR(m.tracker_ms()[0], 2.0, 1e-9);
  m.OnTf(1100, 10.004);  // a newer stamp (the next IMU sample) carries it too
  ASSERT_EQ(m.end_to_end_ms().size(), 1u);
  EXPECT_NEAR(m.end_to_end_ms()[0], 4.0, 1e-9);
  m.OnTf(1200, 10.005);  // counted once
  EXPECT_EQ(m.end_to_end_ms().size(), 1u);
}

TEST(LatencyMatcher, PoseWithoutFrameAndRejectedFrames) {
  LatencyMatcher m(2);
  m.OnPose(5, 1.0);
  EXPECT_EQ(m.unmatched_poses(), 1u);
  m.OnImage(10, 1.0);  // rejected by the tracker: never a pose
  m.OnImage(20, 1.1);
  m.OnImage(30, 1.2);  // evicts stamp 10
  m.OnPose(10, 1.3);
  EXPECT_EQ(m.unmatched_poses(), 2u);
  m.OnPose(30, 1.21);
  m.OnTf(40, 1.22);
  ASSERT_EQ(m.end_to_end_ms().size(), 1u);
  EXPECT_NEAR(m.end_to_end_ms()[0], 20.0, 1e-9);
}

}  // namespace
}  // namespace ar_bringup
