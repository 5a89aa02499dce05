// Draws meshes at poses into an offscreen framebuffer sized for the camera and
// returns an RGBA overlay in the raw image's geometry. Depth-tested, lit
// (Lambert diffuse + Blinn-Phong specular, headlight near the camera), with
// per-vertex and per-draw alpha; transparent pixels have alpha 0.
//
// Not thread-safe: construct, use and destroy on one thread (egl_context.h).
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "ar_overlay/core/camera_projection.h"
#include "ar_overlay/core/egl_context.h"
#include "ar_overlay/core/mesh.h"

namespace ar_overlay {

struct DrawItem {
  int mesh_id = -1;
  Eigen::Matrix4f T_cones_model = Eigen::Matrix4f::Identity();  // may include scale
  float alpha = 1.0f;
  Eigen::Vector4f color_override = Eigen::Vector4f::Zero();  // rgb, weight in w (0: vertex colours)
};

struct RenderConfig {
  double near_m = 0.05;
  double far_m = 200.0;
  // Level of detail: a mesh of at least kLodMinTriangles gets coarser copies
  // (meshoptimizer's quadric simplifier, each about half the triangles of the
  // last, over the same vertices, so normals and colours are unchanged), and
  // each frame draws the coarsest whose geometric error, projected at the
  // mesh's nearest vertex, is at most this many pixels. 0: always the full mesh.
  double lod_max_error_px = 0.5;
};

constexpr size_t kLodMinTriangles = 4096;

class Renderer {
 public:
  explicit Renderer(const RenderConfig& config = RenderConfig());
  ~Renderer();

  // Uploads a mesh; returns its id for DrawItem::mesh_id.
  int AddMesh(const Mesh& mesh);
  // Rebuilds the framebuffer and distortion map when the intrinsics change.
  void SetCamera(const CameraModel& k);
  // Renders `items` seen from T_camera_cones (p_camera = R p_cones + t) into
  // `overlay_rgba` (CV_8UC4, the camera's size, premultiplied R G B A, zero
  // outside the models); it refers to the renderer's own buffer, valid (and
  // not to be written) until the next Render. Returns the region that can hold model pixels: only
  // there are pixels read back, remapped and (by the caller) composited, the
  // frame's main cost after the rasterisation itself.
  cv::Rect Render(const std::vector<DrawItem>& items, const Eigen::Isometry3d& T_camera_cones, cv::Mat& overlay_rgba);

  const std::string& gl_renderer() const { return egl_.renderer(); }
  // Triangles drawn by the last Render (after the level-of-detail choice).
  size_t drawn_triangles() const { return drawn_triangles_; }
  // A mesh's levels of detail as (triangles, geometric error in the mesh's
  // units), finest (the mesh itself, error 0) first.
  std::vector<std::pair<size_t, float>> LevelsOfDetail(int mesh_id) const;

 private:
  struct Gl;  // GL object names, kept out of this header
  EglContext egl_;
  RenderConfig config_;
  CameraModel camera_;
  std::unique_ptr<DistortionMap> map_;
  std::unique_ptr<Gl> gl_;
  cv::Mat canvas_;
  cv::Rect canvas_written_;   // canvas_ is zero outside it
  cv::Mat overlay_;           // what Render hands out,
  cv::Rect overlay_written_;  // zero outside this
  size_t drawn_triangles_ = 0;
  // Where the items can appear on the canvas: their bounding boxes projected.
  cv::Rect CanvasRoi(const std::vector<DrawItem>& items, const Eigen::Matrix4f& T_camera_cones) const;
  // (Re)allocates the framebuffer when a width x height region does not fit or
  // would fit in a quarter of it.
  void FitFramebuffer(int width, int height);
  // Index of the level of detail to draw for a mesh at T_camera_model.
  size_t ChooseLevel(int mesh_id, const Eigen::Matrix4f& T_camera_model) const;
};

}  // namespace ar_overlay
