// A triangle mesh as the renderer wants it: interleaved position, normal and
// RGBA colour per vertex, 32-bit indices. Models from assimp and the
// project's generated models (mesh_generators.h) both end up here.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace ar_overlay {

struct Vertex {
  float position[3];
  float normal[3];
  float color[4];  // linear RGBA in [0, 1]
};

struct Mesh {
  std::vector<Vertex> vertices;
  std::vector<uint32_t> indices;  // three per triangle

  size_t TriangleCount() const { return indices.size() / 3; }
  // Appends `other` moved by T_this_other (normals rotated with it).
  void Append(const Mesh& other, const Eigen::Isometry3f& T_this_other = Eigen::Isometry3f::Identity());
};

// Writes `mesh` as ASCII PLY with normals and 8-bit colours, which assimp
// reads back; throws std::runtime_error naming the file.
void WritePly(const Mesh& mesh, const std::string& path);

}  // namespace ar_overlay
