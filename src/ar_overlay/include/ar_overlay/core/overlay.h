// The whole overlay step without ROS: loads a scene, keeps the joint angles,
// and turns (camera image, intrinsics, T_camera_cones) into the composited
// image. Models that fail to load are reported and left out; the rest draw.
// Not thread-safe (one thread: it owns the GL context through Renderer).
#pragma once

#include <Eigen/Geometry>
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ar_overlay/core/renderer.h"
#include "ar_overlay/core/scene.h"

namespace ar_overlay {

class Overlay {
 public:
  explicit Overlay(const RenderConfig& config = RenderConfig());

  // Replaces the scene with the YAML's models. Returns one message per model
  // that failed to load ("<name>: <file>: <assimp's reason>"); throws
  // std::runtime_error only when the YAML itself is unusable.
  std::vector<std::string> LoadScene(const std::string& yaml_path);
  // Adds one model already in memory (tests, the benchmark).
  void AddModel(const ModelSpec& spec, const Mesh& mesh);
  // Joint angles by name (radians); unknown names are ignored.
  void SetJointPositions(const std::map<std::string, double>& joint_rad);

  // Draws the models over `image` (in `encoding`) into `out`, the composited
  // colour image; `out_encoding` is rgb8 or bgr8 (see composite.h: `out`'s
  // buffer is reused when it has the right size and type).
  void Process(const cv::Mat& image, const std::string& encoding, const CameraModel& k,
               const Eigen::Isometry3d& T_camera_cones, cv::Mat& out, std::string& out_encoding);

  size_t model_count() const { return specs_.size(); }
  const std::string& gl_renderer() const { return renderer_.gl_renderer(); }
  const Renderer& renderer() const { return renderer_; }

 private:
  Renderer renderer_;
  std::vector<ModelSpec> specs_;
  std::vector<int> mesh_ids_;
  std::map<std::string, double> joint_rad_;
  cv::Mat overlay_rgba_;
};

}  // namespace ar_overlay
