// Real photos (../shared/data/images/fsoco_site, Formula Student cones): runs
// `detect_cones --config photos` on them, as a user would, and checks the
// counts against what the photos show (counted by eye; the folder's labels
// are drawn into example images, not machine-readable). Skips when absent.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <cstdio>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "test_files.h"

namespace {

std::string PhotoDir() {
  return cone_tracker::SharedDataDir("images/fsoco_site", "fsg__cone.png", "CONE_TRACKER_PHOTO_DIR");
}

struct Expect {
  int min_found, max_found;  // accepted cones
};

}  // namespace

TEST(Photos, DetectConesOnFsocoPhotos) {
  const std::string dir = PhotoDir();
  if (dir.empty()) GTEST_SKIP() << "../shared/data/images/fsoco_site not found: real-photo test skipped";
  // Orange (and red-white FSG) cones seen in each photo; yellow- and
  // blue-only photos must give none.
  const std::map<std::string, Expect> expect = {
      {"fsg__cone.png", {0, 0}},                        // one yellow cone
      {"fsg__fsg_cone.png", {0, 0}},                    // one yellow cone
      {"fsg__HD__fsg_yellow_cones.jpg", {0, 0}},        // yellow cones
      {"labels__box-truncated.png", {0, 0}},            // blue cone
      {"labels__box-base-plate.png", {0, 0}},           // blue cone
      {"overview__ff.jpg", {0, 0}},                     // blue and yellow cones
      {"labels__class-large-orange.png", {1, 1}},       // one large orange cone
      {"overview__amz.png", {1, 3}},                    // one near orange cone, distant ones ~20 px tall
      {"fsg__HD__fsg_laptop.jpg", {2, 3}},              // two red-white cones
      {"fsg__HD__fsg_2nd_run.jpg", {2, 10}},            // two red-white cones, orange print on the sign
      {"fsg__HD__fsg_acceleration_track.jpg", {3, 7}},  // four red-white cones near; the DNN finds 3
  };
  std::string cmd = std::string(DETECT_CONES_EXE) + " --config photos --output /tmp/cone_tracker_photos.jsonl";
  for (const auto& [name, e] : expect) cmd += " " + dir + "/" + name;
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream in("/tmp/cone_tracker_photos.jsonl");
  std::string line;
  int lines = 0;
  while (std::getline(in, line)) {
    const nlohmann::json j = nlohmann::json::parse(line);
    const std::string path = j["image"];
    const std::string name = path.substr(path.rfind('/') + 1);
    ASSERT_FALSE(j.contains("error")) << name << ": " << j["error"];
    const int found = int(j["cones"].size());
    std::printf("%-40s %d cones\n", name.c_str(), found);
    const Expect& e = expect.at(name);
    EXPECT_GE(found, e.min_found) << name;
    EXPECT_LE(found, e.max_found) << name;
    if (name == "labels__class-large-orange.png" && found == 1) {  // the whole cone, not a stripe of it
      EXPECT_GT(j["cones"][0]["bbox"][3].get<double>(), 200.0);
    }
    ++lines;
  }
  EXPECT_EQ(lines, int(expect.size()));
}

// detect_cones's config files (no photos needed): the shipped one loads, a misspelt key is refused
// with the file, line and nearest field, and the tool exits with status 2.
std::string RunDetectCones(const std::string& config, int* status) {
  const std::string out = ::testing::TempDir() + "cone_tracker_detect_cones_config.txt";
  const std::string cmd = std::string(DETECT_CONES_EXE) + " --config " + config + " --output " + ::testing::TempDir() +
                          "cone_tracker_detect_cones.jsonl /nonexistent.png 2>" + out;
  *status = std::system(cmd.c_str());
  std::ifstream in(out);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(DetectConesConfig, ShippedLoadsAndMisspeltKeyIsRefused) {
  int status = -1;
  RunDetectCones("photos", &status);
  // The config loads: the exit status is 1, for the unreadable image, not 2 (a bad config).
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 1) << status;
  const std::string path = ::testing::TempDir() + "cone_tracker_misspelt_photos.yaml";
  std::ofstream(path) << "sat_min: 0.5\nsat_maxx: 1.0\n";
  std::string err = RunDetectCones(path, &status);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 2) << status;
  EXPECT_NE(err.find(path + ":2: unknown key 'sat_maxx' (did you mean 'sat_max'?)"), std::string::npos) << err;
  // The keys are the nodelet's parameters, hue in degrees: the radians of old are refused.
  std::ofstream(path) << "hue_min_rad: 5.93\n";
  err = RunDetectCones(path, &status);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 2) << status;
  EXPECT_NE(err.find(path + ":1: unknown key 'hue_min_rad' (did you mean 'hue_min_deg'?)"), std::string::npos) << err;
  std::ofstream(path) << "hue_min_deg: 340\npeak_refinement: 7\n";
  err = RunDetectCones(path, &status);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 2) << status;
  EXPECT_NE(err.find(path + ":2: peak_refinement: must be one of outline, templates, none"), std::string::npos) << err;
  std::ofstream(path) << "max_area_px: .inf\n";
  err = RunDetectCones(path, &status);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 2) << status;
  EXPECT_NE(err.find(path + ":1: max_area_px: must be finite"), std::string::npos) << err;
}
