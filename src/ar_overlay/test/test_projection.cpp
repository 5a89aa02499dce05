// Projection matrix, distortion map, compositing and pose extrapolation: no GL.
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "ar_overlay/core/camera_projection.h"
#include "ar_overlay/core/composite.h"
#include "ar_overlay/core/pose_extrapolation.h"

namespace ar_overlay {
namespace {

TEST(Projection, PixelCentreLandsOnPixelCentre) {
  const int W = 640, H = 480;
  const Eigen::Matrix4f P = ProjectionFromIntrinsics(500, 510, 320.3, 239.7, W, H, 0.1, 100);
  // A point that the pinhole model puts at pixel (100, 50).
  const double z = 3.0, x = (100 - 320.3) * z / 500, y = (50 - 239.7) * z / 510;
  const Eigen::Vector4f clip = P * Eigen::Vector4f(x, y, z, 1);
  const double u_edge = (clip.x() / clip.w() + 1) / 2 * W, v_edge = (clip.y() / clip.w() + 1) / 2 * H;
  EXPECT_NEAR(u_edge, 100.5, 1e-3);  // the centre of column 100 is 100.5 pixel edges from the left
  EXPECT_NEAR(v_edge, 50.5, 1e-3);   // row 0 (NDC y = -1) is the image's top row
  EXPECT_NEAR((P * Eigen::Vector4f(0, 0, 0.1f, 1)).z() / 0.1f, -1.0, 1e-4);  // near plane
  EXPECT_NEAR((P * Eigen::Vector4f(0, 0, 100, 1)).z() / 100, 1.0, 1e-4);     // far plane
}

TEST(Projection, RejectsBadIntrinsics) {
  CameraModel k{640, 480, 500, 500, 320, 240, {}};
  EXPECT_EQ(Validate(k), "");
  k.fx_px = 0;
  EXPECT_NE(Validate(k).find("fx"), std::string::npos);
  k.fx_px = 500;
  k.distortion = {0.1, NAN, 0, 0, 0};
  EXPECT_NE(Validate(k), "");
  k.distortion = {0.1, 0.2, 0.3};
  EXPECT_NE(Validate(k), "");
}

TEST(DistortionMap, IdentityWithoutDistortionAndCanvasCoversBarrel) {
  CameraModel k{320, 240, 250, 250, 160, 120, {0, 0, 0, 0, 0}};
  DistortionMap none(k);
  EXPECT_TRUE(none.identity());
  EXPECT_EQ(none.canvas_width(), 320);
  k.distortion = {-0.3, 0.1, 0, 0, 0};  // barrel: the raw corners see beyond the pinhole frame
  DistortionMap barrel(k);
  EXPECT_FALSE(barrel.identity());
  EXPECT_GT(barrel.canvas_width(), 320);
  EXPECT_GT(barrel.canvas_height(), 240);
  // A dot drawn on the canvas at the ideal position of a raw pixel appears at that raw pixel.
  const cv::Matx33d K(250, 0, 160, 0, 250, 120, 0, 0, 1);
  std::vector<cv::Point2f> raw{{20.0f, 30.0f}}, ideal;
  cv::undistortPoints(raw, ideal, K, k.distortion, cv::noArray(), K);
  cv::Mat canvas(barrel.canvas_height(), barrel.canvas_width(), CV_8UC4, cv::Scalar::all(0)), out;
  const int cu = cvRound(ideal[0].x + barrel.canvas_cx() - 160), cv_ = cvRound(ideal[0].y + barrel.canvas_cy() - 120);
  cv::rectangle(canvas, cv::Rect(cu - 3, cv_ - 3, 7, 7), cv::Scalar::all(255), cv::FILLED);
  barrel.Apply(canvas, out);
  EXPECT_EQ(out.at<cv::Vec4b>(30, 20)[3], 255);
  EXPECT_EQ(out.at<cv::Vec4b>(120, 160)[3], 0);
}

TEST(Composite, BlendsPremultipliedAndSwapsForBgr) {
  cv::Mat overlay(1, 3, CV_8UC4);
  overlay.at<cv::Vec4b>(0, 0) = {0, 0, 0, 0};       // transparent
  overlay.at<cv::Vec4b>(0, 1) = {200, 0, 0, 255};   // opaque red
  overlay.at<cv::Vec4b>(0, 2) = {100, 0, 50, 128};  // half-transparent, premultiplied
  cv::Mat rgb(1, 3, CV_8UC3, cv::Scalar(10, 20, 30));
  cv::Mat bgr = rgb.clone();
  CompositeInPlace(overlay, "rgb8", rgb);
  EXPECT_EQ(rgb.at<cv::Vec3b>(0, 0), cv::Vec3b(10, 20, 30));
  EXPECT_EQ(rgb.at<cv::Vec3b>(0, 1), cv::Vec3b(200, 0, 0));
  EXPECT_EQ(rgb.at<cv::Vec3b>(0, 2), cv::Vec3b(105, 10, 65));  // c + (1 - 128/255) under
  CompositeInPlace(overlay, "bgr8", bgr);
  EXPECT_EQ(bgr.at<cv::Vec3b>(0, 1), cv::Vec3b(0, 0, 200));
  cv::Mat wrong(2, 3, CV_8UC3);
  EXPECT_THROW(CompositeInPlace(overlay, "rgb8", wrong), std::invalid_argument);
}

TEST(Composite, ConvertsEncodings) {
  std::string enc;
  cv::Mat bayer(4, 4, CV_8UC1, cv::Scalar(0));
  for (int v = 0; v < 4; v += 2)
    for (int u = 0; u < 4; u += 2) bayer.at<uint8_t>(v, u) = 200;  // rggb: the R sites
  cv::Mat c;
  ToColor(bayer, "bayer_rggb8", c, enc);
  EXPECT_EQ(enc, "bgr8");
  EXPECT_GT(c.at<cv::Vec3b>(1, 1)[2], 100);  // red
  EXPECT_LT(c.at<cv::Vec3b>(1, 1)[0], 20);   // not blue
  cv::Mat reused(2, 2, CV_8UC3);
  const uint8_t* buffer = reused.data;
  ToColor(cv::Mat(2, 2, CV_8UC1, cv::Scalar(7)), "mono8", reused, enc);
  EXPECT_EQ(reused.data, buffer);  // written into the caller's memory
  EXPECT_EQ(reused.at<cv::Vec3b>(1, 1), cv::Vec3b(7, 7, 7));
  EXPECT_THROW(ToColor(cv::Mat(2, 2, CV_16UC1), "mono16", c, enc), std::invalid_argument);
  EXPECT_THROW(ToColor(cv::Mat(2, 2, CV_8UC1), "rgb8", c, enc), std::invalid_argument);
}

TEST(PoseExtrapolation, ConstantVelocity) {
  Eigen::Isometry3d T0 = Eigen::Isometry3d::Identity(), T1 = Eigen::Isometry3d::Identity();
  T1.translation() << 0.1, 0, 0;
  T1.linear() = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Isometry3d T = ExtrapolatePose(T0, 1.0, T1, 1.1, 1.15, 1.0);
  EXPECT_NEAR(T.translation().x(), 0.15, 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(T.linear()).angle(), 0.3, 1e-12);
  EXPECT_NEAR(ExtrapolatePose(T0, 1.0, T1, 1.1, 5.0, 0.05).translation().x(), 0.15, 1e-12);  // capped
  EXPECT_TRUE(ExtrapolatePose(T0, 1.1, T1, 1.1, 1.2, 1.0).isApprox(T1));                     // no interval: latest
  EXPECT_TRUE(ExtrapolatePose(T0, 1.0, T1, 1.1, 1.05, 1.0).isApprox(T1));                    // not ahead: latest
}

}  // namespace
}  // namespace ar_overlay
