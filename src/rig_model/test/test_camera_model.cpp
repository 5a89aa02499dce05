#include "rig_model/camera_model.h"

#include <cmath>

#include <gtest/gtest.h>

namespace rig_model {
namespace {

CameraModel Rational() {
  CameraModel c = ThesisCamera();
  c.distortion_model = DistortionModel::kRationalPolynomial;
  c.distortion = {0.3, -0.05, 0.0008, -0.0005, 0.01, 0.5, 0.02, 0.005};
  return c;
}

TEST(CameraModel, DistortIsTheThesisPolynomial) {
  const CameraModel cam = ThesisCamera();
  const double k1 = -0.22, k2 = 0.07, p1 = 0.0008, p2 = -0.0005;
  const double x = 0.3, y = -0.2, r2 = x * x + y * y;
  const double radial = 1 + k1 * r2 + k2 * r2 * r2;
  const Eigen::Vector2d d = cam.Distort(Eigen::Vector2d(x, y));
  EXPECT_NEAR(d.x(), x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x), 1e-15);  // (3.10)
  EXPECT_NEAR(d.y(), y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y, 1e-15);
  CameraModel none = cam;
  none.distortion.clear();
  EXPECT_FALSE(none.HasDistortion());
  EXPECT_EQ(none.Distort(Eigen::Vector2d(x, y)), Eigen::Vector2d(x, y));
}

TEST(CameraModel, UndistortInvertsDistortAcrossTheImage) {
  for (const CameraModel& cam : {ThesisCamera(), Rational()}) {
    double worst = 0.0;
    for (double u = 0; u <= 1023; u += 93)
      for (double v = 0; v <= 767; v += 69) {
        const Eigen::Vector3d ray = cam.PixelRay(u, v);
        Eigen::Vector2d uv;
        ASSERT_TRUE(cam.Project(ray, &uv));
        worst = std::max(worst, (uv - Eigen::Vector2d(u, v)).norm());
      }
    EXPECT_LT(worst, 1e-9) << DistortionModelName(cam.distortion_model);
  }
}

TEST(CameraModel, AnalyticJacobiansMatchNumeric) {
  const double h = 1e-6;
  for (const CameraModel& cam : {ThesisCamera(), Rational()}) {
    for (const Eigen::Vector2d& p : {Eigen::Vector2d(0.3, -0.2), Eigen::Vector2d(-0.5, 0.4), Eigen::Vector2d(0, 0)}) {
      Eigen::Matrix2d numeric;
      for (int k = 0; k < 2; ++k) {
        const Eigen::Vector2d dp = Eigen::Vector2d::Unit(k) * h;
        numeric.col(k) = (cam.Distort(p + dp) - cam.Distort(p - dp)) / (2 * h);
      }
      EXPECT_LT((cam.DistortJacobian(p) - numeric).norm(), 1e-8) << p.transpose();
    }
    const Eigen::Vector3d X(0.4, -0.3, 2.5);
    Eigen::Vector2d uv;
    Eigen::Matrix<double, 2, 3> J, numeric;
    ASSERT_TRUE(cam.Project(X, &uv, &J));
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector2d a, b;
      cam.Project(X + Eigen::Vector3d::Unit(k) * h, &a);
      cam.Project(X - Eigen::Vector3d::Unit(k) * h, &b);
      numeric.col(k) = (a - b) / (2 * h);
    }
    EXPECT_LT((J - numeric).norm(), 1e-5) << "\n" << J << "\n" << numeric;
  }
}

TEST(CameraModel, BehindTheCameraDoesNotProject) {
  Eigen::Vector2d uv(7, 7);
  EXPECT_FALSE(ThesisCamera().Project(Eigen::Vector3d(0, 0, -1), &uv));
  EXPECT_FALSE(ThesisCamera().Project(Eigen::Vector3d(0, 0, 0), &uv));
  EXPECT_EQ(uv, Eigen::Vector2d(7, 7));
}

TEST(CameraModel, ScaledKeepsThePrincipalPointCentred) {
  const CameraModel c = ThesisCamera().Scaled(0.25);
  EXPECT_EQ(c.width_px, 256);
  EXPECT_EQ(c.height_px, 192);
  EXPECT_NEAR(c.cx_px, 127.5, 1e-12);
  EXPECT_NEAR(c.fx_px, 192.5, 1e-12);
  EXPECT_EQ(c.distortion, ThesisCamera().distortion);
}

TEST(CameraModel, ValidateNamesTheField) {
  EXPECT_EQ(Validate(ThesisCamera()), "");
  EXPECT_EQ(Validate(Rational()), "");
  CameraModel bad = ThesisCamera();
  bad.fx_px = -1;
  EXPECT_NE(Validate(bad).find("fx_px"), std::string::npos);
  bad = ThesisCamera();
  bad.distortion[1] = std::nan("");
  EXPECT_NE(Validate(bad).find("distortion"), std::string::npos);
  bad = ThesisCamera();
  bad.width_px = 0;
  EXPECT_NE(Validate(bad).find("width_px"), std::string::npos);
  bad = ThesisCamera();
  bad.distortion.resize(8);
  EXPECT_NE(Validate(bad).find("plumb_bob needs 4 or 5"), std::string::npos);
  bad = Rational();
  bad.distortion.resize(5);
  EXPECT_NE(Validate(bad).find("rational_polynomial needs 8"), std::string::npos);
  DistortionModel m;
  EXPECT_TRUE(DistortionModelFromName("rational_polynomial", &m));
  EXPECT_EQ(m, DistortionModel::kRationalPolynomial);
  EXPECT_FALSE(DistortionModelFromName("equidistant", &m));
}

}  // namespace
}  // namespace rig_model
