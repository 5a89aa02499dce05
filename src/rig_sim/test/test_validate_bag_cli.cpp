// validate_bag as a user runs it: exit status and one stderr line per problem, on a bag
// cut short (as a killed recorder or a partial copy leaves it), a missing file and bad arguments.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

#include "rig_sim/ros/bag_reader.h"
#include "rig_sim/ros/bag_writer.h"
#include "test_util.h"

namespace rig_sim {
namespace {

std::string TempPath(const std::string& name) {
  return "/tmp/rig_sim_cli_test_" + std::to_string(getpid()) + "_" + name;
}

struct ToolRun {
  int status = -1;
  std::string err;
};

ToolRun RunValidateBag(const std::string& args) {
  const std::string err_path = TempPath("stderr.txt");
  const std::string cmd = std::string(VALIDATE_BAG_EXE) + " " + args + " >/dev/null 2>" + err_path;
  const int raw = std::system(cmd.c_str());
  ToolRun r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  std::ifstream in(err_path);
  r.err.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  std::remove(err_path.c_str());
  return r;
}

std::string WriteBag(const std::string& tag) {
  const std::string path = TempPath(tag + ".bag");
  std::string err;
  EXPECT_TRUE(WriteScenarioBag(TestScenario("still", 3, 0.5, 0.125), BagOptions(), path, nullptr, &err)) << err;
  return path;
}

void CutTo(const std::string& from, const std::string& to, double fraction) {
  std::ifstream in(from, std::ios::binary);
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(data.size(), 1000u);
  std::ofstream(to, std::ios::binary).write(data.data(), std::streamsize(double(data.size()) * fraction));
}

TEST(ValidateBagCli, GoodBagExitsZero) {
  const std::string path = WriteBag("good");
  const ToolRun r = RunValidateBag(path);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err, "");
  std::remove(path.c_str());
}

TEST(ValidateBagCli, TruncatedBagSaysTruncatedAndSuggestsReindex) {
  const std::string path = WriteBag("whole"), cut = TempPath("cut.bag");
  CutTo(path, cut, 0.6);
  const ToolRun r = RunValidateBag(cut);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("validate_bag: reading '" + cut + "': the bag is truncated"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("rosbag reindex " + cut), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  // The library says the same to its other callers.
  BagContents c;
  std::string err;
  EXPECT_FALSE(ReadBagContents(cut, TopicNames(), &c, &err));
  EXPECT_NE(err.find("truncated"), std::string::npos) << err;
  std::remove(path.c_str());
  std::remove(cut.c_str());
}

TEST(ValidateBagCli, MissingOrNotABagExitsOneNamingTheFile) {
  const std::string missing = TempPath("missing.bag");
  ToolRun r = RunValidateBag(missing);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find(missing), std::string::npos) << r.err;
  const std::string text = TempPath("text.bag");
  std::ofstream(text) << "not a bag\n";
  r = RunValidateBag(text);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find(text), std::string::npos) << r.err;
  std::remove(text.c_str());
}

TEST(ValidateBagCli, BadArgumentsExitTwo) {
  ToolRun r = RunValidateBag("");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("give a bag file"), std::string::npos) << r.err;
  r = RunValidateBag("x.bag --imu-rate fast");  // used to abort in std::stod
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--imu-rate needs a positive number, got 'fast'"), std::string::npos) << r.err;
}

TEST(ValidateBagCli, FailedChecksAreNamedOnStderr) {
  const std::string path = WriteBag("rates");
  const ToolRun r = RunValidateBag(path + " --imu-rate 50");  // the bag's IMU runs at 100 Hz
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("validate_bag: " + path + ": imu/data_raw"), std::string::npos) << r.err;
  std::remove(path.c_str());
}

}  // namespace
}  // namespace rig_sim
