#include "rig_sim/camera_model.h"

#include <cmath>
#include <sstream>

#include <Eigen/LU>

namespace rig_sim {

CameraConfig CameraConfig::Scaled(double factor) const {
  CameraConfig c = *this;
  c.width_px = static_cast<int>(std::lround(width_px * factor));
  c.height_px = static_cast<int>(std::lround(height_px * factor));
  c.fu_px = fu_px * factor;
  c.fv_px = fv_px * factor;
  // Keep the principal point at the centre of the scaled image.
  c.cu_px = (cu_px + 0.5) * factor - 0.5;
  c.cv_px = (cv_px + 0.5) * factor - 0.5;
  return c;
}

std::string CameraConfig::Validate() const {
  std::ostringstream err;
  if (width_px < 8 || height_px < 8 || width_px > 8192 || height_px > 8192)
    err << "width_px/height_px must be in [8, 8192], got " << width_px << "x" << height_px;
  else if (!(fu_px > 0.0) || !(fv_px > 0.0))
    err << "fu_px and fv_px must be positive";
  else if (!std::isfinite(cu_px) || !std::isfinite(cv_px))
    err << "cu_px/cv_px must be finite";
  else if (!std::isfinite(k1) || !std::isfinite(k2) || !std::isfinite(p1) || !std::isfinite(p2) || !std::isfinite(k3))
    err << "distortion coefficients must be finite";
  else if (!(rate_hz > 0.0))
    err << "rate_hz must be positive";
  return err.str();
}

CameraModel::CameraModel(const CameraConfig& config) : config_(config) {}

Eigen::Vector2d CameraModel::Distort(const Eigen::Vector2d& p) const {
  const CameraConfig& c = config_;
  const double x = p.x(), y = p.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (c.k1 + r2 * (c.k2 + r2 * c.k3));
  // (3.10): radial term plus the tangential (decentering) term.
  return {x * radial + 2.0 * c.p1 * x * y + c.p2 * (r2 + 2.0 * x * x),
          y * radial + c.p1 * (r2 + 2.0 * y * y) + 2.0 * c.p2 * x * y};
}

Eigen::Vector2d CameraModel::Undistort(const Eigen::Vector2d& d) const {
  const CameraConfig& c = config_;
  Eigen::Vector2d p = d;
  for (int it = 0; it < 50; ++it) {
    const double x = p.x(), y = p.y();
    const double r2 = x * x + y * y;
    const double radial = 1.0 + r2 * (c.k1 + r2 * (c.k2 + r2 * c.k3));
    const double dradial = c.k1 + r2 * (2.0 * c.k2 + 3.0 * r2 * c.k3);  // d radial / d r2
    Eigen::Matrix2d J;
    J(0, 0) = radial + 2.0 * x * x * dradial + 2.0 * c.p1 * y + 6.0 * c.p2 * x;
    J(0, 1) = 2.0 * x * y * dradial + 2.0 * c.p1 * x + 2.0 * c.p2 * y;
    J(1, 0) = 2.0 * x * y * dradial + 2.0 * c.p1 * x + 2.0 * c.p2 * y;
    J(1, 1) = radial + 2.0 * y * y * dradial + 6.0 * c.p1 * y + 2.0 * c.p2 * x;
    const Eigen::Vector2d step = J.inverse() * (Distort(p) - d);
    p -= step;
    if (step.norm() < 1e-14) break;
  }
  return p;
}

bool CameraModel::Project(const Eigen::Vector3d& p, Eigen::Vector2d* uv) const {
  if (!(p.z() > 1e-9)) return false;
  const Eigen::Vector2d d = Distort(Eigen::Vector2d(p.x() / p.z(), p.y() / p.z()));
  *uv = Eigen::Vector2d(config_.fu_px * d.x() + config_.cu_px, config_.fv_px * d.y() + config_.cv_px);
  return true;
}

Eigen::Vector3d CameraModel::PixelRay(double u, double v) const {
  const Eigen::Vector2d d((u - config_.cu_px) / config_.fu_px, (v - config_.cv_px) / config_.fv_px);
  const Eigen::Vector2d p = Undistort(d);
  return {p.x(), p.y(), 1.0};
}

}  // namespace rig_sim
