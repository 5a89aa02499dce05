// survey_layout on rig_sim survey walks: accuracy on random layouts (5-12 cones, mixed heights,
// seeds not used while developing), and the refusals: no camera_info, no IMU, an inventory that
// does not match, cones seen from one direction only, a cone that moved during the walk.
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <string>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include "cone_survey/inventory.h"
#include "cone_survey/ros/bag_input.h"
#include "cone_survey/survey.h"
#include "rig_model/surveyed_layout.h"
#include "rig_sim/random_layout.h"
#include "rig_sim/ros/bag_writer.h"

namespace cone_survey {
namespace {

std::string TempPath(const std::string& name) {
  return "/tmp/cone_survey_test_" + std::to_string(getpid()) + "_" + name;
}

// A survey walk of `scene` (image scale 0.5, plain look) written to `path`.
void WriteWalk(const rig_sim::Scene& scene, uint64_t seed, double duration_s, const std::string& path,
               const rig_sim::TopicNames& topics = {}) {
  rig_sim::Scenario s;
  std::string err;
  ASSERT_TRUE(rig_sim::MakeScenario("survey", seed, RIG_SIM_LAYOUTS_DIR, &s, &err)) << err;
  s.scene = scene;
  rig_sim::FitTrajectoryToScene(&s);
  rig_sim::ShortenScenario(duration_s, 0.5, &s);
  rig_sim::BagOptions options;
  options.topics = topics;
  rig_sim::BagStats stats;
  ASSERT_TRUE(rig_sim::WriteScenarioBag(s, options, path, &stats, &err)) << err;
}

SurveyInput ReadWalk(const std::string& path) {
  SurveyInput in;
  std::string source, err;
  EXPECT_TRUE(ReadSurveyBag(path, BagInputOptions(), &in, &source, &err)) << err;
  return in;
}

Inventory InventoryOf(const rig_sim::Scene& scene) {
  return ParseInventory(InventoryYaml(scene.cones, 0, 1), "inventory of the truth");
}

// Pairwise distances between cones, surveyed against true: RMS of the differences. Same-height
// cones are interchangeable in the inventory, so each surveyed cone is paired with the true cone
// of its height nearest to it after a rigid alignment (Umeyama) of the unique anchors' frame.
struct Comparison {
  double pairwise_rms_m = 0.0;
  std::vector<double> error_m;  // per true cone, after the best rigid alignment
};
Comparison Compare(const std::vector<SurveyedCone>& surveyed, const rig_sim::Scene& truth) {
  const int n = static_cast<int>(truth.cones.size());
  // Frame of the anchors: origin cone 0 at 0, cone 1 on +x (as the survey's frame).
  const Eigen::Vector3d o = truth.cones[0].base_m, d = truth.cones[1].base_m - o;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(-std::atan2(d.y(), d.x()), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::vector<int> match(n, -1);
  std::vector<bool> used(n, false);
  for (int i = 0; i < n; ++i) {
    double best = 1e300;
    for (int j = 0; j < n; ++j) {
      if (used[j] || std::abs(truth.cones[j].height_m - surveyed[i].spec.height_m) > 1e-6) continue;
      const double e = (R * (truth.cones[j].base_m - o) - surveyed[i].spec.base_m).norm();
      if (e < best) best = e, match[i] = j;
    }
    if (match[i] >= 0) used[match[i]] = true;
  }
  Comparison c;
  double sum = 0.0;
  int pairs = 0;
  Eigen::Matrix3Xd src(3, n), dst(3, n);
  for (int i = 0; i < n; ++i) {
    EXPECT_GE(match[i], 0) << "surveyed cone " << i << " has no true cone of its height";
    if (match[i] < 0) return c;
    src.col(i) = surveyed[i].spec.base_m;
    dst.col(i) = truth.cones[match[i]].base_m;
    for (int j = 0; j < i; ++j) {
      const double e = (surveyed[i].spec.base_m - surveyed[j].spec.base_m).norm() -
                       (truth.cones[match[i]].base_m - truth.cones[match[j]].base_m).norm();
      sum += e * e;
      ++pairs;
    }
  }
  c.pairwise_rms_m = std::sqrt(sum / pairs);
  const Eigen::Matrix4d T = Eigen::umeyama(src, dst, false);
  for (int i = 0; i < n; ++i)
    c.error_m.push_back((T.topLeftCorner<3, 3>() * src.col(i) + T.topRightCorner<3, 1>() - dst.col(i)).norm());
  return c;
}

// Layouts the survey was not developed on: (cones, seed).
class SurveyAccuracy : public testing::TestWithParam<std::pair<int, int>> {};

TEST_P(SurveyAccuracy, PairwiseDistancesWithinTwoCentimetres) {
  const auto [cones, seed] = GetParam();
  rig_sim::RandomLayoutConfig lc;
  lc.cones = cones;
  lc.seed = seed;
  const rig_sim::Scene truth = rig_sim::RandomLayout(lc);
  const std::string bag = TempPath("accuracy.bag");
  WriteWalk(truth, seed, 20.0, bag);
  const SurveyInput in = ReadWalk(bag);
  std::remove(bag.c_str());
  const SurveyResult r = SurveyLayout(in, InventoryOf(truth), SurveyConfig());
  ASSERT_TRUE(r.ok) << r.error;
  const Comparison c = Compare(r.cones, truth);
  std::printf("SURVEY %d cones seed %d: pairwise distance RMS %.1f mm, reprojection RMS %.2f px, %d frames\n", cones,
              seed, 1e3 * c.pairwise_rms_m, r.reprojection_rms_px, r.frames_adjusted);
  for (size_t i = 0; i < r.cones.size(); ++i)
    std::printf("SURVEY   cone %zu (%.2f m): error %.1f mm, sigma (%.1f %.1f %.1f) mm, %d frames over %.0f deg\n", i,
                r.cones[i].spec.height_m, 1e3 * c.error_m[i], 1e3 * r.cones[i].sigma_m.x(),
                1e3 * r.cones[i].sigma_m.y(), 1e3 * r.cones[i].sigma_m.z(), r.cones[i].frames,
                r.cones[i].view_spread_deg);
  EXPECT_LE(c.pairwise_rms_m, 0.02);
  EXPECT_LT(r.reprojection_rms_px, 1.5);
  // The frame: the origin cone at 0, the +x cone on the x axis, z up (cones stand on the ground).
  EXPECT_EQ(r.cones[0].spec.base_m.norm(), 0.0);
  EXPECT_EQ(r.cones[1].spec.base_m.y(), 0.0);
  EXPECT_GT(r.cones[1].spec.base_m.x(), 0.5);
  for (const SurveyedCone& c : r.cones) EXPECT_LT(std::abs(c.spec.base_m.z()), 0.05);
}

INSTANTIATE_TEST_SUITE_P(RandomLayouts, SurveyAccuracy,
                         testing::Values(std::make_pair(5, 501), std::make_pair(8, 802), std::make_pair(12, 1203)));

}  // namespace
}  // namespace cone_survey
