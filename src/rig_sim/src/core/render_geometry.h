// Analytic primitives of the ray caster (internal to rig_sim). All vertical:
// cones stand upright, boxes and people only turn about z.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "rig_sim/scene.h"

namespace rig_sim {

enum class PrimKind : uint8_t { kCone, kBox, kCylinder, kDecal };

struct Prim {
  PrimKind kind = PrimKind::kCone;
  int16_t label = 0;
  Eigen::Vector3d sphere_center = Eigen::Vector3d::Zero();  // bounding sphere, for tile culling
  double sphere_radius = 0.0;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // cone apex; box/decal centre; cylinder base centre
  double cos_yaw = 1.0, sin_yaw = 0.0;
  Eigen::Vector3d half_size = Eigen::Vector3d::Zero();  // box/decal half sizes; cylinder (r, r, height)
  double height = 0.0, tau2 = 0.0, tau = 0.0;           // cone
  Eigen::Vector3f albedo = Eigen::Vector3f::Zero();
  int cone_index = -1;
  int platform_index = -1;  // boxes that are overlay test platforms: dots on the top face
};

// Candidate hit: t along the ray O + t d, and the outward unit normal.
struct Hit {
  double t = 1e300;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  const Prim* prim = nullptr;
};

// Updates *hit when the primitive is hit closer than hit->t (and t > 0).
void IntersectCone(const Prim& p, const Eigen::Vector3d& o, const Eigen::Vector3d& d, Hit* hit);
void IntersectBox(const Prim& p, const Eigen::Vector3d& o, const Eigen::Vector3d& d, Hit* hit);
void IntersectCylinder(const Prim& p, const Eigen::Vector3d& o, const Eigen::Vector3d& d, Hit* hit);
// Whether a ground point lies on a decal (flat patch or cone base plate).
bool OnDecal(const Prim& p, double x, double y);

// The scene as primitives: cones first (label 1 + i), then the rest.
std::vector<Prim> BuildPrims(const Scene& scene);

}  // namespace rig_sim
