// The models the project generates itself (thesis 6.5's three applications):
// MATLAB's peaks surface, a six-axis KR6-class manipulator, a C-130-like
// cargo aircraft, and the primitives they are built from. Units are metres.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "ar_overlay/core/mesh.h"

namespace ar_overlay {

using Rgba = std::array<float, 4>;

// MATLAB's peaks(x, y) on [-3, 3]^2.
double Peaks(double x, double y);
// The peaks surface on an n x n grid over [-3, 3]^2 (2 (n-1)^2 triangles),
// z = peaks(x, y), coloured by height with a parula-like map. n >= 2.
Mesh PeaksSurface(int n);

// Primitives, flat-shaded where they have edges, centred on the origin.
Mesh Box(float size_x, float size_y, float size_z, const Rgba& color);
// A frustum along +z from z = 0 (radius r0) to z = length (radius r1), capped.
Mesh Frustum(float r0, float r1, float length, int segments, const Rgba& color);

// The virtual object of the overlay test platform (7.2): rows x cols flat
// discs in the z = 0 plane facing +z, centred on the origin, `spacing` apart.
Mesh DotGrid(int rows, int cols, float spacing, float radius, int segments, const Rgba& color);

// A C-130-like four-engine cargo aircraft (about 30 m long, 40 m span),
// nose along +x, high wing, z up, origin on the fuselage axis under the
// wing's centre. The propeller discs are translucent.
Mesh CargoAircraft();

// A KR6-class six-axis arm as seven links; link i rotates about joint i.
struct ArmLink {
  std::string name;              // file stem, e.g. "kr6_link1"
  std::string joint;             // "" for the base
  std::array<double, 3> xyz{};   // joint origin in the parent link (m)
  std::array<double, 3> axis{};  // joint axis in the parent link
  Mesh mesh;                     // in the link's own frame
};
std::vector<ArmLink> Kr6Arm();

}  // namespace ar_overlay
