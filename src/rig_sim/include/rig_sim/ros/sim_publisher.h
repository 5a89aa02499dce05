// Live publishing of a scenario: paced by the wall clock (times a real-time
// factor), driving /clock, optionally also writing the Crista byte stream to
// a pseudo-terminal so imu_driver can be tested over a real tty.
#pragma once

#include <memory>
#include <string>

#include <image_transport/image_transport.h>
#include <ros/ros.h>

#include "imu_driver/core/pseudo_terminal.h"
#include "rig_model/param_table.h"
#include "rig_model/ros/diagnostics.h"
#include "rig_sim/ros/frame_pipeline.h"
#include "rig_sim/ros/messages.h"

namespace rig_sim {

struct SimPublisherConfig {
  std::string scenario = "handheld";
  std::string look;  // ListLooks(); empty: the scenario's own
  int seed = 1;
  double image_scale = 1.0;
  double duration_s = 0.0;  // 0: the scenario's own
  double realtime_factor = 1.0;
  double camera_delay_ms = 0.0;
  double start_time_s = 1700000000.0;
  bool loop = false;  // restart at the end, time continuing forward
  bool publish_clock = true;
  bool serial_pty = false;
  std::string serial_link = "/tmp/rig_sim_crista";  // symlink to the pty slave
  std::string layouts_dir;                          // default: rig_model's config/layouts
  // Publish nothing (not even /clock) until this manager answers and lists these nodelets
  // (space-separated), so that a graph started beside the simulator sees every message.
  std::string wait_for_manager;
  std::string wait_for_nodelets;
};

// SimPublisherConfig's parameters under ~, by the field names.
const rig_model::ParamTable<SimPublisherConfig>& SimPublisherParams();

// Reads ~parameters through SimPublisherParams() (rig_model::LoadParams: type-checked, unknown
// names refused); returns false with a message naming the bad parameter.
bool LoadSimPublisherConfig(const ros::NodeHandle& pnh, SimPublisherConfig* config, std::string* error);

class SimPublisher {
 public:
  SimPublisher(ros::NodeHandle nh, ros::NodeHandle pnh, const SimPublisherConfig& config);
  ~SimPublisher();
  // Publishes until the scenario ends (or forever with loop) or ROS shuts down.
  void Run();

 private:
  void WaitForNodelets();
  void StartPass();
  void Publish(const SimEvent& ev);
  void Diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);

  SimPublisherConfig config_;
  Scenario scenario_;
  ros::NodeHandle nh_;
  image_transport::ImageTransport it_;
  image_transport::CameraPublisher camera_pub_;
  ros::Publisher imu_pub_, truth_pub_, bias_pub_, clock_pub_, tf_pub_, tf_static_pub_, markers_pub_;
  rig_model::WallDiagnostics diagnostics_;  // on a wall timer, served by Run()'s spinOnce()
  std::unique_ptr<SimStream> stream_;
  std::unique_ptr<FramePipeline> frames_;
  std::unique_ptr<imu_driver::PseudoTerminal> pty_;
  uint64_t pty_dropped_ = 0;  // packets not written: nobody reading and the pty buffer full
  TopicNames topics_;
  FrameNames frames_names_;
  double pass_start_s_ = 0.0;  // sim time of this pass's t = 0
  uint64_t images_ = 0, imu_ = 0, late_events_ = 0;
};

}  // namespace rig_sim
