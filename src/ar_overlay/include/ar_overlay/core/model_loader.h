// Loads a model file through assimp (OBJ, DAE, STL, PLY, glTF, ...) into a Mesh,
// with node transforms applied, triangulated, with normals.
#pragma once

#include <string>

#include "ar_overlay/core/mesh.h"

namespace ar_overlay {

// Throws std::runtime_error "<path>: <assimp's reason>" when the file cannot be
// read or holds no triangles. Colours: the mesh's vertex colours, else its
// material's diffuse colour, else light grey.
Mesh LoadModel(const std::string& path);

}  // namespace ar_overlay
