// SolvePnpRansac (ransac.h): matches with outliers, drawn and real (../shared/data/pnp/sqpnp_robust).
#include <fstream>
#include <sstream>

#include "cone_tracker/pose/ransac.h"
#include "pnp_json.h"
#include "test_files.h"
#include "test_util.h"

namespace cone_tracker {
namespace {

// A random cloud's pixels with 0.5 px noise, and `outliers` of them replaced by pixels anywhere in the image.
struct Contaminated {
  sim::Case k;
  std::vector<Eigen::Vector2d> image;
  std::vector<char> outlier;
};

Contaminated Contaminate(unsigned seed, int points, int outliers) {
  std::mt19937 rng(seed);
  Contaminated c{sim::RandomCloud(rng, points), {}, std::vector<char>(size_t(points), 0)};
  std::normal_distribution<double> noise(0.0, 0.5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  c.image = c.k.image;
  for (Eigen::Vector2d& p : c.image) p += Eigen::Vector2d(noise(rng), noise(rng));
  for (int i = 0; i < outliers; ++i) {
    const size_t j = size_t(i * points / outliers);
    c.outlier[j] = 1;
    c.image[j] = Eigen::Vector2d(u(rng) * c.k.camera.width_px, u(rng) * c.k.camera.height_px);
  }
  return c;
}

TEST(Ransac, FindsThePoseAndTheOutliersOfADrawnCloud) {
  const Contaminated c = Contaminate(5, 60, 18);  // 30 % outliers
  const RansacPnpResult r = SolvePnpRansac(c.k.camera, c.k.model, c.image, PnpOptions(), RansacOptions());
  ASSERT_TRUE(r.pnp.ok) << r.pnp.error;
  int wrong = 0;
  for (size_t i = 0; i < c.outlier.size(); ++i) wrong += bool(r.inlier[i]) == bool(c.outlier[i]);
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(r.num_inliers, 42);
  EXPECT_EQ(r.pnp.residuals_px.size(), 42u);
  // The same pose as SolvePnp on the true inliers alone.
  std::vector<Eigen::Vector3d> m;
  std::vector<Eigen::Vector2d> p;
  for (size_t i = 0; i < c.outlier.size(); ++i)
    if (!c.outlier[i]) m.push_back(c.k.model[i]), p.push_back(c.image[i]);
  const PnpResult oracle = SolvePnp(c.k.camera, m, p, PnpOptions());
  ASSERT_TRUE(oracle.ok) << oracle.error;
  EXPECT_TRUE(PoseNear(r.pnp.T_camera_model, oracle.T_camera_model, 1e-6));
  EXPECT_TRUE(PoseNear(r.pnp.T_camera_model, c.k.T_camera_model, 0.01));
  // Without it, the outliers pull the pose far off.
  const PnpResult plain = SolvePnp(c.k.camera, c.k.model, c.image, PnpOptions());
  EXPECT_TRUE(!plain.ok || plain.reproj_rms_px > 20.0) << plain.reproj_rms_px;
}

TEST(Ransac, RefusesWhatItCannotSolve) {
  const Contaminated c = Contaminate(6, 10, 0);
  const std::vector<Eigen::Vector3d> three(c.k.model.begin(), c.k.model.begin() + 3);
  const std::vector<Eigen::Vector2d> three_px(c.image.begin(), c.image.begin() + 3);
  EXPECT_EQ(SolvePnpRansac(c.k.camera, three, three_px, PnpOptions(), RansacOptions()).pnp.error,
            "RANSAC needs at least 4 points, got 3");
  RansacOptions zero;
  zero.threshold_px = 0.0;
  EXPECT_FALSE(SolvePnpRansac(c.k.camera, c.k.model, c.image, PnpOptions(), zero).pnp.ok);
  std::vector<Eigen::Vector2d> nan = c.image;
  nan[4].x() = NAN;
  EXPECT_EQ(SolvePnpRansac(c.k.camera, c.k.model, nan, PnpOptions(), RansacOptions()).pnp.error,
            "point 4 is not finite (NaN or inf)");
}

TEST(Ransac, JsonCaseListsTheOutliers) {
  const Contaminated c = Contaminate(7, 40, 8);
  nlohmann::json in;
  in["K"] = {c.k.camera.fx_px, c.k.camera.fy_px, c.k.camera.cx_px, c.k.camera.cy_px};
  for (const Eigen::Vector3d& m : c.k.model) in["model"].push_back({m.x(), m.y(), m.z()});
  for (const Eigen::Vector2d& p : c.image) in["image"].push_back({p.x(), p.y()});
  const RansacOptions ransac;
  const nlohmann::ordered_json out = SolveJsonCase(in, PnpOptions(), &ransac);
  ASSERT_TRUE(out["ok"].get<bool>()) << out.dump();
  EXPECT_EQ(out["inliers"].get<int>(), 32);
  std::vector<int> expected;
  for (size_t i = 0; i < c.outlier.size(); ++i)
    if (c.outlier[i]) expected.push_back(int(i));
  EXPECT_EQ(out["outliers"].get<std::vector<int>>(), expected);
  in["init"] = {{"q", {1, 0, 0, 0}}, {"t", {0, 0, 4}}};
  const nlohmann::ordered_json refused = SolveJsonCase(in, PnpOptions(), &ransac);
  EXPECT_FALSE(refused["ok"].get<bool>());
  EXPECT_EQ(refused["error"].get<std::string>(), "bad input: init is not used with RANSAC: give one or the other");
}

// SQPnP's robust example (891 real matches with outliers, K.txt: fx 2980, fy 3000, cx 600, cy 450; the data
// README: a RANSAC PnP with a 3 px threshold finds about 710 inliers at about 0.58 px mean error).
TEST(Ransac, RealMatchesWithOutliers) {
  const std::string dir = SharedDataDir("pnp/sqpnp_robust", "32D.txt", "CONE_TRACKER_PNP_DATA");
  if (dir.empty()) GTEST_SKIP() << "../shared/data/pnp/sqpnp_robust not found: real-PnP test skipped";
  CameraModel camera;
  std::ifstream k_file(dir + "/K.txt");
  double K[9];
  for (double& v : K) ASSERT_TRUE(bool(k_file >> v)) << dir << "/K.txt";
  camera.fx_px = K[0], camera.cx_px = K[2], camera.fy_px = K[4], camera.cy_px = K[5];
  std::ifstream in(dir + "/32D.txt");
  std::vector<Eigen::Vector3d> model;
  std::vector<Eigen::Vector2d> image;
  double X, Y, Z, u, v;
  while (in >> X >> Y >> Z >> u >> v) model.emplace_back(X, Y, Z), image.emplace_back(u, v);
  ASSERT_EQ(model.size(), 891u);
  const RansacPnpResult r = SolvePnpRansac(camera, model, image, PnpOptions(), RansacOptions());
  ASSERT_TRUE(r.pnp.ok) << r.pnp.error;
  double sum = 0.0;
  for (const Eigen::Vector2d& e : r.pnp.residuals_px) sum += e.norm();
  const double mean = sum / r.num_inliers;
  const PnpResult plain = SolvePnp(camera, model, image, PnpOptions());
  std::printf(
      "sqpnp_robust: %d of 891 inliers, mean error %.3f px, t (%.3f %.3f %.3f) m; without RANSAC t (%.3f %.3f "
      "%.3f) m, RMS %.1f px\n",
      r.num_inliers, mean, r.pnp.T_camera_model.t.x(), r.pnp.T_camera_model.t.y(), r.pnp.T_camera_model.t.z(),
      plain.T_camera_model.t.x(), plain.T_camera_model.t.y(), plain.T_camera_model.t.z(), plain.reproj_rms_px);
  EXPECT_GE(r.num_inliers, 690);
  EXPECT_LE(r.num_inliers, 730);
  EXPECT_LT(mean, 0.7);
}

}  // namespace
}  // namespace cone_tracker
