// The pose_ekf nodelet: subscriptions, tf, publishers, diagnostics and
// dynamic_reconfigure around PoseEkfAdapter. All callbacks run on the
// nodelet's single-threaded queue, so no locking.
#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <pluginlib/class_list_macros.hpp>

#include <memory>

#include "pose_ekf/PoseEkfConfig.h"
#include "pose_ekf/node/pose_ekf_adapter.h"
#include "rig_model/ros/diagnostics.h"
#include "rig_model/ros/imu_mount.h"
#include "rig_model/ros/param_table_ros.h"

namespace pose_ekf {
namespace {

const char* CameraUpdateName(CameraUpdate u) { return u == CameraUpdate::kCones ? "cones" : "pose"; }

}  // namespace

class PoseEkfNodelet : public nodelet::Nodelet {
 private:
  void onInit() override;
  bool LoadOrRefuse(NodeConfig* config);
  void AddDiagnostics(const NodeConfig& config);
  void AdvertiseAndSubscribe(const NodeConfig& config);
  void StartReconfigure(const NodeConfig& config);
  void OnCamera(const geometry_msgs::PoseWithCovarianceStampedConstPtr& msg);
  void OnImu(const sensor_msgs::ImuConstPtr& msg);
  void OnObservations(const cone_tracker::ConeObservationsConstPtr& msg);
  void OnOutputTimer(const ros::TimerEvent& event);
  void OnReconfigure(PoseEkfConfig& cfg, uint32_t level);
  bool ImuRotation(const std::string& imu_frame, Eigen::Quaterniond* q_camera_imu, Eigen::Vector3d* p_imu_in_camera_m);
  void CheckTimeJump();
  void Report(AddResult r, const std::string& why, const char* what);
  void Publish();
  void Diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);

  std::unique_ptr<PoseEkfAdapter> adapter_;
  ros::Subscriber camera_sub_, imu_sub_, observations_sub_;
  ros::Publisher pose_pub_, odom_pub_;
  ros::Timer output_timer_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> tf_broadcaster_;
  rig_model::ImuMountCache imu_mounts_;  // the static camera-IMU rotation and lever arm per IMU frame
  std::unique_ptr<rig_model::WallDiagnostics> diagnostics_;  // first: a refused config is published too
  std::unique_ptr<rig_model::StampRateTask> imu_freq_, camera_freq_, observations_freq_;
  boost::recursive_mutex reconfigure_mutex_;  // lets updateConfig() seed the server safely
  std::unique_ptr<dynamic_reconfigure::Server<PoseEkfConfig>> reconfigure_;
  ros::Time last_now_;
  double last_published_stamp_s_ = -1.0;
  uint64_t imu_without_tf_ = 0, imu_without_tf_reported_ = 0;
  uint64_t time_jumps_back_ = 0;  // ROS time or a message stamp: each one reset the filter
  std::string imu_tf_error_;      // why the last IMU sample had no camera-IMU rotation
};

void PoseEkfNodelet::onInit() {
  diagnostics_ =
      std::make_unique<rig_model::WallDiagnostics>(getNodeHandle(), getPrivateNodeHandle(), getName(), "pose_ekf");
  NodeConfig config;
  if (!LoadOrRefuse(&config)) return;
  adapter_ = std::make_unique<PoseEkfAdapter>(config);
  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, getNodeHandle());
  tf_broadcaster_ = std::make_unique<tf2_ros::TransformBroadcaster>();
  AddDiagnostics(config);
  AdvertiseAndSubscribe(config);
  StartReconfigure(config);
  last_now_ = ros::Time::now();
  NODELET_INFO("pose_ekf: fusing cone_tracker/pose and imu/data_raw into tf %s -> %s", config.cones_frame.c_str(),
               config.camera_frame.c_str());
  if (config.ekf.camera_update == CameraUpdate::kCones) {
    if (config.layout_cones.empty()) {
      NODELET_WARN("pose_ekf: camera_update is cones but ~layout_file is not set: %s is not used, camera poses are",
                   kObservationsTopic);
    } else {
      NODELET_INFO("pose_ekf: per-cone updates from %s (%zu cones in %s)", kObservationsTopic,
                   config.layout_cones.size(), config.layout_file.c_str());
    }
  }
}

// A refused config stays on /diagnostics as ERROR naming the parameter; the nodelet does nothing else.
bool PoseEkfNodelet::LoadOrRefuse(NodeConfig* config) {
  try {
    *config = LoadConfig(getPrivateNodeHandle());
    return true;
  } catch (const std::exception& e) {
    NODELET_FATAL(
        "%s", diagnostics_->RefuseConfig("filter", "pose_ekf", std::string("invalid parameter: ") + e.what()).c_str());
    return false;
  }
}

void PoseEkfNodelet::AddDiagnostics(const NodeConfig& config) {
  rig_model::RateCheckConfig imu_rate = rig_model::RateCheckConfig::Around(config.imu_expected_rate_hz, 0.2);
  imu_freq_ = std::make_unique<rig_model::StampRateTask>("imu input", imu_rate);
  rig_model::RateCheckConfig camera_rate = rig_model::RateCheckConfig::Around(config.camera_expected_rate_hz, 0.5);
  camera_rate.stale_level = diagnostic_msgs::DiagnosticStatus::WARN;  // no cones in view: the IMU carries on
  camera_freq_ = std::make_unique<rig_model::StampRateTask>("camera input", camera_rate);
  diagnostics_->Add(*imu_freq_);
  diagnostics_->Add(*camera_freq_);
  observations_freq_ = std::make_unique<rig_model::StampRateTask>("cone observations input", camera_rate);
  diagnostics_->Add(*observations_freq_);
  diagnostics_->Add("filter", [this](diagnostic_updater::DiagnosticStatusWrapper& s) { Diagnose(s); });
}

void PoseEkfNodelet::AdvertiseAndSubscribe(const NodeConfig& config) {
  ros::NodeHandle& nh = getNodeHandle();
  pose_pub_ = nh.advertise<geometry_msgs::PoseWithCovarianceStamped>("pose_ekf/pose", 10);
  odom_pub_ = nh.advertise<nav_msgs::Odometry>("pose_ekf/odometry", 10);
  camera_sub_ = nh.subscribe("cone_tracker/pose", 10, &PoseEkfNodelet::OnCamera, this);
  imu_sub_ = nh.subscribe("imu/data_raw", 200, &PoseEkfNodelet::OnImu, this);
  observations_sub_ = nh.subscribe(kObservationsTopic, 10, &PoseEkfNodelet::OnObservations, this);
  if (config.output_rate_hz > 0.0) {
    output_timer_ = nh.createTimer(ros::Duration(1.0 / config.output_rate_hz), &PoseEkfNodelet::OnOutputTimer, this);
  }
}

// The server starts from the loaded parameters, not the .cfg defaults.
void PoseEkfNodelet::StartReconfigure(const NodeConfig& config) {
  reconfigure_ =
      std::make_unique<dynamic_reconfigure::Server<PoseEkfConfig>>(reconfigure_mutex_, getPrivateNodeHandle());
  reconfigure_->updateConfig(rig_model::ToReconfigure<NodeConfig, PoseEkfConfig>(Params(), config));
  reconfigure_->setCallback([this](PoseEkfConfig& cfg, uint32_t level) { OnReconfigure(cfg, level); });
}

void PoseEkfNodelet::OnReconfigure(PoseEkfConfig& cfg, uint32_t /*level*/) {
  NodeConfig c = adapter_->config();
  try {
    rig_model::FromReconfigure(Params(), cfg, &c);
    ValidateConfig(&c);  // use_accel switches ekf.accel_mode between off and ~accel_mode
    adapter_->Reconfigure(c.ekf);
  } catch (const std::exception& ex) {
    NODELET_WARN("pose_ekf: reconfigure refused, settings unchanged: %s", ex.what());
    cfg = rig_model::ToReconfigure<NodeConfig, PoseEkfConfig>(Params(), adapter_->config());  // what is in use
  }
}

// ROS time going backwards (bag loop with /use_sim_time, simulator reset): clear with one warning.
void PoseEkfNodelet::CheckTimeJump() {
  const ros::Time now = ros::Time::now();
  if (now < last_now_) {
    NODELET_WARN("pose_ekf: ROS time jumped back by %.3f s; resetting the filter", (last_now_ - now).toSec());
    ++time_jumps_back_;
    adapter_->Reset();
    adapter_->buffer().TakeResetWarning();
    imu_mounts_.Clear();
    tf_buffer_->clear();
    last_published_stamp_s_ = -1.0;
  }
  last_now_ = now;
}

void PoseEkfNodelet::Report(AddResult r, const std::string& why, const char* what) {
  if (adapter_->buffer().TakeResetWarning()) {
    NODELET_WARN("pose_ekf: %s stamp jumped back by more than time_jump_reset_s; filter reset", what);
    ++time_jumps_back_;
    last_published_stamp_s_ = -1.0;
  }
  if (r == AddResult::kRejectedNonFinite || r == AddResult::kRejectedInvalid || r == AddResult::kDroppedLate ||
      r == AddResult::kGated) {
    NODELET_WARN_THROTTLE(1.0, "pose_ekf: %s %s: %s", what, ToString(r), why.c_str());
  } else if (!why.empty() && r != AddResult::kReinitialized) {
    NODELET_WARN_THROTTLE(5.0, "pose_ekf: %s: %s", what, why.c_str());  // used, with a note (e.g. |q| far from 1)
  }
  if (r == AddResult::kReinitialized) NODELET_WARN("pose_ekf: %s", why.c_str());  // once per re-initialisation
}

void PoseEkfNodelet::OnCamera(const geometry_msgs::PoseWithCovarianceStampedConstPtr& msg) {
  try {
    CheckTimeJump();
    camera_freq_->Tick(msg->header.stamp);
    std::string why;
    const AddResult r = adapter_->HandleCamera(*msg, &why);
    Report(r, why, "camera pose");
    if (r == AddResult::kInitialized) NODELET_INFO("pose_ekf: initialised from the first camera pose");
    if (r == AddResult::kInitialized || r == AddResult::kReinitialized || r == AddResult::kApplied ||
        r == AddResult::kReplayed) {
      Publish();
    }
  } catch (const std::exception& e) {
    NODELET_WARN_THROTTLE(1.0, "pose_ekf: camera callback failed: %s", e.what());
  }
}

void PoseEkfNodelet::OnObservations(const cone_tracker::ConeObservationsConstPtr& msg) {
  try {
    CheckTimeJump();
    observations_freq_->Tick(msg->header.stamp);
    std::string why;
    const AddResult r = adapter_->HandleObservations(*msg, &why);
    Report(r, why, "cone observations");
    if (r == AddResult::kApplied || r == AddResult::kReplayed) Publish();
  } catch (const std::exception& e) {
    NODELET_WARN_THROTTLE(1.0, "pose_ekf: cone observations callback failed: %s", e.what());
  }
}

void PoseEkfNodelet::OnImu(const sensor_msgs::ImuConstPtr& msg) {
  try {
    CheckTimeJump();
    imu_freq_->Tick(msg->header.stamp);
    Eigen::Quaterniond q_camera_imu;
    Eigen::Vector3d p_imu_in_camera_m;
    if (!ImuRotation(msg->header.frame_id, &q_camera_imu, &p_imu_in_camera_m)) {
      ++imu_without_tf_;
      return;
    }
    std::string why;
    const AddResult r = adapter_->HandleImu(*msg, q_camera_imu, &why, p_imu_in_camera_m);
    Report(r, why, "IMU sample");
    if (r == AddResult::kApplied || r == AddResult::kReplayed) Publish();
  } catch (const std::exception& e) {
    NODELET_WARN_THROTTLE(1.0, "pose_ekf: IMU callback failed: %s", e.what());
  }
}

// The camera-IMU rotation and lever arm are a static transform (3.2.2): looked up once per IMU frame.
bool PoseEkfNodelet::ImuRotation(const std::string& imu_frame, Eigen::Quaterniond* q, Eigen::Vector3d* p) {
  const std::string& camera_frame = adapter_->config().camera_frame;
  bool fresh = false;
  const std::optional<rig_model::ImuMount> mount =
      imu_mounts_.Lookup(*tf_buffer_, camera_frame, imu_frame, adapter_->config().tf_timeout_s, &imu_tf_error_, &fresh);
  if (!mount) {
    NODELET_WARN_THROTTLE(2.0, "pose_ekf: %s (IMU sample not used)", imu_tf_error_.c_str());
    return false;
  }
  const std::string refused = CheckLeverArm(mount->p_imu_in_camera_m, camera_frame, imu_frame);
  if (!refused.empty()) {
    imu_tf_error_ = refused;
    NODELET_ERROR_THROTTLE(5.0, "pose_ekf: %s", refused.c_str());
    return false;
  }
  *q = mount->q_camera_imu;
  *p = mount->p_imu_in_camera_m;
  if (fresh)
    NODELET_INFO("pose_ekf: camera-IMU rotation %s <- %s found, lever arm [%.3f %.3f %.3f] m", camera_frame.c_str(),
                 imu_frame.c_str(), p->x(), p->y(), p->z());
  return true;
}

void PoseEkfNodelet::Publish() {
  AdapterOutputs out;
  if (!adapter_->MakeOutputs(&out)) return;
  const double stamp = out.pose.header.stamp.toSec();
  if (stamp <= last_published_stamp_s_) return;  // a late camera frame re-applied in the past: nothing newer
  last_published_stamp_s_ = stamp;
  if (adapter_->config().publish_tf) tf_broadcaster_->sendTransform(out.tf);
  pose_pub_.publish(boost::make_shared<geometry_msgs::PoseWithCovarianceStamped>(out.pose));
  odom_pub_.publish(boost::make_shared<nav_msgs::Odometry>(out.odometry));
}

void PoseEkfNodelet::OnOutputTimer(const ros::TimerEvent& /*event*/) {
  AdapterOutputs out;
  const double now = ros::Time::now().toSec();
  if (now <= last_published_stamp_s_ || !adapter_->MakePredictedOutputs(now, &out)) return;
  last_published_stamp_s_ = now;
  if (adapter_->config().publish_tf) tf_broadcaster_->sendTransform(out.tf);
  pose_pub_.publish(boost::make_shared<geometry_msgs::PoseWithCovarianceStamped>(out.pose));
  odom_pub_.publish(boost::make_shared<nav_msgs::Odometry>(out.odometry));
}

void PoseEkfNodelet::Diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  const BufferCounters& c = adapter_->buffer().counters();
  if (imu_without_tf_ > imu_without_tf_reported_) {  // the IMU path is dead until the tf appears
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::ERROR, "%lu IMU sample(s) dropped since the last report: %s",
                  static_cast<unsigned long>(imu_without_tf_ - imu_without_tf_reported_), imu_tf_error_.c_str());
  } else if (!adapter_->buffer().filter().initialized()) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "waiting for the first camera pose");
  } else if (adapter_->buffer().ReacquireDue()) {
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::WARN,
                  "tracking poorly (position sigma %.2f m, %d camera frames gated in a row): the next camera pose "
                  "re-initialises the filter",
                  adapter_->buffer().PositionSigmaM(), adapter_->buffer().camera_gated_in_a_row());
  } else if (adapter_->buffer().camera_gated_in_a_row() > 0) {
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::WARN,
                  "tracking; the last %d camera frames (poses or cone observations) failed the chi2 gate",
                  adapter_->buffer().camera_gated_in_a_row());
  } else {
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "tracking");
  }
  stat.add("camera updates", c.camera_applied);
  stat.add("gyro updates", c.gyro_applied);
  stat.add("accel updates", c.accel_applied);
  stat.add("accel gated (|a| != g)", c.accel_gated);
  stat.add("camera poses rejected (chi2 gate)", c.camera_gated);
  stat.add("camera chi2 gate threshold (6 dof)", adapter_->buffer().filter().camera_gate_chi2());
  stat.add("camera chi2 of the last rejected pose", c.camera_gate_last_rejected_chi2);
  stat.add("re-initialisations (chi2 gate)", c.reinits);
  stat.add("camera poses rejected (bad quaternion, position, covariance or frame)", adapter_->camera_rejected());
  stat.add("camera quaternions normalised (| |q|^2 - 1 | > 0.01)", adapter_->camera_quaternions_normalized());
  // Tightly coupled camera updates (camera_update = cones).
  stat.add("camera update path", CameraUpdateName(adapter_->config().ekf.camera_update));
  stat.add("cone frames fused", c.cone_frames_applied);
  stat.add("cone frames rejected (no cone passed the gates)", c.cone_frames_rejected);
  stat.add("cone frames not fused while re-acquiring (fewer than reacquire_min_cones)", c.cone_frames_too_few);
  stat.add("lone cones not fused (another layout cone fits nearly as well)", c.cone_frames_ambiguous);
  stat.add("cone frames not fused (the same view as the last fused one, cone_repeat_px)", c.cone_frames_repeated);
  stat.add("cones fused", c.cones_applied);
  stat.add("cones rejected (chi2 gate)", c.cones_gated);
  stat.add("cones dropped (joint chi2 check of their frame)", c.cones_joint_dropped);
  stat.add("cones behind the predicted camera", c.cones_behind_camera);
  stat.add("cone chi2 gate threshold (4 dof)", adapter_->buffer().filter().cone_gate_chi2());
  stat.add("cone chi2 of the last rejection", c.cone_last_rejected_chi2);
  stat.add("cone NIS last (frame)", c.cone_nis_last);
  stat.add("cone NIS mean (frame)", c.cone_nis_count ? c.cone_nis_sum / c.cone_nis_count : 0.0);
  // Frames fuse one to many cones: per degree of freedom a consistent filter's NIS averages 1 (rig_check reads it).
  stat.add("cone NIS mean per dof", c.cone_nis_dof ? c.cone_nis_sum / static_cast<double>(c.cone_nis_dof) : 0.0);
  stat.add("cone observations refused (frame, stamp, intrinsics, no layout)", adapter_->observations_rejected());
  stat.add("cones refused (NaN pixel or covariance)", adapter_->cones_refused_nan());
  stat.add("cones refused (unknown cone_id, bad covariance)", adapter_->cones_refused_invalid());
  stat.add("cone frames before the first pose", c.cone_frames_before_start);
  stat.add("cone frames not used (camera_update = pose)", c.cone_frames_not_used);
  stat.add("camera poses not fused (their frame's cones were)", c.poses_superseded);
  stat.add("cone frames not fused (their pose (re-)initialised the filter)", c.cone_frames_superseded);
  stat.add("re-acquisitions from a camera pose (cones mode)", c.reacquisitions);
  stat.add("position sigma (m)", adapter_->buffer().PositionSigmaM());
  stat.add("dropped late", c.dropped_late);  // poses and IMU samples
  stat.add("cone frames dropped late", c.cone_frames_dropped_late);
  stat.add("IMU before the first pose", c.imu_before_start);
  stat.add("NaN rejected", c.nan_rejected + adapter_->nan_rejected());
  stat.add("invalid rejected", adapter_->invalid_rejected());
  imu_without_tf_reported_ = imu_without_tf_;
  stat.add("IMU without camera-IMU tf", imu_without_tf_);
  stat.add("time jumps back", time_jumps_back_);
  stat.add("numerical failures", c.numerical_failures);
  stat.add("resets", c.resets);
  stat.add("late replays", c.replays);
  stat.add("camera NIS last", c.camera_nis_last);
  stat.add("camera NIS mean", c.camera_nis_count ? c.camera_nis_sum / c.camera_nis_count : 0.0);
}

}  // namespace pose_ekf

PLUGINLIB_EXPORT_CLASS(pose_ekf::PoseEkfNodelet, nodelet::Nodelet)
