#include "ar_overlay/core/overlay.h"

#include <stdexcept>

#include "ar_overlay/core/composite.h"
#include "ar_overlay/core/model_loader.h"

namespace ar_overlay {

Overlay::Overlay(const RenderConfig& config) : renderer_(config) {}

std::vector<std::string> Overlay::LoadScene(const std::string& yaml_path) {
  const std::vector<ModelSpec> specs = LoadSceneYaml(yaml_path);  // throws: the YAML is unusable
  std::vector<std::string> errors;
  specs_.clear();
  mesh_ids_.clear();
  // A model that fails keeps its place (mesh id -1) so its children still
  // find their parent: a missing link leaves a gap, not a collapsed arm.
  for (const ModelSpec& s : specs) {
    specs_.push_back(s);
    try {
      mesh_ids_.push_back(renderer_.AddMesh(LoadModel(s.file)));
    } catch (const std::exception& e) {
      mesh_ids_.push_back(-1);
      errors.push_back(s.name + ": " + e.what());
    }
  }
  return errors;
}

void Overlay::AddModel(const ModelSpec& spec, const Mesh& mesh) {
  specs_.push_back(spec);
  mesh_ids_.push_back(renderer_.AddMesh(mesh));
}

void Overlay::SetJointPositions(const std::map<std::string, double>& joint_rad) {
  for (const auto& [name, q] : joint_rad) joint_rad_[name] = q;
}

void Overlay::Process(const cv::Mat& image, const std::string& encoding, const CameraModel& k,
                      const Eigen::Isometry3d& T_camera_cones, cv::Mat& out, std::string& out_encoding) {
  ToColor(image, encoding, out, out_encoding);
  if (out.cols != k.width_px || out.rows != k.height_px)
    throw std::invalid_argument("ar_overlay: image is " + std::to_string(out.cols) + "x" + std::to_string(out.rows) +
                                " but camera_info says " + std::to_string(k.width_px) + "x" +
                                std::to_string(k.height_px));
  if (!T_camera_cones.matrix().allFinite()) throw std::invalid_argument("ar_overlay: camera pose is not finite");
  renderer_.SetCamera(k);
  const std::vector<Eigen::Isometry3d> poses = ModelPoses(specs_, joint_rad_);
  std::vector<DrawItem> items;
  for (size_t i = 0; i < specs_.size(); ++i) {
    if (mesh_ids_[i] < 0) continue;
    DrawItem d;
    d.mesh_id = mesh_ids_[i];
    d.T_cones_model = poses[i].matrix().cast<float>();
    d.T_cones_model.topLeftCorner<3, 3>() *= static_cast<float>(specs_[i].scale);
    d.alpha = static_cast<float>(specs_[i].alpha);
    if (specs_[i].has_color) d.color_override << specs_[i].color, 1.0f;
    items.push_back(d);
  }
  const cv::Rect roi = renderer_.Render(items, T_camera_cones, overlay_rgba_);
  if (roi.empty()) return;
  cv::Mat out_roi = out(roi);
  CompositeInPlace(overlay_rgba_(roi), out_encoding, out_roi);
}

}  // namespace ar_overlay
