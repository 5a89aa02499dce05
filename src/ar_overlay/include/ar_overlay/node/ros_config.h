// The overlay nodelet's settings: one struct, units in the names, filled through one parameter
// table (Params(), the parameters' names) and validated by LoadConfig.
#pragma once

#include <ros/node_handle.h>
#include <sensor_msgs/CameraInfo.h>

#include <string>

#include "ar_overlay/core/camera_projection.h"
#include "rig_model/param_table.h"

namespace ar_overlay {

// pose_mode's values, in the order of the names the parameter takes (image_stamp, predicted).
enum PoseMode : int {
  kImageStamp,  // the pose at the image's stamp (tf2, waiting up to tf_timeout_s)
  kPredicted,   // thesis 6.5: at render_rate_hz, the latest estimate predicted to display time
};

struct OverlayConfig {
  std::string scene_yaml;                 // models to draw (scene.h); "" draws nothing
  std::string fixed_frame = "cones";      // where the models live
  std::string camera_frame;               // "" takes the image's frame_id
  int pose_mode = PoseMode::kImageStamp;  // a PoseMode
  double tf_timeout_s = 0.05;             // image-stamp mode: wait this long for the pose
  double render_rate_hz = 40.0;           // predicted mode
  double display_latency_s = 0.0;         // predicted mode: frame-out to on-screen delay to predict across
  double max_prediction_s = 0.1;          // predicted mode: never extrapolate further than this
  double velocity_window_s = 0.025;       // predicted mode: the older pose for the velocity is this far back
  double near_m = 0.05;
  double far_m = 200.0;
  double lod_max_error_px = 0.5;  // RenderConfig's: level-of-detail error bound; 0 always draws the full meshes
  bool show_window = false;       // fullscreen OpenCV window for the rig's LCD
  std::string window_name = "ar_overlay";
};

// OverlayConfig's parameters: each field's name under ~, its type and (pose_mode) its names.
const rig_model::ParamTable<OverlayConfig>& Params();

// Reads ~parameters into `c` (rig_model::LoadParams: type-checked, unknown names refused);
// returns "" or a message naming the first bad one.
std::string LoadConfig(const ros::NodeHandle& private_nh, OverlayConfig& c);

// The camera of a camera_info (rig_model::FromCameraInfo); throws std::invalid_argument with its
// reason (a distortion model other than plumb_bob / rational_polynomial, NaN, zero focal length...).
CameraModel FromCameraInfo(const sensor_msgs::CameraInfo& info);

}  // namespace ar_overlay
