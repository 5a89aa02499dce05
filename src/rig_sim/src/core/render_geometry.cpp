#include "render_geometry.h"

#include <cmath>

namespace rig_sim {

void IntersectCone(const Prim& p, const Eigen::Vector3d& o_world, const Eigen::Vector3d& d, Hit* hit) {
  // Apex at the origin of the quadric x^2 + y^2 = tau^2 z^2, body for z in [-h, 0].
  const Eigen::Vector3d o = o_world - p.origin;
  const double a = d.x() * d.x() + d.y() * d.y() - p.tau2 * d.z() * d.z();
  const double b = 2.0 * (o.x() * d.x() + o.y() * d.y() - p.tau2 * o.z() * d.z());
  const double c = o.x() * o.x() + o.y() * o.y() - p.tau2 * o.z() * o.z();
  double roots[2];
  int n = 0;
  if (std::fabs(a) < 1e-14) {
    if (std::fabs(b) < 1e-300) return;
    roots[n++] = -c / b;
  } else {
    const double disc = b * b - 4.0 * a * c;
    if (disc < 0.0) return;
    const double sq = std::sqrt(disc);
    // Numerically stable pair of roots.
    const double q = -0.5 * (b + (b >= 0.0 ? sq : -sq));
    double r0 = q / a, r1 = (q != 0.0) ? c / q : r0;
    if (r0 > r1) std::swap(r0, r1);
    roots[n++] = r0;
    roots[n++] = r1;
  }
  for (int i = 0; i < n; ++i) {
    const double t = roots[i];
    if (!(t > 1e-9) || t >= hit->t) continue;
    const Eigen::Vector3d q = o + t * d;
    if (q.z() > 0.0 || q.z() < -p.height) continue;  // the other nappe, or below the base
    const double rxy = std::sqrt(q.x() * q.x() + q.y() * q.y());
    const double s = std::sqrt(1.0 + p.tau2);
    Eigen::Vector3d n =
        rxy > 1e-12 ? Eigen::Vector3d(q.x() / rxy / s, q.y() / rxy / s, p.tau / s) : Eigen::Vector3d::UnitZ();
    hit->t = t;
    hit->normal = n;
    hit->prim = &p;
    return;
  }
}

void IntersectBox(const Prim& p, const Eigen::Vector3d& o_world, const Eigen::Vector3d& d_world, Hit* hit) {
  const Eigen::Vector3d r = o_world - p.origin;
  // Into the box frame (rotation by -yaw about z).
  const Eigen::Vector3d o(p.cos_yaw * r.x() + p.sin_yaw * r.y(), -p.sin_yaw * r.x() + p.cos_yaw * r.y(), r.z());
  const Eigen::Vector3d d(p.cos_yaw * d_world.x() + p.sin_yaw * d_world.y(),
                          -p.sin_yaw * d_world.x() + p.cos_yaw * d_world.y(), d_world.z());
  double t_near = -1e300, t_far = 1e300;
  int axis = -1;
  for (int i = 0; i < 3; ++i) {
    if (std::fabs(d[i]) < 1e-15) {
      if (std::fabs(o[i]) > p.half_size[i]) return;
      continue;
    }
    double t0 = (-p.half_size[i] - o[i]) / d[i], t1 = (p.half_size[i] - o[i]) / d[i];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > t_near) t_near = t0, axis = i;
    t_far = std::min(t_far, t1);
  }
  if (t_near > t_far || !(t_near > 1e-9) || t_near >= hit->t || axis < 0) return;
  Eigen::Vector3d n_local = Eigen::Vector3d::Zero();
  n_local[axis] = d[axis] > 0.0 ? -1.0 : 1.0;
  hit->t = t_near;
  hit->normal = Eigen::Vector3d(p.cos_yaw * n_local.x() - p.sin_yaw * n_local.y(),
                                p.sin_yaw * n_local.x() + p.cos_yaw * n_local.y(), n_local.z());
  hit->prim = &p;
}

void IntersectCylinder(const Prim& p, const Eigen::Vector3d& o_world, const Eigen::Vector3d& d, Hit* hit) {
  const Eigen::Vector3d o = o_world - p.origin;
  const double r = p.half_size.x(), h = p.height;
  const double a = d.x() * d.x() + d.y() * d.y();
  if (a > 1e-15) {
    const double b = 2.0 * (o.x() * d.x() + o.y() * d.y());
    const double c = o.x() * o.x() + o.y() * o.y() - r * r;
    const double disc = b * b - 4.0 * a * c;
    if (disc >= 0.0) {
      const double t = (-b - std::sqrt(disc)) / (2.0 * a);
      const double z = o.z() + t * d.z();
      if (t > 1e-9 && t < hit->t && z >= 0.0 && z <= h) {
        const Eigen::Vector3d q = o + t * d;
        hit->t = t;
        hit->normal = Eigen::Vector3d(q.x() / r, q.y() / r, 0.0);
        hit->prim = &p;
        return;
      }
    }
  }
  if (d.z() < 0.0) {  // top cap, seen from above
    const double t = (h - o.z()) / d.z();
    const Eigen::Vector3d q = o + t * d;
    if (t > 1e-9 && t < hit->t && q.x() * q.x() + q.y() * q.y() <= r * r) {
      hit->t = t;
      hit->normal = Eigen::Vector3d::UnitZ();
      hit->prim = &p;
    }
  }
}

bool OnDecal(const Prim& p, double x, double y) {
  const double rx = x - p.origin.x(), ry = y - p.origin.y();
  const double lx = p.cos_yaw * rx + p.sin_yaw * ry, ly = -p.sin_yaw * rx + p.cos_yaw * ry;
  return std::fabs(lx) <= p.half_size.x() && std::fabs(ly) <= p.half_size.y();
}

namespace {

// A box or ground decal turned by yaw about the vertical through its centre.
Prim YawedPrim(PrimKind kind, int16_t label, const Eigen::Vector3d& center, double yaw_rad,
               const Eigen::Vector3d& half_size, const Eigen::Vector3d& albedo) {
  Prim p;
  p.kind = kind;
  p.label = label;
  p.origin = center;
  p.cos_yaw = std::cos(yaw_rad);
  p.sin_yaw = std::sin(yaw_rad);
  p.half_size = half_size;
  p.albedo = albedo.cast<float>();
  p.sphere_center = center;
  p.sphere_radius = half_size.norm() * 1.001;
  return p;
}

}  // namespace

std::vector<Prim> BuildPrims(const Scene& scene) {
  std::vector<Prim> prims;
  for (size_t i = 0; i < scene.cones.size(); ++i) {
    const ConeSpec& c = scene.cones[i];
    Prim p;
    p.kind = PrimKind::kCone;
    p.label = static_cast<int16_t>(1 + i);
    p.cone_index = static_cast<int>(i);
    p.origin = c.peak_m();
    p.height = c.height_m;
    p.tau = c.tau;
    p.tau2 = c.tau * c.tau;
    p.sphere_center = c.mid_m();
    p.sphere_radius = std::hypot(0.5 * c.height_m, c.radius_m()) * 1.001;
    p.albedo = c.albedo.cast<float>();
    prims.push_back(p);
  }
  int16_t label = 1000;
  for (size_t i = 0; i < scene.cones.size(); ++i) {  // black base plates of road cones
    const ConeSpec& c = scene.cones[i];
    if (c.base_plate_m <= 0.0 || c.base_m.z() > 1e-6) continue;
    Prim p;
    p.kind = PrimKind::kDecal;
    p.label = 0;  // part of the ground
    p.origin = c.base_m;
    p.half_size = Eigen::Vector3d(0.5 * c.base_plate_m, 0.5 * c.base_plate_m, 0.0);
    p.albedo = Eigen::Vector3f(0.03f, 0.03f, 0.03f);
    p.sphere_center = c.base_m;
    p.sphere_radius = 0.75 * c.base_plate_m;
    prims.push_back(p);
  }
  for (const BoxSpec& b : scene.boxes)
    prims.push_back(YawedPrim(PrimKind::kBox, label++, b.center_m, b.yaw_rad, 0.5 * b.size_m, b.albedo));
  for (size_t i = 0; i < scene.platforms.size(); ++i) {
    const PlatformSpec& b = scene.platforms[i];
    const Eigen::Vector3d center(b.center_m.x(), b.center_m.y(), 0.5 * b.size_m.z());
    prims.push_back(YawedPrim(PrimKind::kBox, label++, center, b.yaw_rad, 0.5 * b.size_m, b.albedo));
    prims.back().platform_index = static_cast<int>(i);
  }
  for (const PatchSpec& s : scene.patches) {
    const Eigen::Vector3d center(s.center_m.x(), s.center_m.y(), 0.0);
    const Eigen::Vector3d half_size(0.5 * s.size_m.x(), 0.5 * s.size_m.y(), 0.0);
    prims.push_back(YawedPrim(PrimKind::kDecal, label++, center, s.yaw_rad, half_size, s.albedo));
  }
  for (const PersonSpec& s : scene.people) {
    Prim p;
    p.kind = PrimKind::kCylinder;
    p.label = label++;
    p.origin = Eigen::Vector3d(s.position_m.x(), s.position_m.y(), 0.0);
    p.half_size = Eigen::Vector3d(s.radius_m, s.radius_m, 0.0);
    p.height = s.height_m;
    p.albedo = Eigen::Vector3f(0.95f, 0.30f, 0.02f);  // hi-vis orange vest
    p.sphere_center = p.origin + Eigen::Vector3d(0, 0, 0.5 * s.height_m);
    p.sphere_radius = std::hypot(0.5 * s.height_m, s.radius_m) * 1.001;
    prims.push_back(p);
  }
  return prims;
}

}  // namespace rig_sim
