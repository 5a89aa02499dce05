#include "rig_model/ros/conversions.h"

#include <cmath>

#include <gtest/gtest.h>

#include "pose_math/covariance.h"

namespace rig_model {
namespace {

pose_math::Pose SomePose() {
  pose_math::Pose T;
  T.q = pose_math::Quat(0.9, -0.2, 0.3, 0.25).normalized();
  T.t = Eigen::Vector3d(1.25, -2.5, 0.75);
  return T;
}

pose_math::Matrix6d SomeCovariance() {
  Eigen::Matrix<double, 6, 6> A;
  for (int i = 0; i < 36; ++i) A(i / 6, i % 6) = std::sin(1.0 + i);
  return A * A.transpose() * 1e-3 + pose_math::Matrix6d::Identity() * 1e-4;
}

TEST(Conversions, PoseRoundTripsExactly) {
  const pose_math::Pose T = SomePose();
  const geometry_msgs::Pose m = ToPoseMsg(T);
  EXPECT_EQ(m.orientation.w, T.q[0]);  // thesis order [q0 qx qy qz] <-> ROS (x y z w)
  EXPECT_EQ(m.orientation.x, T.q[1]);
  EXPECT_EQ(m.position.y, T.t.y());
  const pose_math::Pose back = FromPoseMsg(m);
  EXPECT_EQ(back.q, T.q);
  EXPECT_EQ(back.t, T.t);
  const pose_math::Pose tf_back = FromTransformMsg(ToTransformMsg(T));
  EXPECT_EQ(tf_back.q, T.q);
  EXPECT_EQ(tf_back.t, T.t);
  const geometry_msgs::TransformStamped s = ToTransformStamped(T, ros::Time(3.5), "cones", "camera_optical");
  EXPECT_EQ(s.header.frame_id, "cones");
  EXPECT_EQ(s.child_frame_id, "camera_optical");
  EXPECT_EQ(s.header.stamp, ros::Time(3.5));
  EXPECT_EQ(FromTransformMsg(s.transform).q, T.q);
}

TEST(Conversions, PoseWithCovarianceRoundTrips) {
  const pose_math::Pose T = SomePose();
  const pose_math::Matrix6d cov6 = SomeCovariance();
  const geometry_msgs::PoseWithCovariance m = ToPoseWithCovarianceMsg(T, cov6);
  EXPECT_EQ(m.covariance[1], cov6(0, 1));  // row-major
  EXPECT_EQ(m.covariance[6], cov6(1, 0));
  pose_math::Pose back;
  pose_math::Matrix6d cov_back;
  FromPoseWithCovarianceMsg(m, &back, &cov_back);
  EXPECT_EQ(back.q, T.q);
  EXPECT_EQ(back.t, T.t);
  EXPECT_EQ(cov_back, cov6);

  // Thesis 7x7 -> message -> 7x7: the covariance comes back (pose_math's maps, 5.6.4).
  const pose_math::PoseWithCovariance thesis{T, pose_math::CovarianceThesisFromRos(T.q, cov6)};
  const geometry_msgs::PoseWithCovarianceStamped stamped = ToPoseWithCovarianceStamped(thesis, ros::Time(2.0), "cones");
  EXPECT_EQ(stamped.header.frame_id, "cones");
  FromPoseWithCovarianceMsg(stamped.pose, &back, &cov_back);
  EXPECT_LT((pose_math::CovarianceThesisFromRos(back.q, cov_back) - thesis.cov).norm(), 1e-12 * thesis.cov.norm());
  EXPECT_LT((cov_back - cov6).norm(), 1e-12 * cov6.norm());
}

TEST(Conversions, ExtrinsicsRoundTripThroughTf) {
  CameraImuExtrinsics e;
  e.q_camera_imu = Eigen::Quaterniond(MountRotation(Eigen::Vector3d(1.5, -2.0, 1.0)));
  e.p_imu_in_camera_m = Eigen::Vector3d(0.02, 0.08, -0.06);
  const geometry_msgs::TransformStamped m = ToTransformStamped(e, ros::Time(1.0));
  EXPECT_EQ(m.header.frame_id, "camera_optical");
  EXPECT_EQ(m.child_frame_id, "imu");
  CameraImuExtrinsics back;
  std::string why;
  ASSERT_TRUE(FromTransformStamped(m, &back, &why)) << why;
  EXPECT_LT((back.R_camera_imu() - e.R_camera_imu()).norm(), 1e-15);
  EXPECT_EQ(back.p_imu_in_camera_m, e.p_imu_in_camera_m);
  geometry_msgs::TransformStamped zero = m;
  zero.transform.rotation.w = zero.transform.rotation.x = zero.transform.rotation.y = zero.transform.rotation.z = 0;
  EXPECT_FALSE(FromTransformStamped(zero, &back, &why));
  EXPECT_NE(why.find("zero quaternion"), std::string::npos) << why;
  zero.transform.translation.x = NAN;
  EXPECT_FALSE(FromTransformStamped(zero, &back, &why));
  EXPECT_NE(why.find("not finite"), std::string::npos) << why;
}

TEST(Conversions, CameraInfoRoundTrips) {
  CameraModel rational = ThesisCamera().Scaled(0.5);
  rational.distortion_model = DistortionModel::kRationalPolynomial;
  rational.distortion = {0.3, -0.05, 0.0008, -0.0005, 0.01, 0.5, 0.02, 0.005};
  CameraModel none = ThesisCamera();
  none.distortion.clear();
  for (const CameraModel& c : {ThesisCamera(), rational, none}) {
    const sensor_msgs::CameraInfo info = ToCameraInfo(c, ros::Time(4.0), "camera_optical");
    EXPECT_EQ(info.distortion_model, DistortionModelName(c.distortion_model));
    EXPECT_EQ(info.K[0], c.fx_px);
    EXPECT_EQ(info.P[6], c.cy_px);
    EXPECT_EQ(info.header.frame_id, "camera_optical");
    CameraModel back;
    std::string why;
    ASSERT_TRUE(FromCameraInfo(info, &back, &why)) << why;
    EXPECT_TRUE(back == c);
  }
}

TEST(Conversions, BadCameraInfoIsRefusedWithTheReason) {
  auto why_of = [](const sensor_msgs::CameraInfo& info) {
    CameraModel c = ThesisCamera();
    std::string why;
    EXPECT_FALSE(FromCameraInfo(info, &c, &why));
    EXPECT_TRUE(c == ThesisCamera());  // untouched
    return why;
  };
  const sensor_msgs::CameraInfo good = ToCameraInfo(ThesisCamera(), ros::Time(), "camera_optical");
  sensor_msgs::CameraInfo info = good;
  info.D[1] = INFINITY;
  EXPECT_NE(why_of(info).find("NaN or inf"), std::string::npos);
  info = good;
  info.K[0] = 0.0;
  EXPECT_NE(why_of(info).find("uncalibrated"), std::string::npos);
  info = good;
  info.distortion_model = "equidistant";
  EXPECT_NE(why_of(info).find("'equidistant' is not supported"), std::string::npos);
  info = good;
  info.D.resize(8);
  EXPECT_NE(why_of(info).find("plumb_bob needs 4 or 5"), std::string::npos);
  info = good;
  info.width = 0;
  EXPECT_NE(why_of(info).find("image size"), std::string::npos);
  // No model named: eight coefficients are rational_polynomial (OpenCV's rule).
  info = good;
  info.distortion_model = "";
  info.D.resize(8);
  CameraModel c;
  std::string why;
  ASSERT_TRUE(FromCameraInfo(info, &c, &why)) << why;
  EXPECT_EQ(c.distortion_model, DistortionModel::kRationalPolynomial);
}

TEST(Conversions, ImageBoxesBecomeTheWholePixelsTheyTouch) {
  // Pixel 10 spans 9.5-10.5: a box from 9.7 to 20.2 touches pixels 10-20.
  sensor_msgs::RegionOfInterest roi = ToRoi({9.7, 30.0, 20.2, 40.6}, 512, 384, true);
  EXPECT_EQ(roi.x_offset, 10u);
  EXPECT_EQ(roi.width, 11u);
  EXPECT_EQ(roi.y_offset, 30u);
  EXPECT_EQ(roi.height, 12u);  // 30 .. 41
  EXPECT_TRUE(roi.do_rectify);
  const ImageBox b = FromRoi(roi);
  EXPECT_DOUBLE_EQ(b.u_min, 9.5);
  EXPECT_DOUBLE_EQ(b.u_max, 20.5);
  EXPECT_DOUBLE_EQ(b.v_min, 29.5);
  EXPECT_DOUBLE_EQ(b.v_max, 41.5);
  // Clipped to the image; wholly outside or not finite: width 0.
  roi = ToRoi({-30.0, -5.0, 600.0, 10.0}, 512, 384, false);
  EXPECT_EQ(roi.x_offset, 0u);
  EXPECT_EQ(roi.width, 512u);
  EXPECT_EQ(roi.y_offset, 0u);
  EXPECT_EQ(roi.height, 11u);
  EXPECT_EQ(ToRoi({-30.0, 5.0, -10.0, 10.0}, 512, 384, false).width, 0u);
  EXPECT_EQ(ToRoi({NAN, 5.0, 10.0, 10.0}, 512, 384, false).width, 0u);
}

}  // namespace
}  // namespace rig_model
