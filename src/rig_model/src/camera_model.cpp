#include "rig_model/camera_model.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/LU>

namespace rig_model {
namespace {

// The coefficients with the absent ones zero: k1 k2 p1 p2 k3 k4 k5 k6.
struct Coefficients {
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0, k4 = 0, k5 = 0, k6 = 0;
  bool rational = false;
};

Coefficients Coeffs(const CameraModel& c) {
  Coefficients k;
  const std::vector<double>& d = c.distortion;
  double* out[8] = {&k.k1, &k.k2, &k.p1, &k.p2, &k.k3, &k.k4, &k.k5, &k.k6};
  for (size_t i = 0; i < d.size() && i < 8; ++i) *out[i] = d[i];
  k.rational = d.size() >= 8;  // OpenCV's rule: eight coefficients are the rational model
  return k;
}

}  // namespace

std::string DistortionModelName(DistortionModel model) {
  return model == DistortionModel::kRationalPolynomial ? "rational_polynomial" : "plumb_bob";
}

bool DistortionModelFromName(const std::string& name, DistortionModel* model) {
  if (name == "plumb_bob") {
    *model = DistortionModel::kPlumbBob;
  } else if (name == "rational_polynomial") {
    *model = DistortionModel::kRationalPolynomial;
  } else {
    return false;
  }
  return true;
}

bool CameraModel::HasDistortion() const {
  return std::any_of(distortion.begin(), distortion.end(), [](double d) { return d != 0.0; });
}

bool CameraModel::operator==(const CameraModel& o) const {
  return width_px == o.width_px && height_px == o.height_px && fx_px == o.fx_px && fy_px == o.fy_px &&
         cx_px == o.cx_px && cy_px == o.cy_px && distortion_model == o.distortion_model && distortion == o.distortion;
}

Eigen::Vector2d CameraModel::Distort(const Eigen::Vector2d& p) const {
  const Coefficients c = Coeffs(*this);
  const double x = p.x(), y = p.y();
  const double r2 = x * x + y * y;
  double radial = 1.0 + r2 * (c.k1 + r2 * (c.k2 + r2 * c.k3));
  if (c.rational) radial /= 1.0 + r2 * (c.k4 + r2 * (c.k5 + r2 * c.k6));
  // 3.10: radial term plus the tangential (decentering) term.
  return {x * radial + 2.0 * c.p1 * x * y + c.p2 * (r2 + 2.0 * x * x),
          y * radial + c.p1 * (r2 + 2.0 * y * y) + 2.0 * c.p2 * x * y};
}

Eigen::Matrix2d CameraModel::DistortJacobian(const Eigen::Vector2d& p) const {
  const Coefficients c = Coeffs(*this);
  const double x = p.x(), y = p.y();
  const double r2 = x * x + y * y;
  double radial = 1.0 + r2 * (c.k1 + r2 * (c.k2 + r2 * c.k3));
  double dradial = c.k1 + r2 * (2.0 * c.k2 + 3.0 * r2 * c.k3);  // d radial / d r2
  if (c.rational) {
    const double den = 1.0 + r2 * (c.k4 + r2 * (c.k5 + r2 * c.k6));
    const double dden = c.k4 + r2 * (2.0 * c.k5 + 3.0 * r2 * c.k6);
    dradial = (dradial * den - radial * dden) / (den * den);
    radial /= den;
  }
  Eigen::Matrix2d J;
  J(0, 0) = radial + 2.0 * x * x * dradial + 2.0 * c.p1 * y + 6.0 * c.p2 * x;
  J(0, 1) = 2.0 * x * y * dradial + 2.0 * c.p1 * x + 2.0 * c.p2 * y;
  J(1, 0) = 2.0 * x * y * dradial + 2.0 * c.p1 * x + 2.0 * c.p2 * y;
  J(1, 1) = radial + 2.0 * y * y * dradial + 6.0 * c.p1 * y + 2.0 * c.p2 * x;
  return J;
}

Eigen::Vector2d CameraModel::Undistort(const Eigen::Vector2d& d) const {
  Eigen::Vector2d p = d;
  for (int it = 0; it < 50; ++it) {  // 3.11
    const Eigen::Vector2d step = DistortJacobian(p).inverse() * (Distort(p) - d);
    p -= step;
    if (step.norm() < 1e-14) break;
  }
  return p;
}

bool CameraModel::Project(const Eigen::Vector3d& p, Eigen::Vector2d* uv, Eigen::Matrix<double, 2, 3>* J) const {
  if (!(p.z() > 1e-9)) return false;
  const Eigen::Vector2d n(p.x() / p.z(), p.y() / p.z());
  const Eigen::Vector2d d = Distort(n);
  *uv = Eigen::Vector2d(fx_px * d.x() + cx_px, fy_px * d.y() + cy_px);
  if (J) {
    Eigen::Matrix<double, 2, 3> J_n_p;
    J_n_p << 1.0 / p.z(), 0.0, -n.x() / p.z(), 0.0, 1.0 / p.z(), -n.y() / p.z();
    *J = Eigen::Vector2d(fx_px, fy_px).asDiagonal() * DistortJacobian(n) * J_n_p;
  }
  return true;
}

Eigen::Vector3d CameraModel::PixelRay(double u, double v) const {
  const Eigen::Vector2d p = Undistort(Eigen::Vector2d((u - cx_px) / fx_px, (v - cy_px) / fy_px));
  return {p.x(), p.y(), 1.0};
}

CameraModel CameraModel::Scaled(double factor) const {
  CameraModel c = *this;
  c.width_px = static_cast<int>(std::lround(width_px * factor));
  c.height_px = static_cast<int>(std::lround(height_px * factor));
  c.fx_px = fx_px * factor;
  c.fy_px = fy_px * factor;
  // Keep the principal point at the same place in the scaled image.
  c.cx_px = (cx_px + 0.5) * factor - 0.5;
  c.cy_px = (cy_px + 0.5) * factor - 0.5;
  return c;
}

std::string Validate(const CameraModel& k) {
  std::ostringstream err;
  if (k.width_px < 1 || k.height_px < 1 || k.width_px > 8192 || k.height_px > 8192) {
    err << "image size width_px x height_px = " << k.width_px << "x" << k.height_px << " is not in 1..8192";
  } else if (!(std::isfinite(k.fx_px) && k.fx_px > 0.0) || !(std::isfinite(k.fy_px) && k.fy_px > 0.0)) {
    err << "focal lengths fx_px = " << k.fx_px << ", fy_px = " << k.fy_px << " must be finite and > 0 (uncalibrated?)";
  } else if (!std::isfinite(k.cx_px) || !std::isfinite(k.cy_px)) {
    err << "principal point cx_px/cy_px must be finite";
  } else if (!std::all_of(k.distortion.begin(), k.distortion.end(), [](double d) { return std::isfinite(d); })) {
    err << "distortion coefficients must be finite";
  } else {
    const size_t n = k.distortion.size();
    if (k.distortion_model == DistortionModel::kPlumbBob && n != 0 && n != 4 && n != 5)
      err << "plumb_bob needs 4 or 5 distortion coefficients (k1 k2 p1 p2 [k3]), got " << n;
    if (k.distortion_model == DistortionModel::kRationalPolynomial && n != 0 && n != 8)
      err << "rational_polynomial needs 8 distortion coefficients (k1 k2 p1 p2 k3 k4 k5 k6), got " << n;
  }
  return err.str();
}

CameraModel ThesisCamera() {
  CameraModel c;
  c.width_px = 1024;
  c.height_px = 768;
  c.fx_px = 770.0;
  c.fy_px = 776.0;
  c.cx_px = 511.5;
  c.cy_px = 383.5;
  c.distortion_model = DistortionModel::kPlumbBob;
  c.distortion = {-0.22, 0.07, 0.0008, -0.0005, 0.0};
  return c;
}

}  // namespace rig_model
