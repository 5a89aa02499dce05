// pnp_solve's JSON lines: the issue's input and output formats.
#include "pnp_json.h"
#include "test_util.h"

namespace cone_tracker {
namespace {

using nlohmann::json;

json CaseJson(const sim::Case& k, const std::vector<Eigen::Vector2d>& image) {
  json in;
  in["K"] = {k.camera.fx_px, k.camera.fy_px, k.camera.cx_px, k.camera.cy_px};
  in["dist"] = {0.0, 0.0, 0.0, 0.0};
  for (const Eigen::Vector3d& m : k.model) in["model"].push_back({m.x(), m.y(), m.z()});
  for (const Eigen::Vector2d& p : image) in["image"].push_back({p.x(), p.y()});
  in["sigma_px"] = 0.8;
  return in;
}

TEST(PnpJson, SolvesACaseInTheIssueFormat) {
  std::mt19937 rng(40);
  const sim::Case k = sim::ConeLayout(rng);
  PnpOptions options;
  const nlohmann::ordered_json out = SolveJsonCase(json::parse(CaseJson(k, k.image).dump()), options);
  EXPECT_EQ(out.begin().key(), "ok");
  ASSERT_TRUE(out["ok"].get<bool>()) << out.dump();
  const auto q = out["q"].get<std::vector<double>>();
  const auto t = out["t"].get<std::vector<double>>();
  ASSERT_EQ(q.size(), 4u);
  ASSERT_EQ(t.size(), 3u);
  const pose_math::Pose T{pose_math::Quat(q[0], q[1], q[2], q[3]), Eigen::Vector3d(t[0], t[1], t[2])};
  EXPECT_TRUE(PoseNear(T, k.T_camera_model, 1e-9));
  EXPECT_LT(out["reproj_rms_px"].get<double>(), 1e-6);
  EXPECT_GE(out["iterations"].get<int>(), 0);
  EXPECT_GE(out["time_us"].get<double>(), 0.0);

  // cov6 is (rotation vector, translation): compare with SolvePnp's ROS form (x y z rx ry rz).
  const auto cov6 = out["cov6"].get<std::vector<double>>();
  ASSERT_EQ(cov6.size(), 36u);
  options.sigma_px = 0.8;
  const PnpResult r = SolvePnp(k.camera, k.model, k.image, options);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      EXPECT_NEAR(cov6[6 * i + j], r.cov6_ros((i + 3) % 6, (j + 3) % 6), 1e-12 + 1e-9 * std::abs(cov6[6 * i + j]));
    }
}

TEST(PnpJson, BadInputGivesAnErrorLine) {
  std::mt19937 rng(41);
  const sim::Case k = sim::ConeLayout(rng);
  const json good = CaseJson(k, k.image);
  json missing = good;
  missing.erase("image");
  json short_k = good;
  short_k["K"] = {770.0, 776.0};
  json bad_point = good;
  bad_point["model"][2] = {1.0, 2.0};
  json text = good;
  text["image"][0] = {"a", 1.0};
  json few = good;
  few["model"] = json::array({good["model"][0], good["model"][1], good["model"][2]});
  few["image"] = json::array({good["image"][0], good["image"][1], good["image"][2]});
  for (const json& in : {missing, short_k, bad_point, text, few}) {
    const nlohmann::ordered_json out = SolveJsonCase(in, PnpOptions());
    EXPECT_FALSE(out["ok"].get<bool>()) << in.dump();
    EXPECT_FALSE(out["error"].get<std::string>().empty());
  }
}

}  // namespace
}  // namespace cone_tracker
