#include "ar_overlay/core/renderer.h"

#include <GLES3/gl3.h>
#include <malloc.h>
#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ar_overlay {
namespace {

const char* kVertexShader = R"(#version 300 es
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_color;
uniform mat4 u_model_view;   // camera_from_model
uniform mat3 u_normal_matrix;
uniform mat4 u_projection;
out vec3 v_normal_c;
out vec4 v_color;
void main() {
  vec4 p = u_model_view * vec4(a_position, 1.0);
  v_normal_c = u_normal_matrix * a_normal;
  v_color = a_color;
  gl_Position = u_projection * p;
}
)";

// Lambert diffuse plus Blinn-Phong specular from a headlight above and left of
// the camera; two-sided so open surfaces (peaks) are lit from below too.
// Output is premultiplied by alpha, which is what remap's interpolation at
// model edges and the composite (composite.cpp) expect.
// The direction to the eye is the pixel's ray, (u - cx) / fx, (v - cy) / fy, 1
// from gl_FragCoord (u_ray), not an interpolated camera-frame position: the
// same vector, but three fewer varyings for llvmpipe to set up per triangle
// and interpolate per pixel, which is where its time goes with small triangles.
const char* kFragmentShader = R"(#version 300 es
precision highp float;
in vec3 v_normal_c;
in vec4 v_color;
uniform float u_alpha;
uniform vec4 u_color_override;
uniform vec4 u_ray;  // x/z = fragcoord.x * u_ray.x + u_ray.y, y/z likewise with zw
out vec4 o_color;
void main() {
  vec3 n = normalize(v_normal_c);
  vec3 to_eye = -normalize(vec3(gl_FragCoord.xy * u_ray.xz + u_ray.yw, 1.0));
  if (dot(n, to_eye) < 0.0) n = -n;
  vec3 to_light = normalize(vec3(-0.3, -0.6, -1.0));
  float diffuse = max(dot(n, to_light), 0.0);
  // x^32 by five squarings: llvmpipe's pow is exp2(32 log2 x), several times the cost.
  float specular = max(dot(n, normalize(to_light + to_eye)), 0.0);
  specular *= specular;
  specular *= specular;
  specular *= specular;
  specular *= specular;
  specular *= specular;
  vec3 base = mix(v_color.rgb, u_color_override.rgb, u_color_override.a);
  vec3 rgb = min(base * (0.3 + 0.7 * diffuse) + vec3(0.25 * specular), vec3(1.0));
  float a = v_color.a * u_alpha;
  o_color = vec4(rgb * a, a);
}
)";

GLuint Compile(GLenum type, const char* source) {
  GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[1024] = {0};
    glGetShaderInfoLog(shader, sizeof(log), nullptr, log);
    throw std::runtime_error(std::string("ar_overlay: shader compile failed: ") + log);
  }
  return shader;
}

}  // namespace

struct Renderer::Gl {
  GLuint program = 0;
  GLint u_model_view = -1, u_normal_matrix = -1, u_projection = -1, u_alpha = -1, u_color_override = -1, u_ray = -1;
  GLuint framebuffer = 0, color_rb = 0, depth_rb = 0;
  struct Level {
    GLuint ibo = 0;
    GLsizei index_count = 0;
    float error = 0.0f;  // geometric error, in the mesh's units
  };
  struct GpuMesh {
    GLuint vao = 0, vbo = 0;
    std::vector<Level> levels;  // finest first; levels[0] is the mesh itself
    GLenum index_type = GL_UNSIGNED_INT;
    Eigen::AlignedBox3f bounds;  // in the model's frame
    // Vertex positions (columns) of a mesh with levels of detail, for the
    // nearest depth in ChooseLevel; empty for a mesh with one level.
    Eigen::Matrix3Xf positions;
  };
  std::vector<GpuMesh> meshes;
  int fbo_width = 0, fbo_height = 0;  // the framebuffer's storage, a region of the canvas (FitFramebuffer)
};

namespace {
// Up to this many vertices the level of detail is chosen by the nearest
// vertex, beyond it by the nearest corner of the bounding box (ChooseLevel).
constexpr size_t kLodMaxExactVertices = 1u << 20;
// Framebuffer sizes are multiples of this: llvmpipe's tile size, and few reallocations.
constexpr int kFramebufferStep = 64;
int RoundUp(int v) { return (v + kFramebufferStep - 1) / kFramebufferStep * kFramebufferStep; }
}  // namespace

void Renderer::FitFramebuffer(int width, int height) {
  // The framebuffer holds the frame's region, not the canvas, so the frame
  // clears the whole framebuffer, no scissor. On llvmpipe the scissored clear
  // of the bench's 507x775 region cost about 1.4 ms of rasterisation (timed
  // with and without it) and a whole-canvas clear about 0.5 ms less; a clear
  // of a region-sized buffer is cheaper still. It grows to fit and shrinks
  // when a quarter of it would do, so its size changes rarely.
  const int w = RoundUp(width), h = RoundUp(height);
  Gl& g = *gl_;
  if (w <= g.fbo_width && h <= g.fbo_height && 4 * w * h > g.fbo_width * g.fbo_height) return;
  g.fbo_width = w, g.fbo_height = h;
  glBindFramebuffer(GL_FRAMEBUFFER, g.framebuffer);
  glBindRenderbuffer(GL_RENDERBUFFER, g.color_rb);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, g.color_rb);
  glBindRenderbuffer(GL_RENDERBUFFER, g.depth_rb);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, g.depth_rb);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("ar_overlay: offscreen framebuffer incomplete");
}

Renderer::Renderer(const RenderConfig& config) : config_(config), gl_(new Gl) {
  // llvmpipe mallocs and frees megabytes of vertex and bin data per draw. With
  // glibc's dynamic trimming each free hands them back to the kernel and the
  // next frame faults them in again, zero-filled: about a third of the CPU time
  // of a 50k-triangle frame (perf: brk and clear_page). Keeping freed heap costs
  // the process nothing it was not already using at its peak.
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
  if (!(config.near_m > 0 && config.far_m > config.near_m))
    throw std::invalid_argument("ar_overlay: need 0 < near_m < far_m");
  GLuint vs = Compile(GL_VERTEX_SHADER, kVertexShader), fs = Compile(GL_FRAGMENT_SHADER, kFragmentShader);
  gl_->program = glCreateProgram();
  glAttachShader(gl_->program, vs);
  glAttachShader(gl_->program, fs);
  glLinkProgram(gl_->program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(gl_->program, GL_LINK_STATUS, &ok);
  if (!ok) throw std::runtime_error("ar_overlay: shader program link failed");
  gl_->u_model_view = glGetUniformLocation(gl_->program, "u_model_view");
  gl_->u_normal_matrix = glGetUniformLocation(gl_->program, "u_normal_matrix");
  gl_->u_projection = glGetUniformLocation(gl_->program, "u_projection");
  gl_->u_alpha = glGetUniformLocation(gl_->program, "u_alpha");
  gl_->u_color_override = glGetUniformLocation(gl_->program, "u_color_override");
  gl_->u_ray = glGetUniformLocation(gl_->program, "u_ray");
}

Renderer::~Renderer() {
  egl_.MakeCurrent();
  for (auto& m : gl_->meshes) {
    glDeleteVertexArrays(1, &m.vao);
    glDeleteBuffers(1, &m.vbo);
    for (auto& level : m.levels) glDeleteBuffers(1, &level.ibo);
  }
  glDeleteFramebuffers(1, &gl_->framebuffer);
  glDeleteRenderbuffers(1, &gl_->color_rb);
  glDeleteRenderbuffers(1, &gl_->depth_rb);
  glDeleteProgram(gl_->program);
}

int Renderer::AddMesh(const Mesh& mesh) {
  Gl::GpuMesh m;
  glGenVertexArrays(1, &m.vao);
  glBindVertexArray(m.vao);
  glGenBuffers(1, &m.vbo);
  glBindBuffer(GL_ARRAY_BUFFER, m.vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.vertices.size() * sizeof(Vertex)), mesh.vertices.data(),
               GL_STATIC_DRAW);
  // Levels of detail (RenderConfig::lod_max_error_px). meshoptimizer rather
  // than our own simplifier: its quadric collapse keeps the topology and the
  // open borders (the peaks surface's edge) and reports the error it made.
  std::vector<std::pair<std::vector<uint32_t>, float>> levels{{mesh.indices, 0.0f}};
  if (mesh.TriangleCount() >= kLodMinTriangles) {
    const float* positions = mesh.vertices.empty() ? nullptr : mesh.vertices[0].position;
    const float scale = meshopt_simplifyScale(positions, mesh.vertices.size(), sizeof(Vertex));
    while (levels.back().first.size() / 3 >= kLodMinTriangles / 4) {
      const std::vector<uint32_t>& finer = levels.back().first;
      std::vector<uint32_t> coarser(finer.size());
      float relative_error = 0.0f;
      coarser.resize(meshopt_simplify(coarser.data(), finer.data(), finer.size(), positions, mesh.vertices.size(),
                                      sizeof(Vertex), finer.size() / 2, 1.0f, 0, &relative_error));
      if (coarser.empty() || coarser.size() > finer.size() * 3 / 4) break;  // the simplifier is stuck
      // Errors accumulate from level to level; the simplifier's is against its input.
      levels.emplace_back(std::move(coarser), levels.back().second + relative_error * scale);
    }
  }
  const bool short_indices = mesh.vertices.size() <= 65536;  // half the index traffic for llvmpipe's vertex fetch
  m.index_type = short_indices ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT;
  for (auto& [indices, error] : levels) {
    // Triangles reordered for the post-transform vertex cache (llvmpipe's draw
    // module keeps one too): fewer vertex shader runs per triangle drawn.
    meshopt_optimizeVertexCache(indices.data(), indices.data(), indices.size(), mesh.vertices.size());
    Gl::Level level;
    glGenBuffers(1, &level.ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, level.ibo);
    if (short_indices) {
      const std::vector<uint16_t> shorts(indices.begin(), indices.end());
      glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(shorts.size() * sizeof(uint16_t)), shorts.data(),
                   GL_STATIC_DRAW);
    } else {
      glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indices.size() * sizeof(uint32_t)), indices.data(),
                   GL_STATIC_DRAW);
    }
    level.index_count = static_cast<GLsizei>(indices.size());
    level.error = error;
    m.levels.push_back(level);
  }
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, position)));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, normal)));
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, color)));
  glBindVertexArray(0);
  for (const Vertex& v : mesh.vertices) m.bounds.extend(Eigen::Vector3f(v.position[0], v.position[1], v.position[2]));
  if (m.levels.size() > 1 && mesh.vertices.size() <= kLodMaxExactVertices) {
    m.positions.resize(3, static_cast<Eigen::Index>(mesh.vertices.size()));
    for (size_t i = 0; i < mesh.vertices.size(); ++i)
      m.positions.col(static_cast<Eigen::Index>(i)) = Eigen::Vector3f::Map(mesh.vertices[i].position);
  }
  gl_->meshes.push_back(m);
  return static_cast<int>(gl_->meshes.size()) - 1;
}

std::vector<std::pair<size_t, float>> Renderer::LevelsOfDetail(int mesh_id) const {
  std::vector<std::pair<size_t, float>> out;
  if (mesh_id < 0 || mesh_id >= static_cast<int>(gl_->meshes.size())) return out;
  for (const Gl::Level& l : gl_->meshes[static_cast<size_t>(mesh_id)].levels)
    out.emplace_back(static_cast<size_t>(l.index_count) / 3, l.error);
  return out;
}

size_t Renderer::ChooseLevel(int mesh_id, const Eigen::Matrix4f& T_camera_model) const {
  const Gl::GpuMesh& m = gl_->meshes[static_cast<size_t>(mesh_id)];
  if (config_.lod_max_error_px <= 0.0 || m.levels.size() < 2 || m.bounds.isEmpty()) return 0;
  // The error projects largest at the nearest point, and a mesh's nearest
  // point is one of its vertices (a triangle's depth is least at a corner).
  // Their depths are one 1x3 by 3xN product (about 10 us for the peaks'
  // 25,921 vertices); a mesh too large for that uses its bounding box's
  // nearest corner, which is nearer still.
  float nearest = INFINITY;
  if (m.positions.cols() > 0) {
    nearest = (T_camera_model.block<1, 3>(2, 0) * m.positions).minCoeff() + T_camera_model(2, 3);
  } else {
    for (int corner = 0; corner < 8; ++corner)
      nearest = std::min(
          nearest,
          (T_camera_model * m.bounds.corner(static_cast<Eigen::AlignedBox3f::CornerType>(corner)).homogeneous()).z());
  }
  nearest = std::max(nearest, static_cast<float>(config_.near_m));
  const float model_scale = T_camera_model.topLeftCorner<3, 3>().colwise().norm().maxCoeff();
  const float px_per_unit = static_cast<float>(std::max(camera_.fx_px, camera_.fy_px)) * model_scale / nearest;
  size_t level = 0;
  while (level + 1 < m.levels.size() &&
         m.levels[level + 1].error * px_per_unit <= static_cast<float>(config_.lod_max_error_px))
    ++level;
  return level;
}

void Renderer::SetCamera(const CameraModel& k) {
  if (map_ && k == camera_) return;
  const std::string why = Validate(k);
  if (!why.empty()) throw std::invalid_argument("ar_overlay: camera intrinsics: " + why);
  camera_ = k;
  map_.reset(new DistortionMap(k));
  if (gl_->framebuffer == 0) {
    glGenFramebuffers(1, &gl_->framebuffer);
    glGenRenderbuffers(1, &gl_->color_rb);
    glGenRenderbuffers(1, &gl_->depth_rb);
  }
  gl_->fbo_width = gl_->fbo_height = 0;  // sized by the first Render (FitFramebuffer)
  canvas_.create(map_->canvas_height(), map_->canvas_width(), CV_8UC4);
  canvas_.setTo(cv::Scalar::all(0));
  canvas_written_ = cv::Rect();
}

cv::Rect Renderer::CanvasRoi(const std::vector<DrawItem>& items, const Eigen::Matrix4f& T_camera_cones) const {
  const cv::Rect canvas(0, 0, map_->canvas_width(), map_->canvas_height());
  Eigen::AlignedBox2f box;
  for (const DrawItem& item : items) {
    if (item.mesh_id < 0 || item.mesh_id >= static_cast<int>(gl_->meshes.size())) continue;
    const Eigen::AlignedBox3f& b = gl_->meshes[static_cast<size_t>(item.mesh_id)].bounds;
    if (b.isEmpty()) continue;
    const Eigen::Matrix4f T = T_camera_cones * item.T_cones_model;
    Eigen::Vector3f p[8];
    int behind = 0;
    for (int corner = 0; corner < 8; ++corner) {
      p[corner] = (T * b.corner(static_cast<Eigen::AlignedBox3f::CornerType>(corner)).homogeneous()).head<3>();
      behind += p[corner].z() < static_cast<float>(config_.near_m);
    }
    if (behind == 8) continue;      // wholly behind the near plane: invisible
    if (behind > 0) return canvas;  // straddles it: GL clips, keep everything
    for (const Eigen::Vector3f& c : p)
      box.extend(Eigen::Vector2f(static_cast<float>(camera_.fx_px * c.x() / c.z() + map_->canvas_cx()),
                                 static_cast<float>(camera_.fy_px * c.y() / c.z() + map_->canvas_cy())));
  }
  if (box.isEmpty()) return cv::Rect();
  const float big = 4.0f * static_cast<float>(canvas.width + canvas.height);  // keeps the int conversion sane
  const Eigen::Vector2f lo = box.min().cwiseMax(-big), hi = box.max().cwiseMin(big);
  const cv::Rect r(static_cast<int>(std::floor(lo.x())) - 2, static_cast<int>(std::floor(lo.y())) - 2,
                   static_cast<int>(std::ceil(hi.x() - lo.x())) + 5, static_cast<int>(std::ceil(hi.y() - lo.y())) + 5);
  return r & canvas;
}

cv::Rect Renderer::Render(const std::vector<DrawItem>& items, const Eigen::Isometry3d& T_camera_cones,
                          cv::Mat& overlay_rgba) {
  if (!map_) throw std::logic_error("ar_overlay: Renderer::Render before SetCamera");
  const int W = map_->canvas_width();
  const Eigen::Matrix4f T_c_m0 = T_camera_cones.matrix().cast<float>();
  // overlay_ is the renderer's own buffer, so zeroing what the last frame wrote
  // is enough: a full clear of 1024x768 RGBA costs more than a small model's readback.
  if (overlay_.rows != camera_.height_px || overlay_.cols != camera_.width_px) {
    overlay_.create(camera_.height_px, camera_.width_px, CV_8UC4);
    overlay_.setTo(cv::Scalar::all(0));
  } else if (!overlay_written_.empty()) {
    overlay_(overlay_written_).setTo(cv::Scalar::all(0));
  }
  overlay_written_ = cv::Rect();
  overlay_rgba = overlay_;
  const cv::Rect roi = CanvasRoi(items, T_c_m0);
  drawn_triangles_ = 0;
  if (roi.empty()) return cv::Rect();  // nothing in view: nothing to draw
  // The framebuffer's pixel (0, 0) is the canvas's (roi.x, roi.y): the
  // principal point moves by the region's corner.
  FitFramebuffer(roi.width, roi.height);
  const double cx = map_->canvas_cx() - roi.x, cy = map_->canvas_cy() - roi.y;
  const Eigen::Matrix4f P = ProjectionFromIntrinsics(camera_.fx_px, camera_.fy_px, cx, cy, gl_->fbo_width,
                                                     gl_->fbo_height, config_.near_m, config_.far_m);
  glBindFramebuffer(GL_FRAMEBUFFER, gl_->framebuffer);
  glViewport(0, 0, gl_->fbo_width, gl_->fbo_height);
  glClearColor(0, 0, 0, 0);
  glClearDepthf(1.0f);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);  // imported meshes' winding is not to be trusted
  glDisable(GL_BLEND);      // alpha goes to the composite, against the camera image
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glUseProgram(gl_->program);
  glUniformMatrix4fv(gl_->u_projection, 1, GL_FALSE, P.data());  // Eigen is column-major, as GL
  // gl_FragCoord is the pixel centre, u + 0.5, with row 0 at the image top (ProjectionFromIntrinsics).
  glUniform4f(gl_->u_ray, static_cast<float>(1.0 / camera_.fx_px), static_cast<float>(-(cx + 0.5) / camera_.fx_px),
              static_cast<float>(1.0 / camera_.fy_px), static_cast<float>(-(cy + 0.5) / camera_.fy_px));
  for (const DrawItem& item : items) {
    if (item.mesh_id < 0 || item.mesh_id >= static_cast<int>(gl_->meshes.size())) continue;
    const Eigen::Matrix4f model_view = T_c_m0 * item.T_cones_model;
    const Eigen::Matrix3f normal_matrix = model_view.topLeftCorner<3, 3>().inverse().transpose();
    glUniformMatrix4fv(gl_->u_model_view, 1, GL_FALSE, model_view.data());
    glUniformMatrix3fv(gl_->u_normal_matrix, 1, GL_FALSE, normal_matrix.data());
    glUniform1f(gl_->u_alpha, item.alpha);
    glUniform4fv(gl_->u_color_override, 1, item.color_override.data());
    const Gl::GpuMesh& m = gl_->meshes[static_cast<size_t>(item.mesh_id)];
    const Gl::Level& level = m.levels[ChooseLevel(item.mesh_id, model_view)];
    glBindVertexArray(m.vao);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, level.ibo);
    glDrawElements(GL_TRIANGLES, level.index_count, m.index_type, nullptr);
    drawn_triangles_ += static_cast<size_t>(level.index_count) / 3;
  }
  glBindVertexArray(0);
  // Read back the region into its place in canvas_ (row 0 = image top, camera_projection.h).
  // The remap reads canvas pixels outside `roi` too: they must be zero, and only
  // the last frame's region can be anything else.
  if (!canvas_written_.empty()) canvas_(canvas_written_).setTo(cv::Scalar::all(0));
  canvas_written_ = roi;
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glPixelStorei(GL_PACK_ROW_LENGTH, W);
  glReadPixels(0, 0, roi.width, roi.height, GL_RGBA, GL_UNSIGNED_BYTE, canvas_.ptr(roi.y, roi.x));
  glPixelStorei(GL_PACK_ROW_LENGTH, 0);
  const cv::Rect raw_roi = map_->RawRoi(roi);
  if (!raw_roi.empty()) map_->ApplyRoi(canvas_, raw_roi, overlay_);
  overlay_written_ = raw_roi;
  return raw_roi;
}

}  // namespace ar_overlay
