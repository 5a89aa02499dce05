// The GL path on llvmpipe: markers land where cv::projectPoints (with the
// lens distortion) says, depth, lighting and alpha.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

#include "ar_overlay/core/mesh_generators.h"
#include "ar_overlay/core/overlay.h"
#include "ar_overlay/core/renderer.h"

namespace ar_overlay {
namespace {

const CameraModel kCamera{1024, 768, 820.0, 818.0, 515.3, 380.7, {-0.28, 0.09, 0.0012, -0.0008, -0.012}};

Eigen::Isometry3d TestPose() {  // T_camera_cones, away from identity
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.4, Eigen::Vector3d(0.3, -1, 0.2).normalized()).toRotationMatrix();
  T.translation() << 0.2, -0.1, 2.5;
  return T;
}

// Alpha-weighted centroid of the overlay; false when it is empty.
bool Centroid(const cv::Mat& rgba, cv::Point2d& c) {
  double sw = 0, su = 0, sv = 0;
  for (int v = 0; v < rgba.rows; ++v)
    for (int u = 0; u < rgba.cols; ++u) {
      const double a = rgba.at<cv::Vec4b>(v, u)[3];
      sw += a, su += a * u, sv += a * v;
    }
  if (sw == 0) return false;
  c = {su / sw, sv / sw};
  return true;
}

class RenderTest : public ::testing::Test {
 protected:
  Renderer renderer;
  // A small square facing the camera at p_cones (so its centroid is its centre's projection).
  DrawItem Marker(int mesh, const Eigen::Vector3d& p_cones, const Eigen::Isometry3d& T_camera_cones) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = p_cones;
    T.linear() = T_camera_cones.linear().transpose();
    DrawItem d;
    d.mesh_id = mesh;
    d.T_cones_model = T.matrix().cast<float>();
    return d;
  }
};

TEST_F(RenderTest, MarkersLandOnDistortedProjection) {
  const int square = renderer.AddMesh(Box(0.012f, 0.012f, 0.0005f, {1, 1, 1, 1}));
  renderer.SetCamera(kCamera);
  const Eigen::Isometry3d T = TestPose();
  const cv::Matx33d K(kCamera.fx_px, 0, kCamera.cx_px, 0, kCamera.fy_px, kCamera.cy_px, 0, 0, 1);
  cv::Mat rvec, R_cv;
  cv::eigen2cv(Eigen::Matrix3d(T.linear()), R_cv);
  cv::Rodrigues(R_cv, rvec);
  const cv::Vec3d tvec(T.translation().x(), T.translation().y(), T.translation().z());
  int checked = 0, far_from_pinhole = 0;
  double max_error_px = 0;
  cv::Mat overlay;
  for (double xn = -0.6; xn <= 0.61; xn += 0.2) {
    for (double yn = -0.45; yn <= 0.46; yn += 0.15) {
      const Eigen::Vector3d p_camera(xn * 2.0, yn * 2.0, 2.0);
      const Eigen::Vector3d p_cones = T.inverse() * p_camera;
      std::vector<cv::Point3d> object{{p_cones.x(), p_cones.y(), p_cones.z()}};
      std::vector<cv::Point2d> distorted, pinhole;
      cv::projectPoints(object, rvec, tvec, K, kCamera.distortion, distorted);
      cv::projectPoints(object, rvec, tvec, K, cv::noArray(), pinhole);
      const cv::Point2d want = distorted[0];
      if (want.x < 15 || want.y < 15 || want.x > kCamera.width_px - 15 || want.y > kCamera.height_px - 15) continue;
      renderer.Render({Marker(square, p_cones, T)}, T, overlay);
      cv::Point2d got;
      ASSERT_TRUE(Centroid(overlay, got)) << "no marker for " << want;
      max_error_px = std::max(max_error_px, cv::norm(got - want));
      EXPECT_NEAR(got.x, want.x, 0.5) << "at " << want;
      EXPECT_NEAR(got.y, want.y, 0.5) << "at " << want;
      ++checked;
      if (cv::norm(pinhole[0] - want) > 5) ++far_from_pinhole;
    }
  }
  std::printf("markers: %d checked, largest error %.3f px\n", checked, max_error_px);
  EXPECT_GE(checked, 30);
  EXPECT_GE(far_from_pinhole, 10);  // the distortion matters here: a pinhole overlay would miss
}

TEST_F(RenderTest, NearerSurfaceWinsWhateverTheDrawOrder) {
  const int red = renderer.AddMesh(Box(0.5f, 0.5f, 0.01f, {1, 0, 0, 1}));
  const int blue = renderer.AddMesh(Box(0.2f, 0.2f, 0.01f, {0, 0, 1, 1}));
  renderer.SetCamera({320, 240, 300, 300, 160, 120, {}});
  DrawItem near_red, far_blue;
  near_red.mesh_id = red;
  near_red.T_cones_model(2, 3) = 1.0f;
  far_blue.mesh_id = blue;
  far_blue.T_cones_model(2, 3) = 1.5f;
  cv::Mat overlay;
  for (const auto& order : {std::vector<DrawItem>{near_red, far_blue}, std::vector<DrawItem>{far_blue, near_red}}) {
    renderer.Render(order, Eigen::Isometry3d::Identity(), overlay);
    const cv::Vec4b c = overlay.at<cv::Vec4b>(120, 160);
    EXPECT_GT(c[0], 100);
    EXPECT_LT(c[2], 40);  // only the specular highlight's white, no blue
    EXPECT_EQ(c[3], 255);
  }
}

TEST_F(RenderTest, LambertAndSpecularAsTheShaderSays) {
  const int grey = renderer.AddMesh(Box(1.0f, 1.0f, 0.01f, {0.5f, 0.5f, 0.5f, 1}));
  renderer.SetCamera({320, 240, 300, 300, 160, 120, {}});
  DrawItem facing;
  facing.mesh_id = grey;
  facing.T_cones_model(2, 3) = 2.0f;
  cv::Mat overlay;
  renderer.Render({facing}, Eigen::Isometry3d::Identity(), overlay);
  // n = (0,0,-1), light (-0.3,-0.6,-1)/|.|: diffuse 0.8305; half vector with the
  // eye on the axis: n.h = 0.9567, 0.25 * 0.9567^32 = 0.0606.
  const double expected = 255 * (0.5 * (0.3 + 0.7 * 0.8305) + 0.0606);
  EXPECT_NEAR(overlay.at<cv::Vec4b>(120, 160)[0], expected, 3);
  // Tilted 70 degrees away from the light: darker.
  DrawItem tilted = facing;
  tilted.T_cones_model.topLeftCorner<3, 3>() = Eigen::AngleAxisf(1.2f, Eigen::Vector3f::UnitX()).toRotationMatrix();
  renderer.Render({tilted}, Eigen::Isometry3d::Identity(), overlay);
  EXPECT_LT(overlay.at<cv::Vec4b>(120, 160)[0], expected - 40);
}

TEST_F(RenderTest, RegionCoversTheModelWholeAndIsEmptyWhenNothingIsInView) {
  const int plate = renderer.AddMesh(Box(0.4f, 0.4f, 0.01f, {1, 1, 1, 1}));
  renderer.SetCamera(kCamera);
  DrawItem d;
  d.mesh_id = plate;
  d.T_cones_model(0, 3) = 0.9f;  // toward the right edge, where the distortion is strong
  d.T_cones_model(2, 3) = 2.0f;
  cv::Mat overlay;
  const cv::Rect roi = renderer.Render({d}, Eigen::Isometry3d::Identity(), overlay);
  cv::Mat alpha;
  cv::extractChannel(overlay, alpha, 3);
  const cv::Rect drawn = cv::boundingRect(alpha);
  EXPECT_GT(drawn.area(), 1000);
  EXPECT_EQ(drawn & roi, drawn);  // every model pixel inside the region
  EXPECT_LT(roi.area(), 2 * drawn.area() + 2000);
  d.T_cones_model(2, 3) = -2.0f;  // behind the camera
  EXPECT_TRUE(renderer.Render({d}, Eigen::Isometry3d::Identity(), overlay).empty());
  EXPECT_EQ(cv::countNonZero(overlay.reshape(1)), 0);
  d.T_cones_model(2, 3) = 0.0f;  // straddling the camera: GL clips, the region is everything
  d.T_cones_model.topLeftCorner<3, 3>() = Eigen::AngleAxisf(1.3f, Eigen::Vector3f::UnitY()).toRotationMatrix();
  EXPECT_EQ(renderer.Render({d}, Eigen::Isometry3d::Identity(), overlay), cv::Rect(0, 0, 1024, 768));
}

// Levels of detail (RenderConfig::lod_max_error_px) on the benchmark's mesh.
class LodTest : public ::testing::Test {
 protected:
  const Mesh peaks = PeaksSurface(160);   // 50,562 triangles
  static constexpr float kScale = 0.05f;  // as the bench and scene_peaks.yaml: about 0.3 m across

  // The peaks seen from `distance_m` metres, rendered by `renderer`.
  static cv::Mat Draw(Renderer& renderer, int mesh, double distance_m) {
    renderer.SetCamera(kCamera);
    DrawItem d;
    d.mesh_id = mesh;
    d.T_cones_model.topLeftCorner<3, 3>() *= kScale;
    const Eigen::Vector3d eye = Eigen::Vector3d(0.5, -0.6, 0.45).normalized() * distance_m;
    cv::Mat overlay;
    renderer.Render({d}, CameraLookAt(eye, Eigen::Vector3d::Zero()).inverse(), overlay);
    return overlay.clone();
  }
};

TEST_F(LodTest, ChainHalvesTheTrianglesWithGrowingError) {
  Renderer renderer;
  const int mesh = renderer.AddMesh(peaks);
  const auto levels = renderer.LevelsOfDetail(mesh);
  ASSERT_GE(levels.size(), 4u);
  EXPECT_EQ(levels[0].first, peaks.TriangleCount());
  EXPECT_EQ(levels[0].second, 0.0f);
  for (size_t i = 1; i < levels.size(); ++i) {
    EXPECT_LE(levels[i].first, levels[i - 1].first * 3 / 4) << i;
    EXPECT_GT(levels[i].second, levels[i - 1].second) << i;
  }
  EXPECT_GE(levels.back().first, kLodMinTriangles / 8);
  // Small meshes are drawn as they are.
  EXPECT_EQ(renderer.LevelsOfDetail(renderer.AddMesh(Box(1, 1, 1, {1, 1, 1, 1}))).size(), 1u);
}

TEST_F(LodTest, FarAwayDrawsFewerTrianglesNearDrawsThemAll) {
  Renderer renderer;
  const int mesh = renderer.AddMesh(peaks);
  // Part of the surface in front of the near plane: its error is judged there, the full mesh.
  Draw(renderer, mesh, 0.15);
  EXPECT_EQ(renderer.drawn_triangles(), peaks.TriangleCount());
  Draw(renderer, mesh, 1.2);
  const size_t mid = renderer.drawn_triangles();
  Draw(renderer, mesh, 6.0);
  const size_t far = renderer.drawn_triangles();
  EXPECT_LT(mid, peaks.TriangleCount());
  EXPECT_LT(far, mid);
  // The level drawn is the coarsest whose error projects to <= 0.5 px at the
  // nearest vertex, which lies within 0.45 m of the origin.
  const auto levels = renderer.LevelsOfDetail(mesh);
  size_t drawn = levels.size();
  for (size_t i = 0; i < levels.size(); ++i) {
    if (levels[i].first == far) drawn = i;
  }
  ASSERT_LT(drawn, levels.size());
  EXPECT_LE(kCamera.fx_px * levels[drawn].second * kScale / 6.45, 0.5);
  if (drawn + 1 < levels.size()) {
    EXPECT_GT(kCamera.fx_px * levels[drawn + 1].second * kScale / 5.55, 0.5);
  }
  RenderConfig off;
  off.lod_max_error_px = 0.0;
  Renderer full(off);
  Draw(full, full.AddMesh(peaks), 6.0);
  EXPECT_EQ(full.drawn_triangles(), peaks.TriangleCount());
}

TEST_F(LodTest, PictureMatchesTheFullMesh) {
  // At about the bench's distance the default (0.5 px) draws an eighth of the
  // triangles; silhouette and shading must be the full mesh's to within
  // that half pixel: alpha differs only along the outline, colour barely.
  Renderer lod;
  RenderConfig off;
  off.lod_max_error_px = 0.0;
  Renderer full(off);
  const cv::Mat a = Draw(lod, lod.AddMesh(peaks), 1.2), b = Draw(full, full.AddMesh(peaks), 1.2);
  ASSERT_LT(lod.drawn_triangles(), full.drawn_triangles() / 2);
  cv::Mat alpha_a, alpha_b, diff;
  cv::extractChannel(a, alpha_a, 3);
  cv::extractChannel(b, alpha_b, 3);
  const int covered = cv::countNonZero(alpha_b);
  ASSERT_GT(covered, 20000);
  cv::absdiff(alpha_a, alpha_b, diff);
  const int outline_moved = cv::countNonZero(diff > 128);
  std::printf("LOD %zu of %zu triangles: %d of %d covered pixels changed coverage\n", lod.drawn_triangles(),
              full.drawn_triangles(), outline_moved, covered);
  EXPECT_LT(outline_moved, covered / 100);
  cv::Mat both = (alpha_a == 255) & (alpha_b == 255);
  cv::absdiff(a, b, diff);
  const cv::Scalar mean_colour_diff = cv::mean(diff, both);
  std::printf("mean colour difference where both are opaque: %.2f %.2f %.2f of 255\n", mean_colour_diff[0],
              mean_colour_diff[1], mean_colour_diff[2]);
  for (int c = 0; c < 3; ++c) EXPECT_LT(mean_colour_diff[c], 3.0) << c;
}

TEST(OverlayAlpha, HalfTransparentModelBlendsWithTheImage) {
  Overlay overlay;
  ModelSpec spec;
  spec.name = "plate";
  spec.alpha = 0.5;
  spec.has_color = true;
  spec.color = Eigen::Vector3f(1, 1, 1);
  spec.T_parent_origin.translation() << 0, 0, 2;
  overlay.AddModel(spec, Box(1.0f, 1.0f, 0.01f, {0.3f, 0.3f, 0.3f, 1}));
  const cv::Mat image(240, 320, CV_8UC3, cv::Scalar(0, 0, 200));  // bgr: red
  std::string enc;
  cv::Mat out;
  overlay.Process(image, "bgr8", {320, 240, 300, 300, 160, 120, {}}, Eigen::Isometry3d::Identity(), out, enc);
  EXPECT_EQ(enc, "bgr8");
  const cv::Vec3b centre = out.at<cv::Vec3b>(120, 160), corner = out.at<cv::Vec3b>(2, 2);
  EXPECT_EQ(corner, cv::Vec3b(0, 0, 200));  // untouched
  EXPECT_GT(centre[0], 90);                 // half of a lit white
  EXPECT_LT(centre[0], 140);
  EXPECT_GT(centre[2], centre[0] + 60);  // plus half of the red underneath
}

}  // namespace
}  // namespace ar_overlay
