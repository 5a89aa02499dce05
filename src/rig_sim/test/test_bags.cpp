#include <gtest/gtest.h>

#include <unistd.h>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include "rig_sim/ros/bag_reader.h"
#include "rig_sim/ros/bag_writer.h"
#include "test_util.h"

namespace rig_sim {
namespace {

std::string TempPath(const std::string& name) {
  return "/tmp/rig_sim_test_" + std::to_string(getpid()) + "_" + name + ".bag";
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string WriteShort(const std::string& scenario, uint64_t seed, double duration_s, const std::string& tag,
                       BagOptions opt = BagOptions()) {
  const Scenario s = TestScenario(scenario, seed, duration_s, 0.125);
  const std::string path = TempPath(tag);
  std::string err;
  EXPECT_TRUE(WriteScenarioBag(s, opt, path, nullptr, &err)) << err;
  return path;
}

ValidationReport Validate(const std::string& path) {
  BagContents c;
  std::string err;
  EXPECT_TRUE(ReadBagContents(path, TopicNames(), &c, &err)) << err;
  return ValidateContents(c, ValidateConfig());
}

}  // namespace

TEST(Bags, SameSeedGivesAnIdenticalBagOtherSeedDoesNot) {
  const std::string a = WriteShort("handheld", 11, 1.0, "a"), b = WriteShort("handheld", 11, 1.0, "b");
  const std::string c = WriteShort("handheld", 12, 1.0, "c");
  const std::string da = ReadFile(a);
  EXPECT_GT(da.size(), 100000u);
  EXPECT_TRUE(da == ReadFile(b));
  EXPECT_FALSE(da == ReadFile(c));
  for (const auto& p : {a, b, c}) std::remove(p.c_str());
}

TEST(Bags, EveryConnectionCarriesTypeAndMd5SoRosbagPlayAcceptsIt) {
  const std::string path = WriteShort("still", 2, 0.5, "conn");
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  rosbag::View view(bag);
  int latched = 0;
  for (const rosbag::ConnectionInfo* c : view.getConnections()) {
    EXPECT_FALSE(c->datatype.empty()) << c->topic;
    EXPECT_EQ(c->md5sum.size(), 32u) << c->topic;
    EXPECT_FALSE(c->msg_def.empty()) << c->topic;
    ASSERT_TRUE(c->header);
    if (c->header->count("latching") && c->header->at("latching") == "1") {
      ++latched;
      EXPECT_EQ(c->header->at("md5sum"), c->md5sum) << c->topic;
    }
  }
  EXPECT_EQ(latched, 2);  // /tf_static and the cone markers
  bag.close();
  std::remove(path.c_str());
}

TEST(Bags, ValidatorPassesOnEveryScenario) {
  for (const ScenarioInfo& info : ListScenarios()) {
    const std::string path = WriteShort(info.name, 3, 2.5, info.name);
    const ValidationReport r = Validate(path);
    EXPECT_TRUE(r.ok()) << info.name << "\n" << r.Text();
    std::remove(path.c_str());
  }
}

TEST(Bags, ValidatorFailsOnAHalfSecondImuGap) {
  const std::string path = WriteShort("handheld", 3, 3.0, "full");
  const std::string cut = TempPath("gap");
  {
    rosbag::Bag in(path, rosbag::bagmode::Read), out(cut, rosbag::bagmode::Write);
    for (const rosbag::MessageInstance& m : rosbag::View(in)) {
      const double t = (m.getTime() - ros::Time(1700000000)).toSec();
      if (m.getTopic() == "imu/data_raw" && t > 1.0 && t < 1.5) continue;  // drop 0.5 s of IMU
      out.write(m.getTopic(), m.getTime(), m, m.getConnectionHeader());
    }
  }
  EXPECT_TRUE(Validate(path).ok());
  const ValidationReport r = Validate(cut);
  EXPECT_FALSE(r.ok());
  // The last sample before the cut covers (0.99, 1.00] s and is stamped at its midpoint (REP-145).
  EXPECT_NE(r.Text().find("FAIL imu/data_raw gaps: gap of 0.500 s after t=0.995 s"), std::string::npos) << r.Text();
  std::remove(path.c_str());
  std::remove(cut.c_str());
}

TEST(Bags, CameraDelayDeliversFramesLateInRigOrder) {
  BagOptions opt;
  opt.stream.camera_delay_s = 0.045;
  const std::string path = WriteShort("shake", 5, 1.0, "delay", opt);
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  int images = 0;
  double last_bag_time = 0.0;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    EXPECT_GE(m.getTime().toSec(), last_bag_time);
    last_bag_time = m.getTime().toSec();
    if (m.getTopic() != "camera/image_raw") continue;
    const auto img = m.instantiate<sensor_msgs::Image>();
    ASSERT_TRUE(img);
    EXPECT_NEAR((m.getTime() - img->header.stamp).toSec(), 0.045, 1e-9);
    EXPECT_NEAR((img->header.stamp - ros::Time(1700000000)).toSec() * 30.0, images, 1e-6);  // exposure stamps
    ++images;
  }
  EXPECT_EQ(images, 30);
  bag.close();
  EXPECT_TRUE(Validate(path).ok());
  std::remove(path.c_str());
}

}  // namespace rig_sim
