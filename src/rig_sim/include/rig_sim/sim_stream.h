// The simulated rig's output as one time-ordered stream of events: IMU
// samples, ground truth and camera frames, in the order the rig delivers
// them (a camera frame arrives `camera_delay_s` after its exposure stamp).
// Shared by the bag writer and the live publisher. ROS-free.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "rig_sim/imu_model.h"
#include "rig_sim/renderer.h"
#include "rig_sim/scenario.h"

namespace rig_sim {

struct StreamConfig {
  double truth_rate_hz = 300.0;  // a multiple of the camera and IMU rates: truth at every stamp
  double camera_delay_s = 0.0;   // processing delay before the camera frame is delivered
};

enum class EventKind { kImu, kTruth, kImage };

struct SimEvent {
  EventKind kind = EventKind::kImu;
  double stamp_s = 0.0;    // measurement time (exposure for images), scenario time
  double deliver_s = 0.0;  // when the rig hands it over
  uint64_t index = 0;      // per kind, from 0
  ImuSample imu;
  TruePose pose;  // truth: camera in cones at stamp_s
  Eigen::Vector3d omega_camera_rad_s = Eigen::Vector3d::Zero();
};

class SimStream {
 public:
  SimStream(const Scenario& scenario, const StreamConfig& config);
  // The next event in delivery order; false after the scenario's end.
  bool Next(SimEvent* event);
  // Renders camera frame `index` into rgb (width*height*3 bytes) and optionally labels. With the
  // appearance's exposure_time_s > 0 and blur_samples > 1, the frame is the mean over poses of the
  // trajectory spread evenly over the exposure, centred on the stamp (motion blur): an odd number,
  // one per ~2 px of image motion, at most blur_samples; one when the image moves < 0.25 px.
  void RenderFrame(const SimEvent& image_event, uint8_t* rgb, int16_t* labels = nullptr) const;
  // The image event of a frame stamped t_s (scenario time) with its true pose, outside the stream's
  // order: for RenderFrame on stills and in benchmarks. `index` picks the frame's noise.
  SimEvent ImageEventAt(double t_s, uint64_t index = 0) const;
  const Scenario& scenario() const { return scenario_; }
  const Trajectory& trajectory() const { return trajectory_; }
  const Renderer& renderer() const { return renderer_; }

 private:
  Scenario scenario_;
  StreamConfig config_;
  Trajectory trajectory_;
  ImuSimulator imu_;
  Renderer renderer_;
  uint64_t next_imu_ = 0, next_truth_ = 0, next_image_ = 0;
  ImuSample pending_imu_;
};

}  // namespace rig_sim
