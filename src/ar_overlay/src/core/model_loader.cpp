#include "ar_overlay/core/model_loader.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <stdexcept>

namespace ar_overlay {

Mesh LoadModel(const std::string& path) {
  Assimp::Importer importer;
  // Validation runs first and turns a broken file (indices out of range) into an
  // error instead of a crash in the later steps. Pre-transforming flattens the node hierarchy into the file's root
  // frame; the YAML's pose and scale place that frame in `cones`.
  const aiScene* scene = importer.ReadFile(path, aiProcess_ValidateDataStructure | aiProcess_Triangulate |
                                                     aiProcess_JoinIdenticalVertices | aiProcess_GenSmoothNormals |
                                                     aiProcess_PreTransformVertices | aiProcess_SortByPType);
  if (scene == nullptr) throw std::runtime_error(path + ": " + importer.GetErrorString());
  Mesh out;
  for (unsigned mi = 0; mi < scene->mNumMeshes; ++mi) {
    const aiMesh* m = scene->mMeshes[mi];
    if (!(m->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || m->mNormals == nullptr) continue;
    aiColor4D diffuse(0.8f, 0.8f, 0.8f, 1.0f);
    if (m->mMaterialIndex < scene->mNumMaterials) {
      const aiMaterial* mat = scene->mMaterials[m->mMaterialIndex];
      if (aiGetMaterialColor(mat, AI_MATKEY_COLOR_DIFFUSE, &diffuse) != AI_SUCCESS)
        aiGetMaterialColor(mat, AI_MATKEY_BASE_COLOR, &diffuse);  // glTF's PBR colour
    }
    const auto base = static_cast<uint32_t>(out.vertices.size());
    for (unsigned i = 0; i < m->mNumVertices; ++i) {
      const aiVector3D& p = m->mVertices[i];
      const aiVector3D& n = m->mNormals[i];
      const aiColor4D c = m->HasVertexColors(0) ? m->mColors[0][i] : diffuse;
      out.vertices.push_back(Vertex{{p.x, p.y, p.z}, {n.x, n.y, n.z}, {c.r, c.g, c.b, c.a}});
    }
    for (unsigned f = 0; f < m->mNumFaces; ++f) {
      const aiFace& face = m->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines sorted into their own meshes, but be sure
      for (int k = 0; k < 3; ++k) out.indices.push_back(base + face.mIndices[k]);
    }
  }
  if (out.indices.empty()) throw std::runtime_error(path + ": assimp read the file but found no triangles in it");
  return out;
}

}  // namespace ar_overlay
