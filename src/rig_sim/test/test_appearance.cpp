// Looks (issue 15.4): sleeve bands, weathered cones, cast shadows, coloured light, the camera's
// white balance, exposure, noise and motion blur.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "rig_sim/renderer.h"
#include "rig_sim/sim_stream.h"
#include "test_util.h"

namespace rig_sim {
namespace {

// The camera at `eye` looking at `target` (cones frame), horizon level.
TruePose LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  TruePose pose;
  pose.R_cones_camera.col(0) = x;
  pose.R_cones_camera.col(1) = z.cross(x);
  pose.R_cones_camera.col(2) = z;
  pose.p_camera_in_cones_m = eye;
  return pose;
}

struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
  std::vector<int16_t> labels;
  const uint8_t* at(int u, int v) const { return &rgb[3 * (static_cast<size_t>(v) * width + u)]; }
  int16_t label(int u, int v) const { return labels[static_cast<size_t>(v) * width + u]; }
};

Image RenderPoses(const Scenario& s, const std::vector<TruePose>& poses, double t, uint64_t frame) {
  const Renderer r(s.camera.model, s.scene, s.render);
  Image im;
  im.width = r.width();
  im.height = r.height();
  im.rgb.resize(static_cast<size_t>(im.width) * im.height * 3);
  im.labels.resize(static_cast<size_t>(im.width) * im.height);
  r.RenderExposure(poses, t, frame, im.rgb.data(), im.labels.data());
  return im;
}
Image RenderPose(const Scenario& s, const TruePose& pose, double t = 0.0, uint64_t frame = 0) {
  return RenderPoses(s, {pose}, t, frame);
}

// The realistic layout at half size, in `look`, without image noise unless asked.
Scenario LookScenario(const std::string& look, bool noise = false) {
  Scenario s = TestScenario("handheld", 3, 5, 0.5);
  std::string err;
  if (!LoadSceneYaml(LayoutsDir() + "/realistic.yaml", &s.scene, &err)) throw std::runtime_error(err);
  if (!ApplyLook(look, &s, &err)) throw std::runtime_error(err);
  s.render.lighting.variation = 0.0;  // steady sun: the tests compare frames
  s.render.lighting.azimuth_drift_deg_s = 0.0;
  if (!noise) s.render.noise_sigma_dn = 0.0;
  s.render.appearance.exposure_drift = 0.0;
  s.render.appearance.white_balance_drift = 0.0;
  s.render.appearance.vignetting = 0.0;
  return s;
}

// The pixel where point p (cones frame) projects; false outside the image.
bool PixelOf(const Scenario& s, const TruePose& pose, const Eigen::Vector3d& p, int* u, int* v) {
  Eigen::Vector2d uv;
  if (!s.camera.model.Project(pose.R_cones_camera.transpose() * (p - pose.p_camera_in_cones_m), &uv)) return false;
  *u = static_cast<int>(std::lround(uv.x()));
  *v = static_cast<int>(std::lround(uv.y()));
  return *u >= 0 && *v >= 0 && *u < s.camera.model.width_px && *v < s.camera.model.height_px;
}

// A point on the surface of cone i facing the camera, at fraction f of its height.
Eigen::Vector3d OnCone(const ConeSpec& c, const Eigen::Vector3d& eye, double f) {
  Eigen::Vector3d toward = eye - c.base_m;
  toward.z() = 0.0;
  toward.normalize();
  return c.base_m + Eigen::Vector3d(0, 0, f * c.height_m) + 0.97 * c.tau * (1.0 - f) * c.height_m * toward;
}

bool WhiteIsh(const uint8_t* p) {
  return p[0] > 140 && p[1] > 140 && p[2] > 130 && std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]}) < 60;
}
bool OrangeIsh(const uint8_t* p) { return p[0] > 120 && p[0] > p[1] + 60 && p[1] > p[2]; }
double Luma(const uint8_t* p) { return 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2]; }

// Mean absolute horizontal gradient of the green channel: edge sharpness.
double Sharpness(const Image& im) {
  double sum = 0.0;
  for (int v = 0; v < im.height; ++v)
    for (int u = 1; u < im.width; ++u) sum += std::abs(im.at(u, v)[1] - im.at(u - 1, v)[1]);
  return sum / (static_cast<double>(im.height) * (im.width - 1));
}

}  // namespace

TEST(Looks, EveryNamedLookAppliesAndAnUnknownOneIsNamed) {
  for (const auto& look : ListLooks()) {
    Scenario s = TestScenario("handheld", 1, 2, 0.125);
    std::string err;
    ASSERT_TRUE(ApplyLook(look.name, &s, &err)) << look.name << ": " << err;
    EXPECT_EQ(s.look, look.name);
    EXPECT_EQ(s.render.appearance.Validate(), "") << look.name;
    EXPECT_EQ(s.render.appearance.Active(), look.name != "plain") << look.name;
  }
  Scenario s = TestScenario("handheld", 1, 2, 0.125);
  std::string err;
  EXPECT_FALSE(ApplyLook("sunnny", &s, &err));
  EXPECT_NE(err.find("unknown look 'sunnny'"), std::string::npos) << err;
  EXPECT_NE(err.find("low_sun"), std::string::npos) << err;
  EXPECT_EQ(TestScenario("handheld", 1, 2, 0.125).look, "plain");
  EXPECT_EQ(TestScenario("realistic", 1, 2, 0.125).look, "realistic");
}

TEST(Looks, ABadAppearanceIsRefusedNamingItsField) {
  Scenario s = TestScenario("handheld", 1, 2, 0.125);
  s.render.appearance.cone_weathering = 1.5;
  try {
    const Renderer r(s.camera.model, s.scene, s.render);
    FAIL() << "accepted cone_weathering 1.5";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cone_weathering"), std::string::npos) << e.what();
  }
}

TEST(Looks, PlainLookRendersExactlyWhatTheRendererAlwaysRendered) {
  // The default AppearanceConfig takes the old code path: ApplyLook("plain") and a default config
  // give the same bytes, with noise, and the plain config reports itself inactive.
  Scenario a = TestScenario("clutter", 2, 5, 0.25), b = a;
  std::string err;
  ASSERT_TRUE(ApplyLook("plain", &b, &err));
  EXPECT_FALSE(b.render.appearance.Active());
  const Trajectory traj(a.trajectory);
  EXPECT_EQ(RenderPose(a, traj.At(2.0), 2.0, 7).rgb, RenderPose(b, traj.At(2.0), 2.0, 7).rgb);
  // Any active option changes the frame.
  b.render.appearance.white_balance_gain = Eigen::Vector3d(1.2, 1.0, 1.0);
  EXPECT_NE(RenderPose(a, traj.At(2.0), 2.0, 7).rgb, RenderPose(b, traj.At(2.0), 2.0, 7).rgb);
}

TEST(Looks, SleevesAreWhiteAtTheirHeightsAndOrangeElsewhere) {
  // realistic.yaml: cone 1 wears one wide sleeve (0.40-0.75), cone 2 the US two bands
  // (0.42-0.55, 0.62-0.80). The camera looks at each from 2.5 m.
  for (const std::string look : {"plain", "realistic"}) {
    Scenario s = LookScenario(look);
    s.render.appearance.exposure_time_s = 0.0;
    s.render.appearance.cone_weathering = 0.0;
    struct Probe {
      int cone;
      double f;
      bool white;
    };
    const std::vector<Probe> probes = {{0, 0.20, false}, {0, 0.45, true},  {0, 0.58, true}, {0, 0.70, true},
                                       {0, 0.85, false}, {1, 0.30, false}, {1, 0.48, true}, {1, 0.585, false},
                                       {1, 0.71, true},  {1, 0.88, false}};
    for (const Probe& pr : probes) {
      const ConeSpec& c = s.scene.cones[pr.cone];
      const Eigen::Vector3d out = (c.base_m - s.scene.ConeCentroid()).normalized();
      const Eigen::Vector3d eye = c.base_m + 2.5 * Eigen::Vector3d(out.x(), out.y(), 0.0) + Eigen::Vector3d(0, 0, 0.6);
      // The sun behind the camera lights the side we see.
      const double az = std::atan2(out.y(), out.x()) * 180.0 / 3.14159265358979323846;
      s.render.lighting.sun_azimuth_deg = az;
      const TruePose pose = LookAt(eye, c.base_m + Eigen::Vector3d(0, 0, 0.4 * c.height_m));
      const Image im = RenderPose(s, pose);
      int u, v;
      ASSERT_TRUE(PixelOf(s, pose, OnCone(c, eye, pr.f), &u, &v));
      ASSERT_EQ(im.label(u, v), kLabelFirstCone + pr.cone) << look << " cone " << pr.cone << " f " << pr.f;
      const uint8_t* p = im.at(u, v);
      if (pr.white)
        EXPECT_TRUE(WhiteIsh(p)) << look << " cone " << pr.cone << " f " << pr.f << ": " << int(p[0]) << " "
                                 << int(p[1]) << " " << int(p[2]);
      else
        EXPECT_TRUE(OrangeIsh(p)) << look << " cone " << pr.cone << " f " << pr.f << ": " << int(p[0]) << " "
                                  << int(p[1]) << " " << int(p[2]);
    }
  }
}

TEST(Looks, ConesCastShadowsOnTheGroundLongerAtALowSun) {
  for (const std::string look : {"sunny", "low_sun"}) {
    Scenario lit = LookScenario(look);
    Scenario unshadowed = lit;
    unshadowed.render.appearance.shadows = false;
    const LightingConfig& L = lit.render.lighting;
    const double el = L.sun_elevation_deg * 3.14159265358979323846 / 180.0;
    const double az = L.sun_azimuth_deg * 3.14159265358979323846 / 180.0;
    const Eigen::Vector3d away(-std::cos(az), -std::sin(az), 0.0);  // from the cone, away from the sun
    const ConeSpec& c = lit.scene.cones[0];
    // The shadow of the point at 60 % of the axis, and a ground point as far on the sun's side.
    const double reach = 0.6 * c.height_m / std::tan(el);
    const Eigen::Vector3d shadow = c.base_m + reach * away, sunlit = c.base_m - reach * away;
    const Eigen::Vector3d side(-away.y(), away.x(), 0.0);
    const Eigen::Vector3d eye = c.base_m + 4.0 * side + Eigen::Vector3d(0, 0, 1.6);
    const TruePose pose = LookAt(eye, c.base_m);
    const Image a = RenderPose(lit, pose), b = RenderPose(unshadowed, pose);
    int u, v;
    ASSERT_TRUE(PixelOf(lit, pose, shadow, &u, &v)) << look;
    ASSERT_EQ(a.label(u, v), kLabelGround) << look;
    // In the shadow only the sky light remains: the sun gives ~2x (sunny) or more of it.
    EXPECT_LT(Luma(a.at(u, v)), 0.75 * Luma(b.at(u, v))) << look;
    EXPECT_LT(a.at(u, v)[0], b.at(u, v)[0]) << look;
    ASSERT_TRUE(PixelOf(lit, pose, sunlit, &u, &v)) << look;
    EXPECT_EQ(a.at(u, v)[0], b.at(u, v)[0]) << look << ": the sunny side has no shadow";
    EXPECT_EQ(a.at(u, v)[2], b.at(u, v)[2]) << look;
    // Shaded far side of the cone: darker than its sunlit side.
    const Eigen::Vector3d far_eye = c.base_m + 3.0 * away + Eigen::Vector3d(0, 0, 0.5);
    const Eigen::Vector3d near_eye = c.base_m - 3.0 * away + Eigen::Vector3d(0, 0, 0.5);
    const Eigen::Vector3d mid = c.base_m + Eigen::Vector3d(0, 0, 0.25 * c.height_m);
    const TruePose far_pose = LookAt(far_eye, mid), near_pose = LookAt(near_eye, mid);
    const Image fa = RenderPose(lit, far_pose), ne = RenderPose(lit, near_pose);
    int uf, vf, un, vn;
    ASSERT_TRUE(PixelOf(lit, far_pose, OnCone(c, far_eye, 0.25), &uf, &vf));
    ASSERT_TRUE(PixelOf(lit, near_pose, OnCone(c, near_eye, 0.25), &un, &vn));
    ASSERT_EQ(fa.label(uf, vf), kLabelFirstCone);
    ASSERT_EQ(ne.label(un, vn), kLabelFirstCone);
    EXPECT_LT(fa.at(uf, vf)[0] + 40, ne.at(un, vn)[0]) << look;
  }
}

TEST(Looks, WeatheredConesAreDarkerLessSaturatedAndMottled) {
  Scenario clean = LookScenario("plain");
  Scenario dirty = LookScenario("weathered");
  dirty.render.appearance.cone_weathering = 1.0;
  const TruePose pose = LookAt(Eigen::Vector3d(3.5, 0.5, 1.2), Eigen::Vector3d(0.0, 0.0, 0.2));  // all three cones
  const Image a = RenderPose(clean, pose), b = RenderPose(dirty, pose);
  double sum_a = 0, sum_b = 0, sat_a = 0, sat_b = 0, sum_ratio = 0, sq_ratio = 0;
  int n = 0;
  for (int v = 0; v < a.height; ++v)
    for (int u = 0; u < a.width; ++u) {
      if (a.label(u, v) < kLabelFirstCone || a.label(u, v) >= kLabelFirstDistractor || !OrangeIsh(a.at(u, v))) continue;
      ASSERT_EQ(b.label(u, v), a.label(u, v));
      const uint8_t *p = a.at(u, v), *q = b.at(u, v);
      sum_a += Luma(p);
      sum_b += Luma(q);
      const double ratio = Luma(q) / std::max(1.0, Luma(p));  // the dirt alone, without the shading
      sum_ratio += ratio;
      sq_ratio += ratio * ratio;
      sat_a += (p[0] - p[2]) / std::max(1.0, double(p[0]));
      sat_b += (q[0] - q[2]) / std::max(1.0, double(q[0]));
      ++n;
    }
  ASSERT_GT(n, 300);
  std::printf("weathered/clean: luma %.3f, saturation %.3f -> %.3f\n", sum_b / sum_a, sat_a / n, sat_b / n);
  EXPECT_LT(sum_b, 0.95 * sum_a);          // darker (0.90 when written)
  EXPECT_LT(sat_b / n, sat_a / n - 0.15);  // less saturated ((R - B) / R: 0.90 -> 0.62 when written)
  // Mottled: the dirty cone's brightness over the clean one's varies from pixel to pixel.
  const double mean_ratio = sum_ratio / n;
  EXPECT_GT(std::sqrt(std::max(0.0, sq_ratio / n - mean_ratio * mean_ratio)), 0.05);
}

TEST(Looks, WhiteBalanceGainTintsTheImage) {
  Scenario a = LookScenario("plain"), b = a;
  b.render.appearance.white_balance_gain = Eigen::Vector3d(1.25, 1.0, 0.8);
  const TruePose pose = LookAt(Eigen::Vector3d(3.0, 0.5, 1.2), Eigen::Vector3d(0.0, 0.0, 0.2));
  const Image ia = RenderPose(a, pose), ib = RenderPose(b, pose);
  double ra = 0, ba = 0, rb = 0, bb = 0;
  for (size_t i = 0; i < ia.rgb.size(); i += 3)
    ra += ia.rgb[i], ba += ia.rgb[i + 2], rb += ib.rgb[i], bb += ib.rgb[i + 2];
  EXPECT_GT(rb / bb, 1.15 * ra / ba);
}

TEST(Looks, ExposureDriftChangesBrightnessOverTime) {
  Scenario s = LookScenario("plain");
  s.render.appearance.exposure_drift = 0.3;
  s.render.appearance.drift_period_s = 4.0;
  const TruePose pose = LookAt(Eigen::Vector3d(3.0, 0.5, 1.2), Eigen::Vector3d(0.0, 0.0, 0.2));
  double lo = 1e9, hi = 0;
  for (double t = 0; t < 4.0; t += 0.5) {
    const Image im = RenderPose(s, pose, t);
    double sum = 0;
    for (uint8_t c : im.rgb) sum += c;
    lo = std::min(lo, sum / im.rgb.size());
    hi = std::max(hi, sum / im.rgb.size());
  }
  EXPECT_GT(hi, 1.2 * lo);
}

TEST(Looks, ShotNoiseRaisesTheNoiseOnBrightPixelsAndIsSeeded) {
  Scenario clean = LookScenario("plain");
  Scenario read = LookScenario("plain", true);
  read.render.noise_sigma_dn = 2.0;
  Scenario shot = read;
  shot.render.appearance.shot_noise = 8.0;
  const TruePose pose = LookAt(Eigen::Vector3d(3.0, 0.5, 1.2), Eigen::Vector3d(0.0, 0.0, 0.2));
  const Image c = RenderPose(clean, pose), r = RenderPose(read, pose, 0.0, 5), s = RenderPose(shot, pose, 0.0, 5);
  auto sd_bright = [&](const Image& im) {
    double sq = 0;
    int n = 0;
    for (size_t i = 0; i < im.rgb.size(); ++i)
      if (c.rgb[i] > 100 && c.rgb[i] < 230) sq += (im.rgb[i] - c.rgb[i]) * (im.rgb[i] - c.rgb[i]), ++n;
    return std::sqrt(sq / std::max(1, n));
  };
  EXPECT_NEAR(sd_bright(r), 2.0, 0.3);
  EXPECT_GT(sd_bright(s), 1.8 * sd_bright(r));           // sqrt(1 + 8 * >100/255) > 2
  EXPECT_EQ(RenderPose(shot, pose, 0.0, 5).rgb, s.rgb);  // same seed and frame: the same image
  EXPECT_NE(RenderPose(shot, pose, 0.0, 6).rgb, s.rgb);  // another frame: other noise
}

TEST(Looks, MotionBlurSmearsEdgesAndIdenticalPosesDoNot) {
  Scenario s = LookScenario("plain");
  const Eigen::Vector3d eye(3.0, 0.5, 0.9);
  const TruePose still = LookAt(eye, Eigen::Vector3d(0.5, 0.0, 0.3));
  std::vector<TruePose> panning, steady(5, still);
  for (int k = 0; k < 5; ++k)  // a 1.5 deg pan over the exposure
    panning.push_back(LookAt(eye, Eigen::Vector3d(0.5, 0.0, 0.3) + Eigen::Vector3d(0, 0.02 * (k - 2), 0)));
  const Image sharp = RenderPose(s, still), blurred = RenderPoses(s, panning, 0.0, 0),
              same = RenderPoses(s, steady, 0.0, 0);
  EXPECT_LT(Sharpness(blurred), 0.8 * Sharpness(sharp));
  EXPECT_EQ(blurred.labels, sharp.labels);  // labels are the middle pose's
  int worst = 0;
  for (size_t i = 0; i < sharp.rgb.size(); ++i) worst = std::max(worst, std::abs(same.rgb[i] - sharp.rgb[i]));
  EXPECT_LE(worst, 1);
}

TEST(Looks, TheStreamBlursFramesAlongTheTrajectory) {
  // The realistic scenario during its first shake (14-17 s): blurred frames against the same frames
  // with the shutter closed to an instant.
  Scenario blurred = TestScenario("realistic", 1, 20, 0.25);
  Scenario sharp = blurred;
  sharp.render.appearance.exposure_time_s = 0.0;
  blurred.render.noise_sigma_dn = sharp.render.noise_sigma_dn = 0.0;
  const SimStream a(blurred, StreamConfig()), b(sharp, StreamConfig());
  double sa = 0, sb = 0;
  for (double t : {14.4, 14.6, 15.2, 15.5}) {
    const SimEvent ev = a.ImageEventAt(t, 1);
    Image ia, ib;
    ia.width = ib.width = blurred.camera.model.width_px;
    ia.height = ib.height = blurred.camera.model.height_px;
    ia.rgb.resize(ia.width * ia.height * 3);
    ib.rgb.resize(ia.rgb.size());
    a.RenderFrame(ev, ia.rgb.data());
    b.RenderFrame(ev, ib.rgb.data());
    sa += Sharpness(ia);
    sb += Sharpness(ib);
  }
  EXPECT_LT(sa, 0.95 * sb);
}

}  // namespace rig_sim
