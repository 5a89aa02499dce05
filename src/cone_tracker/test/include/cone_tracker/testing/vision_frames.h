// rig_sim frames with ground truth for the segmentation tests and the vision benchmark: a camera
// looking at a scene, the rendered rgb8 frame, and where each cone's peak and front base point
// (the surface point facing the camera, 3.1.4) project. Test code only: the tracker itself never
// depends on the simulator (rig_sim is a test_depend).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cone_tracker/pose/pnp.h"
#include "cone_tracker/vision/segmenter.h"
#include "rig_sim/scene.h"
#include "rig_sim/trajectory.h"

namespace cone_tracker {

struct TruthCone {
  Eigen::Vector2d peak_px, base_px;  // distorted pixels
};

struct SimFrame {
  CameraModel camera;  // rig_model's; what a camera_info of the frame would carry
  rig_sim::TruePose pose;
  std::vector<uint8_t> rgb;
  std::vector<TruthCone> truth;  // one per scene cone, in scene order
};

// camera_optical at eye_m looking at target_m, z up in `cones`.
rig_sim::TruePose LookAt(const Eigen::Vector3d& eye_m, const Eigen::Vector3d& target_m);
// The frame as the segmenter takes it.
ImageView FrameView(const SimFrame& f, const std::string& encoding = "rgb8");
SimFrame RenderSim(const rig_sim::Scene& scene, const rig_sim::TruePose& pose,
                   const CameraModel& camera = rig_model::ThesisCamera(), double noise_sigma_dn = 2.0);

}  // namespace cone_tracker
