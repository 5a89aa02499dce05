#include "ar_overlay/core/mesh_generators.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ar_overlay {
namespace {

using Eigen::AngleAxisf;
using Eigen::Isometry3f;
using Eigen::Vector3f;

Vertex MakeVertex(const Vector3f& p, const Vector3f& n, const Rgba& c) {
  return Vertex{{p.x(), p.y(), p.z()}, {n.x(), n.y(), n.z()}, {c[0], c[1], c[2], c[3]}};
}

// MATLAB's parula, coarsely: blue through teal to yellow.
Rgba Parula(double s) {
  static const float kStops[5][3] = {{0.21f, 0.17f, 0.53f},
                                     {0.07f, 0.44f, 0.88f},
                                     {0.13f, 0.72f, 0.69f},
                                     {0.65f, 0.75f, 0.24f},
                                     {0.98f, 0.98f, 0.05f}};
  s = std::clamp(s, 0.0, 1.0) * 4.0;
  const int i = std::min(static_cast<int>(s), 3);
  const float f = static_cast<float>(s - i);
  Rgba c{0, 0, 0, 1};
  for (int k = 0; k < 3; ++k) c[k] = kStops[i][k] * (1 - f) + kStops[i + 1][k] * f;
  return c;
}

Isometry3f At(float x, float y, float z, const AngleAxisf& r = AngleAxisf(0, Vector3f::UnitZ())) {
  Isometry3f T = Isometry3f::Identity();
  T.translate(Vector3f(x, y, z));
  T.rotate(r);
  return T;
}

const AngleAxisf kZToX(static_cast<float>(M_PI / 2), Vector3f::UnitY());
const AngleAxisf kZToY(static_cast<float>(-M_PI / 2), Vector3f::UnitX());

// A cylinder of `length` centred on the origin along z.
Mesh Cylinder(float r, float length, const Rgba& c) {
  Mesh m;
  m.Append(Frustum(r, r, length, 32, c), At(0, 0, -length / 2));
  return m;
}

}  // namespace

double Peaks(double x, double y) {
  return 3 * (1 - x) * (1 - x) * std::exp(-x * x - (y + 1) * (y + 1)) -
         10 * (x / 5 - x * x * x - std::pow(y, 5)) * std::exp(-x * x - y * y) -
         1.0 / 3 * std::exp(-(x + 1) * (x + 1) - y * y);
}

Mesh PeaksSurface(int n) {
  if (n < 2) throw std::invalid_argument("PeaksSurface: n must be >= 2");
  const double z_min = -6.55, z_max = 8.11, h = 1e-4;  // peaks' range on [-3, 3]^2
  Mesh m;
  m.vertices.reserve(static_cast<size_t>(n) * n);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double x = -3 + 6.0 * i / (n - 1), y = -3 + 6.0 * j / (n - 1), z = Peaks(x, y);
      const double dzdx = (Peaks(x + h, y) - Peaks(x - h, y)) / (2 * h);
      const double dzdy = (Peaks(x, y + h) - Peaks(x, y - h)) / (2 * h);
      const Vector3f normal = Vector3f(static_cast<float>(-dzdx), static_cast<float>(-dzdy), 1.0f).normalized();
      m.vertices.push_back(MakeVertex(Vector3f(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)),
                                      normal, Parula((z - z_min) / (z_max - z_min))));
    }
  }
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const auto a = static_cast<uint32_t>(j * n + i), b = a + 1, c = a + static_cast<uint32_t>(n), d = c + 1;
      m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
    }
  }
  return m;
}

Mesh Box(float sx, float sy, float sz, const Rgba& color) {
  Mesh m;
  const Vector3f half(sx / 2, sy / 2, sz / 2);
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign = -1; sign <= 1; sign += 2) {
      Vector3f n = Vector3f::Zero();
      n[axis] = static_cast<float>(sign);
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const auto base = static_cast<uint32_t>(m.vertices.size());
      for (int k = 0; k < 4; ++k) {
        Vector3f p = n.cwiseProduct(half);
        p[u] = ((k == 1 || k == 2) ? 1.0f : -1.0f) * half[u];
        p[v] = (k >= 2 ? 1.0f : -1.0f) * half[v];
        m.vertices.push_back(MakeVertex(p, n, color));
      }
      m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
  }
  return m;
}

Mesh Frustum(float r0, float r1, float length, int segments, const Rgba& color) {
  Mesh m;
  const float slope = (r0 - r1) / length;
  for (int s = 0; s <= segments; ++s) {  // the side, smooth
    const float a = static_cast<float>(2 * M_PI * s / segments), c = std::cos(a), sn = std::sin(a);
    const Vector3f n = Vector3f(c, sn, slope).normalized();
    m.vertices.push_back(MakeVertex(Vector3f(r0 * c, r0 * sn, 0), n, color));
    m.vertices.push_back(MakeVertex(Vector3f(r1 * c, r1 * sn, length), n, color));
  }
  for (uint32_t s = 0; s < static_cast<uint32_t>(segments); ++s) {
    const uint32_t a = 2 * s;
    m.indices.insert(m.indices.end(), {a, a + 2, a + 3, a, a + 3, a + 1});
  }
  for (int cap = 0; cap < 2; ++cap) {  // the caps, flat
    const float z = cap ? length : 0, r = cap ? r1 : r0;
    if (r <= 0) continue;
    const Vector3f n(0, 0, cap ? 1.0f : -1.0f);
    const auto centre = static_cast<uint32_t>(m.vertices.size());
    m.vertices.push_back(MakeVertex(Vector3f(0, 0, z), n, color));
    for (int s = 0; s <= segments; ++s) {
      const float a = static_cast<float>(2 * M_PI * s / segments);
      m.vertices.push_back(MakeVertex(Vector3f(r * std::cos(a), r * std::sin(a), z), n, color));
    }
    for (uint32_t s = 0; s < static_cast<uint32_t>(segments); ++s)
      m.indices.insert(m.indices.end(), {centre, centre + 1 + s, centre + 2 + s});
  }
  return m;
}

Mesh DotGrid(int rows, int cols, float spacing, float radius, int segments, const Rgba& color) {
  if (rows < 1 || cols < 1 || segments < 3 || !(radius > 0) || !(spacing > 2 * radius))
    throw std::invalid_argument("DotGrid: need rows, cols >= 1, segments >= 3, 0 < radius < spacing / 2");
  Mesh m;
  const Vector3f up = Vector3f::UnitZ();
  for (int r = 0; r < rows; ++r)
    for (int k = 0; k < cols; ++k) {
      const float x = (k - 0.5f * (cols - 1)) * spacing, y = (r - 0.5f * (rows - 1)) * spacing;
      const auto centre = static_cast<uint32_t>(m.vertices.size());
      m.vertices.push_back(MakeVertex(Vector3f(x, y, 0), up, color));
      for (int i = 0; i < segments; ++i) {
        const double a = 2 * M_PI * i / segments;
        m.vertices.push_back(MakeVertex(
            Vector3f(x + radius * static_cast<float>(std::cos(a)), y + radius * static_cast<float>(std::sin(a)), 0), up,
            color));
        const auto next = static_cast<uint32_t>((i + 1) % segments);
        m.indices.insert(m.indices.end(), {centre, centre + 1 + static_cast<uint32_t>(i), centre + 1 + next});
      }
    }
  return m;
}

Mesh CargoAircraft() {
  const Rgba body{0.42f, 0.47f, 0.40f, 1}, dark{0.25f, 0.27f, 0.25f, 1}, glass{0.1f, 0.12f, 0.2f, 1};
  const Rgba prop{0.15f, 0.15f, 0.15f, 0.35f};
  const float r = 2.15f;  // C-130: 29.8 m long, 40.4 m span, fuselage about 4.3 m across
  Mesh m;
  m.Append(Cylinder(r, 18, body), At(0, 0, 0, kZToX));
  m.Append(Frustum(r, 0.9f, 3.5f, 32, body), At(9, 0, 0, kZToX));         // nose
  m.Append(Frustum(0.9f, 0.2f, 1.0f, 32, body), At(12.5f, 0, 0, kZToX));  // radome
  m.Append(Box(1.2f, 2.6f, 0.8f, glass), At(10.2f, 0, 1.5f));             // cockpit windows
  m.Append(Frustum(r, 0.5f, 8.0f, 32, body),
           At(-9, 0, 0.2f, AngleAxisf(static_cast<float>(-M_PI / 2 + 0.12), Vector3f::UnitY())));  // upswept tail
  m.Append(Box(4.0f, 40.4f, 0.5f, body), At(0, 0, r + 0.1f));                                      // high wing
  m.Append(Box(5.0f, 0.5f, 6.5f, body), At(-14.5f, 0, 4.6f));                                      // fin
  m.Append(Box(3.5f, 16.0f, 0.3f, body), At(-15.5f, 0, 1.4f));                                     // tailplane
  const float engines_y[4] = {-10.5f, -5.5f, 5.5f, 10.5f};
  for (float y : engines_y) m.Append(Frustum(0.65f, 0.45f, 5.0f, 24, dark), At(-2.0f, y, 1.6f, kZToX));
  m.Append(Box(3.0f, 1.2f, 1.6f, dark), At(0.5f, 3.0f, -r + 0.2f));  // landing-gear sponsons
  m.Append(Box(3.0f, 1.2f, 1.6f, dark), At(0.5f, -3.0f, -r + 0.2f));
  for (float y : engines_y) m.Append(Cylinder(2.05f, 0.08f, prop), At(3.2f, y, 1.6f, kZToX));  // last: translucent
  return m;
}

std::vector<ArmLink> Kr6Arm() {
  // KR6 R900-class lengths: A1 to A2 0.4 m high with a 0.025 m offset, upper
  // arm 0.455 m, A3 to A4 0.035 m, forearm to the wrist 0.42 m, wrist to flange 0.08 m.
  const Rgba orange{1.0f, 0.45f, 0.0f, 1}, grey{0.22f, 0.22f, 0.24f, 1};
  std::vector<ArmLink> links(7);
  links[0] = {"kr6_link0", "", {0, 0, 0}, {0, 0, 1}, {}};
  links[0].mesh.Append(Frustum(0.16f, 0.13f, 0.1f, 32, grey));
  links[1] = {"kr6_link1", "joint_a1", {0, 0, 0.1}, {0, 0, 1}, {}};
  links[1].mesh.Append(Frustum(0.13f, 0.11f, 0.18f, 32, orange));
  links[1].mesh.Append(Box(0.18f, 0.2f, 0.14f, orange), At(0.02f, 0, 0.24f));
  links[2] = {"kr6_link2", "joint_a2", {0.025, 0, 0.3}, {0, 1, 0}, {}};
  links[2].mesh.Append(Cylinder(0.085f, 0.26f, grey), At(0, 0, 0, kZToY));
  links[2].mesh.Append(Box(0.1f, 0.12f, 0.455f, orange), At(0, 0.05f, 0.2275f));
  links[3] = {"kr6_link3", "joint_a3", {0, 0, 0.455}, {0, 1, 0}, {}};
  links[3].mesh.Append(Cylinder(0.075f, 0.24f, grey), At(0, 0, 0, kZToY));
  links[3].mesh.Append(Box(0.2f, 0.14f, 0.14f, orange), At(0.06f, 0, 0.035f));
  links[4] = {"kr6_link4", "joint_a4", {0.16, 0, 0.035}, {1, 0, 0}, {}};
  links[4].mesh.Append(Frustum(0.06f, 0.045f, 0.26f, 32, orange), At(0, 0, 0, kZToX));
  links[5] = {"kr6_link5", "joint_a5", {0.26, 0, 0}, {0, 1, 0}, {}};
  links[5].mesh.Append(Cylinder(0.045f, 0.1f, grey), At(0, 0, 0, kZToY));
  links[5].mesh.Append(Box(0.06f, 0.07f, 0.07f, orange), At(0.03f, 0, 0));
  links[6] = {"kr6_link6", "joint_a6", {0.08, 0, 0}, {1, 0, 0}, {}};
  links[6].mesh.Append(Cylinder(0.032f, 0.012f, grey), At(0, 0, 0, kZToX));
  links[6].mesh.Append(Frustum(0.02f, 0.003f, 0.06f, 16, grey), At(0.006f, 0, 0, kZToX));  // a pointer tool
  return links;
}

}  // namespace ar_overlay
