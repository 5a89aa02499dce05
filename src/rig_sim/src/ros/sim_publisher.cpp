#include "rig_sim/ros/sim_publisher.h"

#include "rig_model/ros/param_table_ros.h"
#include "rig_sim/crista_link.h"

#include <nodelet/NodeletList.h>
#include <rosgraph_msgs/Clock.h>

#include <algorithm>
#include <sstream>

namespace rig_sim {

const rig_model::ParamTable<SimPublisherConfig>& SimPublisherParams() {
  using C = SimPublisherConfig;
  static const rig_model::ParamTable<C> table =
      rig_model::ParamTable<C>()
          .Add("scenario", [](C& c) -> std::string& { return c.scenario; })
          .Add("look", [](C& c) -> std::string& { return c.look; })
          .Add("seed", [](C& c) -> int& { return c.seed; })
          .Add("image_scale", [](C& c) -> double& { return c.image_scale; })
          .Add("duration_s", [](C& c) -> double& { return c.duration_s; })
          .Add("realtime_factor", [](C& c) -> double& { return c.realtime_factor; })
          .Add("camera_delay_ms", [](C& c) -> double& { return c.camera_delay_ms; })
          .Add("start_time_s", [](C& c) -> double& { return c.start_time_s; })
          .Add("loop", [](C& c) -> bool& { return c.loop; })
          .Add("publish_clock", [](C& c) -> bool& { return c.publish_clock; })
          .Add("serial_pty", [](C& c) -> bool& { return c.serial_pty; })
          .Add("serial_link", [](C& c) -> std::string& { return c.serial_link; })
          .Add("layouts_dir", [](C& c) -> std::string& { return c.layouts_dir; })
          .Add("wait_for_manager", [](C& c) -> std::string& { return c.wait_for_manager; })
          .Add("wait_for_nodelets", [](C& c) -> std::string& { return c.wait_for_nodelets; });
  return table;
}

bool LoadSimPublisherConfig(const ros::NodeHandle& pnh, SimPublisherConfig* c, std::string* error) {
  SimPublisherConfig out;
  out.layouts_dir = RIG_SIM_LAYOUTS_DIR;
  try {
    rig_model::LoadParams(pnh, SimPublisherParams(), &out);
  } catch (const std::invalid_argument& e) {
    if (error) *error = e.what();
    return false;
  }
  std::string err;
  if (out.seed < 0)
    err = "~seed must be >= 0";
  else if (!(out.image_scale > 0.0 && out.image_scale <= 4.0))
    err = "~image_scale must be in (0, 4]";
  else if (out.duration_s < 0.0)
    err = "~duration_s must be >= 0";
  else if (!(out.realtime_factor > 0.0 && out.realtime_factor <= 100.0))
    err = "~realtime_factor must be in (0, 100]";
  else if (!(out.camera_delay_ms >= 0.0 && out.camera_delay_ms <= 1000.0))
    err = "~camera_delay_ms must be in [0, 1000]";
  else if (!(out.start_time_s > 0.0))
    err = "~start_time_s must be positive";
  else if (out.wait_for_manager.empty() && !out.wait_for_nodelets.empty())
    err = "~wait_for_nodelets needs ~wait_for_manager (the manager they load into)";
  else if (!out.look.empty()) {
    Scenario probe;
    if (!ApplyLook(out.look, &probe, &err)) err = "~look: " + err;
  }
  if (!err.empty()) {
    if (error) *error = err;
    return false;
  }
  *c = out;
  return true;
}

SimPublisher::SimPublisher(ros::NodeHandle nh, ros::NodeHandle pnh, const SimPublisherConfig& config)
    : config_(config),
      nh_(nh),
      it_(nh),
      diagnostics_(nh, pnh, ros::this_node::getName(), "rig_sim/" + config.scenario) {
  std::string err;
  if (!MakeScenario(config.scenario, static_cast<uint64_t>(config.seed), config.layouts_dir, &scenario_, &err))
    throw std::invalid_argument(err);
  if (!config.look.empty() && !ApplyLook(config.look, &scenario_, &err)) throw std::invalid_argument("~look: " + err);
  ShortenScenario(config.duration_s, config.image_scale, &scenario_);
  camera_pub_ = it_.advertiseCamera(topics_.image, 2);
  imu_pub_ = nh_.advertise<sensor_msgs::Imu>(topics_.imu, 50);
  truth_pub_ = nh_.advertise<geometry_msgs::PoseStamped>(topics_.truth, 50);
  bias_pub_ = nh_.advertise<sensor_msgs::Imu>(topics_.imu_bias, 50);
  tf_pub_ = nh_.advertise<tf2_msgs::TFMessage>("/tf", 50);
  tf_static_pub_ = nh_.advertise<tf2_msgs::TFMessage>("/tf_static", 1, true);
  markers_pub_ = nh_.advertise<visualization_msgs::MarkerArray>(topics_.markers, 1, true);
  if (config.publish_clock) clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
  if (config.serial_pty) {
    try {
      pty_ = std::make_unique<imu_driver::PseudoTerminal>(config.serial_link);
      pty_->Plug();
      ROS_INFO("rig_sim: Crista byte stream on %s (link %s)", pty_->slave_name().c_str(), config.serial_link.c_str());
    } catch (const std::exception& e) {
      ROS_WARN("rig_sim: no Crista pseudo-terminal: %s", e.what());
      pty_.reset();
    }
  }
  diagnostics_.Add("simulated rig", [this](diagnostic_updater::DiagnosticStatusWrapper& s) { Diagnose(s); });
  pass_start_s_ = config.start_time_s;
  const ros::Time t0 = StampAt(pass_start_s_, 0.0);
  tf_static_pub_.publish(MakeStaticTruth(scenario_.imu, t0, frames_names_));
  markers_pub_.publish(MakeConeMarkers(scenario_.scene, t0, frames_names_.cones));
}

SimPublisher::~SimPublisher() {
  frames_.reset();  // joins the render thread before the stream goes
  stream_.reset();
}

// Waits on the manager's own list: nodelet::Loader holds its lock through a nodelet's onInit(), so a
// listed nodelet has made its subscriptions. A fixed start delay, the alternative, fails on a loaded
// machine (the soak lost the driver's first IMU messages that way).
void SimPublisher::WaitForNodelets() {
  if (config_.wait_for_manager.empty()) return;
  std::vector<std::string> wanted;
  std::istringstream words(config_.wait_for_nodelets);
  for (std::string w; words >> w;) wanted.push_back(w.front() == '/' ? w : "/" + w);
  const std::string service = ros::names::resolve(config_.wait_for_manager) + "/list";
  ros::WallTime next_log = ros::WallTime::now();
  while (ros::ok()) {
    nodelet::NodeletList list;
    std::vector<std::string> missing = wanted;
    const bool answered = ros::service::call(service, list);
    if (answered) {
      for (const std::string& name : list.response.nodelets)
        missing.erase(std::remove(missing.begin(), missing.end(), name), missing.end());
      if (missing.empty()) return;
    }
    if (ros::WallTime::now() >= next_log) {
      std::string names;
      for (const std::string& m : missing) names += " " + m;
      if (answered)
        ROS_INFO("rig_sim: waiting for nodelets in %s (~wait_for_nodelets):%s", service.c_str(), names.c_str());
      else
        ROS_INFO("rig_sim: waiting for the nodelet manager's %s (~wait_for_manager)", service.c_str());
      next_log += ros::WallDuration(5.0);
    }
    ros::spinOnce();  // the wall-timer diagnostics keep reporting
    ros::WallDuration(0.05).sleep();
  }
}

void SimPublisher::StartPass() {
  frames_.reset();
  StreamConfig sc;
  sc.camera_delay_s = config_.camera_delay_ms / 1000.0;
  stream_.reset(new SimStream(scenario_, sc));
  frames_.reset(new FramePipeline(*stream_, pass_start_s_, frames_names_.camera, FrameCount(scenario_)));
}

void SimPublisher::Diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  stat.summary(late_events_ > 0 ? diagnostic_msgs::DiagnosticStatus::WARN : diagnostic_msgs::DiagnosticStatus::OK,
               late_events_ > 0 ? "publishing behind schedule at times (lower image_scale or realtime_factor)"
                                : "publishing on schedule");
  stat.add("images published", images_);
  stat.add("imu samples published", imu_);
  stat.add("events more than 20 ms late", late_events_);
  stat.add("serial packets dropped (no reader)", pty_dropped_);
}

void SimPublisher::Publish(const SimEvent& ev) {
  const ros::Time stamp = StampAt(pass_start_s_, ev.stamp_s);
  switch (ev.kind) {
    case EventKind::kImu: {
      const ros::Time imu_stamp = ImuMessageStamp(stamp, scenario_.imu);
      imu_pub_.publish(MakeImu(ev.imu, scenario_.imu, imu_stamp, frames_names_.imu));
      bias_pub_.publish(MakeImuBias(ev.imu, imu_stamp, frames_names_.imu));
      if (pty_) {
        // The sequence number counts on across loop passes (ev.index restarts), as the Crista's would.
        const std::vector<uint8_t> packet = EncodeCristaPacket(ev.imu, static_cast<uint8_t>(imu_ & 0xFF));
        if (!pty_->WriteIfRoom(packet.data(), packet.size())) ++pty_dropped_;
      }
      ++imu_;
      break;
    }
    case EventKind::kTruth: {
      truth_pub_.publish(MakeTruthPose(ev.pose, stamp, frames_names_.cones));
      if (ev.index % 3 == 0) {
        tf2_msgs::TFMessage tf;
        tf.transforms.push_back(MakeTruthTransform(ev.pose, stamp, frames_names_));
        tf_pub_.publish(tf);
      }
      break;
    }
    case EventKind::kImage: {
      const sensor_msgs::ImagePtr img = frames_->Pop();
      sensor_msgs::CameraInfoPtr info(
          new sensor_msgs::CameraInfo(MakeCameraInfo(scenario_.camera, stamp, frames_names_.camera)));
      camera_pub_.publish(img, info);  // never touched again: zero copy to nodelets in the same manager
      ++images_;
      break;
    }
  }
}

void SimPublisher::Run() {
  WaitForNodelets();
  StartPass();
  const ros::WallTime wall0 = ros::WallTime::now();
  double pass_offset_s = 0.0;  // scenario time already played in earlier passes
  SimEvent ev;
  while (ros::ok()) {
    if (!stream_->Next(&ev)) {
      if (!config_.loop) break;
      pass_offset_s += scenario_.trajectory.duration_s;
      pass_start_s_ = config_.start_time_s + pass_offset_s;  // time keeps going forward
      StartPass();
      continue;
    }
    const double due_s = (pass_offset_s + ev.deliver_s) / config_.realtime_factor;
    const double wait_s = due_s - (ros::WallTime::now() - wall0).toSec();
    if (wait_s > 0.0)
      ros::WallDuration(wait_s).sleep();
    else if (wait_s < -0.02)
      ++late_events_;
    if (clock_pub_) {
      rosgraph_msgs::Clock clock;
      clock.clock = StampAt(pass_start_s_, ev.deliver_s);
      clock_pub_.publish(clock);
    }
    Publish(ev);
    ros::spinOnce();
  }
}

}  // namespace rig_sim
