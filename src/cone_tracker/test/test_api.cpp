// SolvePnp: every method through the one API, distortion, covariance forms and
// every degenerate-input error.
#include <cmath>
#include <limits>

#include "cone_tracker/pose/pnp.h"
#include "pose_math/covariance.h"
#include "test_util.h"

namespace cone_tracker {
namespace {

PnpOptions With(PnpMethod m) {
  PnpOptions o;
  o.method = m;
  return o;
}

TEST(SolvePnp, MethodNamesRoundTrip) {
  ASSERT_EQ(PnpMethodNames().size(), 12u);
  for (const std::string& name : PnpMethodNames()) {
    const auto m = PnpMethodFromName(name);
    ASSERT_TRUE(m.has_value()) << name;
    EXPECT_EQ(PnpMethodName(*m), name);
  }
  EXPECT_FALSE(PnpMethodFromName("nope").has_value());
}

TEST(SolvePnp, EveryMethodRecoversExactPoseWithDistortion) {
  std::mt19937 rng(30);
  sim::Case k = sim::RandomCloud(rng, 12);
  k.camera.distortion = {-0.2, 0.05, 0.001, -0.0005};
  ASSERT_TRUE(sim::Project(k.camera, k.T_camera_model, k.model, &k.image));
  for (const std::string& name : PnpMethodNames()) {
    const PnpResult r = SolvePnp(k.camera, k.model, k.image, With(*PnpMethodFromName(name)));
    ASSERT_TRUE(r.ok) << name << ": " << r.error;
    // undistortPoints iterates to ~1e-10 px, well inside 1e-9 m at 1.5 m.
    EXPECT_TRUE(PoseNear(r.T_camera_model, k.T_camera_model, 1e-9)) << name;
    EXPECT_LT(r.reproj_rms_px, 1e-6) << name;
    EXPECT_EQ(r.residuals_px.size(), k.model.size());
  }
}

TEST(SolvePnp, CovarianceFormsAgree) {
  std::mt19937 rng(31);
  const sim::Case k = sim::ConeLayout(rng);
  PnpOptions o;
  o.sigma_px = 1.5;
  const PnpResult r = SolvePnp(k.camera, k.model, sim::AddNoise(rng, k.image, 1.5), o);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_LT((r.cov7.topLeftCorner<4, 4>() * r.T_camera_model.q).norm(), 1e-9 * r.cov7.norm());  // on the tangent plane
  EXPECT_LT((pose_math::CovarianceThesisFromRos(r.T_camera_model.q, r.cov6_ros) - r.cov7).norm(), 1e-9 * r.cov7.norm());
  EXPECT_GT(r.cov6_ros.diagonal().minCoeff(), 0.0);
}

TEST(SolvePnp, InitialPoseIsUsed) {
  std::mt19937 rng(32);
  const sim::Case k = sim::ConeLayout(rng);
  const PnpResult r = SolvePnp(k.camera, k.model, k.image, With(PnpMethod::kCeres), k.T_camera_model);
  ASSERT_TRUE(r.ok);
  EXPECT_TRUE(PoseNear(r.T_camera_model, k.T_camera_model, 1e-9));
}

class Degenerate : public ::testing::Test {
 protected:
  void SetUp() override {
    std::mt19937 rng(33);
    k_ = sim::RandomCloud(rng, 10);
  }
  void ExpectErrorForAll(const std::vector<Eigen::Vector3d>& model, const std::vector<Eigen::Vector2d>& image,
                         const std::string& what) {
    for (const std::string& name : PnpMethodNames()) {
      const PnpResult r = SolvePnp(k_.camera, model, image, With(*PnpMethodFromName(name)));
      EXPECT_FALSE(r.ok) << name << " accepted " << what;
      EXPECT_FALSE(r.error.empty()) << name;
    }
  }
  sim::Case k_;
};

TEST_F(Degenerate, TooFewPoints) {
  const std::vector<Eigen::Vector3d> model(k_.model.begin(), k_.model.begin() + 3);
  const std::vector<Eigen::Vector2d> image(k_.image.begin(), k_.image.begin() + 3);
  ExpectErrorForAll(model, image, "3 points");
  // Five points: enough for p3p, oia, ceres and best, too few for the rest.
  const std::vector<Eigen::Vector3d> model5(k_.model.begin(), k_.model.begin() + 5);
  const std::vector<Eigen::Vector2d> image5(k_.image.begin(), k_.image.begin() + 5);
  for (const char* name : {"dlt", "mdlt-is", "mdlt-os", "simplex-is", "simplex-os", "epnp", "epnp-gn", "simplex-sdp"}) {
    EXPECT_FALSE(SolvePnp(k_.camera, model5, image5, With(*PnpMethodFromName(name))).ok) << name;
  }
  EXPECT_TRUE(SolvePnp(k_.camera, model5, image5, With(PnpMethod::kBest)).ok);
}

TEST_F(Degenerate, MismatchedSizes) {
  std::vector<Eigen::Vector2d> image = k_.image;
  image.pop_back();
  ExpectErrorForAll(k_.model, image, "mismatched sizes");
}

TEST_F(Degenerate, CollinearModelPoints) {
  std::vector<Eigen::Vector3d> model;
  for (int i = 0; i < 10; ++i) model.emplace_back(0.03 * i, 0.01 * i, -0.02 * i);
  std::vector<Eigen::Vector2d> image;
  ASSERT_TRUE(sim::Project(k_.camera, k_.T_camera_model, model, &image));
  ExpectErrorForAll(model, image, "collinear points");
}

TEST_F(Degenerate, NanAndInfInput) {
  std::vector<Eigen::Vector3d> model = k_.model;
  model[3].y() = std::numeric_limits<double>::quiet_NaN();
  ExpectErrorForAll(model, k_.image, "a NaN model point");
  std::vector<Eigen::Vector2d> image = k_.image;
  image[5].x() = std::numeric_limits<double>::infinity();
  ExpectErrorForAll(k_.model, image, "an infinite image point");
  CameraModel camera = k_.camera;
  camera.fx_px = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(SolvePnp(camera, k_.model, k_.image, PnpOptions()).ok);
  camera = k_.camera;
  camera.distortion = {0.1, std::numeric_limits<double>::quiet_NaN(), 0, 0};
  EXPECT_FALSE(SolvePnp(camera, k_.model, k_.image, PnpOptions()).ok);
  camera.distortion = {0.1, 0.01, 0.0};  // not a length OpenCV accepts
  const PnpResult r = SolvePnp(camera, k_.model, k_.image, PnpOptions());
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("distortion"), std::string::npos) << r.error;
}

TEST_F(Degenerate, PlanarPointsRejectedOnlyWhereTheMethodNeedsDepth) {
  std::vector<Eigen::Vector3d> model = k_.model;
  for (Eigen::Vector3d& p : model) p.z() = 0.0;
  std::vector<Eigen::Vector2d> image;
  ASSERT_TRUE(sim::Project(k_.camera, k_.T_camera_model, model, &image));
  for (const char* name : {"dlt", "mdlt-is", "mdlt-os", "simplex-is", "simplex-os", "epnp", "epnp-gn", "simplex-sdp"}) {
    EXPECT_FALSE(SolvePnp(k_.camera, model, image, With(*PnpMethodFromName(name))).ok) << name;
  }
  for (const char* name : {"p3p", "oia", "ceres", "best"}) {
    const PnpResult r = SolvePnp(k_.camera, model, image, With(*PnpMethodFromName(name)));
    ASSERT_TRUE(r.ok) << name << ": " << r.error;
    EXPECT_TRUE(PoseNear(r.T_camera_model, k_.T_camera_model, 1e-6)) << name;
  }
}

TEST_F(Degenerate, PointsBehindTheCamera) {
  // An initial pose that puts the model behind the camera is refused.
  pose_math::Pose behind = k_.T_camera_model;
  behind.t.z() = -behind.t.z();
  const PnpResult r = SolvePnp(k_.camera, k_.model, k_.image, With(PnpMethod::kCeres), behind);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("behind"), std::string::npos) << r.error;
}

}  // namespace
}  // namespace cone_tracker
