// The cone_tracker nodelet: subscriptions, tf prediction, publishing,
// diagnostics and dynamic_reconfigure around TrackerAdapter. Image, camera_info
// and reconfigure callbacks all run on the nodelet's single-threaded queue, so
// there is no locking (tf's listener thread only fills its own thread-safe buffer).
#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <pluginlib/class_list_macros.hpp>

#include <algorithm>
#include <deque>
#include <memory>
#include <optional>
#include <set>
#include <utility>

#include "cone_tracker/ConeTrackerConfig.h"
#include "cone_tracker/node/layout.h"
#include "cone_tracker/node/params.h"
#include "cone_tracker/node/tracker_adapter.h"
#include "cone_tracker/node/visuals.h"
#include "cone_tracker/vision/two_cone_pose.h"
#include "pose_math/pose.h"
#include "rig_model/ros/conversions.h"
#include "rig_model/ros/diagnostics.h"
#include "rig_model/ros/imu_mount.h"
#include "rig_model/ros/param_table_ros.h"

namespace cone_tracker {

class ConeTrackerNodelet : public nodelet::Nodelet {
 private:
  // A member type, not file-local: in a unity batch a file-local type in a
  // member of this class trips -Wsubobject-linkage.
  struct RunningStat {
    double last = 0, max = 0, sum = 0;
    uint64_t n = 0;
    void Add(double v) { last = v, max = std::max(max, v), sum += v, ++n; }
    double mean() const { return n ? sum / double(n) : 0.0; }
  };

  void onInit() override;
  void WarnIfSymmetric(const NodeConfig& config, const std::vector<ConeModel>& layout);
  void SetUpRateChecks(const NodeConfig& config);
  void SetUpPublishers(ros::NodeHandle& nh, const NodeConfig& config, const std::vector<ConeModel>& layout);
  void SetUpReconfigure(ros::NodeHandle& pnh, const NodeConfig& config);
  void OnImage(const sensor_msgs::ImageConstPtr& msg);
  void OnCameraInfo(const sensor_msgs::CameraInfoConstPtr& msg);
  void OnReconfigure(ConeTrackerConfig& cfg, uint32_t level);
  std::optional<pose_math::Pose> TfPrediction(const ros::Time& stamp);
  void OnFilterPose(const geometry_msgs::PoseWithCovarianceStampedConstPtr& msg);
  void OnImu(const sensor_msgs::ImuConstPtr& msg);
  std::optional<pose_math::Matrix6d> FilterCovariance(const ros::Time& stamp) const;
  void Report(const FrameResult& r, const sensor_msgs::Image& image);
  void Diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);

  std::unique_ptr<TrackerAdapter> adapter_;
  std::string fatal_;  // why the tracker is not running (bad parameter or layout)
  std::unique_ptr<image_transport::ImageTransport> it_;
  image_transport::Subscriber image_sub_;
  image_transport::Publisher debug_pub_;
  ros::Subscriber info_sub_, filter_pose_sub_, imu_sub_;
  // The two-cone start's gravity: the accelerometer in camera_frame, and the camera <- IMU mount per IMU frame.
  GravityWindow gravity_;
  rig_model::ImuMountCache imu_mounts_;
  std::deque<std::pair<ros::Time, pose_math::Matrix6d>> filter_covs_;  // pose_ekf/pose's, the last second
  ros::Publisher pose_pub_, detections_pub_, observations_pub_, markers_pub_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::unique_ptr<rig_model::WallDiagnostics> diagnostics_;
  std::unique_ptr<rig_model::StampRateTask> image_freq_, pose_freq_;
  boost::recursive_mutex reconfigure_mutex_;  // lets updateConfig() seed the server safely
  std::unique_ptr<dynamic_reconfigure::Server<ConeTrackerConfig>> reconfigure_;
  std::set<std::string> encodings_reported_;
  std::string last_problem_;
  FrameStatus last_status_ = FrameStatus::kNoCameraInfo;
  bool any_frame_ = false;
  RunningStat latency_ms_, processing_ms_;
  uint64_t tf_predictions_ = 0, tf_extrapolated_ = 0, debug_images_ = 0, filter_poses_refused_ = 0;
  uint64_t imu_samples_ = 0, imu_refused_ = 0;
};

void ConeTrackerNodelet::onInit() {
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  diagnostics_ = std::make_unique<rig_model::WallDiagnostics>(nh, pnh, getName(), "cone_tracker");
  diagnostics_->Add("tracker", [this](diagnostic_updater::DiagnosticStatusWrapper& s) { Diagnose(s); });

  NodeConfig config;
  std::vector<ConeModel> layout;
  std::string error;
  try {
    config = LoadConfig(pnh);
    if (!LoadLayoutFile(config.layout_file, &layout, &error)) throw std::invalid_argument(error);
    adapter_ = std::make_unique<TrackerAdapter>(config, layout);
  } catch (const std::exception& e) {
    fatal_ = diagnostics_->RefuseConfig("tracker", "cone_tracker", e.what());
    NODELET_FATAL("%s", fatal_.c_str());
    return;
  }
  WarnIfSymmetric(config, layout);
  SetUpRateChecks(config);
  SetUpPublishers(nh, config, layout);
  SetUpReconfigure(pnh, config);
  info_sub_ = nh.subscribe("camera/camera_info", 1, &ConeTrackerNodelet::OnCameraInfo, this);
  image_sub_ = it_->subscribe("camera/image_raw", 2, &ConeTrackerNodelet::OnImage, this);
  NODELET_INFO("cone_tracker: %zu cones from %s; %s + %s -> cone_tracker/pose in '%s'", layout.size(),
               config.layout_file.c_str(), image_sub_.getTopic().c_str(), info_sub_.getTopic().c_str(),
               config.fixed_frame.c_str());
}

void ConeTrackerNodelet::WarnIfSymmetric(const NodeConfig& config, const std::vector<ConeModel>& layout) {
  if (!LayoutHasRotationalSymmetry(layout)) return;
  NODELET_WARN(
      "cone_tracker: the layout in %s is rotationally symmetric (identical cones): without a prediction the "
      "rotated poses fit equally well; heading_prior_deg (%s) picks one. Asymmetric layouts (different heights, "
      "uneven spacing, a stacked cone) avoid this.",
      config.layout_file.c_str(),
      std::isnan(config.heading_prior_deg) ? "not set" : std::to_string(config.heading_prior_deg).c_str());
}

void ConeTrackerNodelet::SetUpRateChecks(const NodeConfig& config) {
  rig_model::RateCheckConfig rate = rig_model::RateCheckConfig::Around(config.expected_rate_hz, config.rate_tolerance);
  image_freq_ = std::make_unique<rig_model::StampRateTask>("image input", rate);  // no images: ERROR
  rate.stale_level = diagnostic_msgs::DiagnosticStatus::WARN;                     // no cones in view is no fault
  pose_freq_ = std::make_unique<rig_model::StampRateTask>("pose rate", rate);
  diagnostics_->Add(*image_freq_);
  diagnostics_->Add(*pose_freq_);
}

void ConeTrackerNodelet::SetUpPublishers(ros::NodeHandle& nh, const NodeConfig& config,
                                         const std::vector<ConeModel>& layout) {
  if (config.use_tf_prediction || config.two_cone_gravity_sigma_deg > 0.0) {
    tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);
  }
  // The tf prediction's covariance, for the per-cone association's spread (pose/associate.h).
  if (config.use_tf_prediction)
    filter_pose_sub_ = nh.subscribe("pose_ekf/pose", 50, &ConeTrackerNodelet::OnFilterPose, this);
  if (config.two_cone_gravity_sigma_deg > 0.0)
    imu_sub_ = nh.subscribe("imu/data_raw", 200, &ConeTrackerNodelet::OnImu, this);
  pose_pub_ = nh.advertise<geometry_msgs::PoseWithCovarianceStamped>("cone_tracker/pose", 10);
  detections_pub_ = nh.advertise<ConeDetections>("cone_tracker/detections", 10);
  observations_pub_ = nh.advertise<ConeObservations>("cone_tracker/observations", 10);
  markers_pub_ = nh.advertise<visualization_msgs::MarkerArray>("cone_tracker/cones", 1, /*latch=*/true);
  markers_pub_.publish(
      boost::make_shared<visualization_msgs::MarkerArray>(MakeLayoutMarkers(layout, config.fixed_frame)));
  it_ = std::make_unique<image_transport::ImageTransport>(nh);
  debug_pub_ = it_->advertise("cone_tracker/debug_image", 1);
}

// The server starts from the loaded parameters, not the .cfg defaults; both sides go through the
// parameter table, by name.
void ConeTrackerNodelet::SetUpReconfigure(ros::NodeHandle& pnh, const NodeConfig& config) {
  reconfigure_ = std::make_unique<dynamic_reconfigure::Server<ConeTrackerConfig>>(reconfigure_mutex_, pnh);
  reconfigure_->updateConfig(rig_model::ToReconfigure<NodeConfig, ConeTrackerConfig>(NodeParams(), config));
  reconfigure_->setCallback([this](ConeTrackerConfig& cfg, uint32_t level) { OnReconfigure(cfg, level); });
}

void ConeTrackerNodelet::OnReconfigure(ConeTrackerConfig& cfg, uint32_t /*level*/) {
  NodeConfig c = adapter_->config();
  try {
    rig_model::FromReconfigure(NodeParams(), cfg, &c);
    adapter_->Reconfigure(c.segmenter, c.pose, c.debug);
  } catch (const std::exception& e) {
    NODELET_WARN("cone_tracker: reconfigure refused, settings unchanged: %s", e.what());
    cfg = rig_model::ToReconfigure<NodeConfig, ConeTrackerConfig>(NodeParams(), adapter_->config());  // in use
  }
}

void ConeTrackerNodelet::OnCameraInfo(const sensor_msgs::CameraInfoConstPtr& msg) {
  if (!adapter_) return;
  const bool was_valid = adapter_->has_camera_info() && adapter_->camera_info_valid();
  std::string error;
  if (!adapter_->SetCameraInfo(*msg, &error)) {
    NODELET_ERROR_THROTTLE(5.0, "cone_tracker: %s on %s; no pose until a valid one arrives", error.c_str(),
                           info_sub_.getTopic().c_str());
  } else if (!was_valid && adapter_->has_camera_info()) {
    NODELET_INFO_ONCE("cone_tracker: camera_info received (%ux%u)", msg->width, msg->height);
  }
}

// The pose_ekf estimate at the image stamp; if tf does not reach that stamp
// yet, the latest transform when it is recent enough, carried on to the stamp
// at the rates it had over the kRateSpanS before it (tf2 does not extrapolate).
// Never waits.
std::optional<pose_math::Pose> ConeTrackerNodelet::TfPrediction(const ros::Time& stamp) {
  // Two of pose_ekf's 100 Hz samples: the rates are current, and not one sample's interpolation.
  constexpr double kRateSpanS = 0.02;
  const NodeConfig& c = adapter_->config();
  if (!tf_buffer_ || !c.use_tf_prediction) return std::nullopt;
  const auto pose_of = [](const geometry_msgs::TransformStamped& tf) {
    pose_math::Pose T = rig_model::FromTransformMsg(tf.transform);
    T.q.normalize();
    return T;
  };
  pose_math::Pose T;
  try {
    if (tf_buffer_->canTransform(c.fixed_frame, c.camera_frame, stamp)) {
      T = pose_of(tf_buffer_->lookupTransform(c.fixed_frame, c.camera_frame, stamp));
    } else {
      const geometry_msgs::TransformStamped newest =
          tf_buffer_->lookupTransform(c.fixed_frame, c.camera_frame, ros::Time(0));
      const double age_s = (stamp - newest.header.stamp).toSec();
      if (std::abs(age_s) > c.prediction_max_age_s) return std::nullopt;
      T = pose_of(newest);
      const ros::Time before = newest.header.stamp - ros::Duration(kRateSpanS);
      if (age_s > 0.0 && tf_buffer_->canTransform(c.fixed_frame, c.camera_frame, before)) {
        // pose_ekf's newest pose is older than the image (it has not fused the IMU up to the stamp yet, typically
        // 8-22 ms on rig_sim's replays): held, it lags a turning camera by 0.4 deg RMS, extrapolated by 0.03-0.12
        // deg (README, "The tf prediction at the image stamp").
        T = pose_math::ExtrapolateConstantRate(
            pose_of(tf_buffer_->lookupTransform(c.fixed_frame, c.camera_frame, before)), before.toSec(), T,
            newest.header.stamp.toSec(), stamp.toSec());
        ++tf_extrapolated_;
      }
    }
  } catch (const tf2::TransformException&) {
    return std::nullopt;  // no pose_ekf running: the last pose or the linear algorithms take over
  }
  if (!T.q.allFinite() || !T.t.allFinite()) return std::nullopt;
  ++tf_predictions_;
  return T;
}

void ConeTrackerNodelet::OnFilterPose(const geometry_msgs::PoseWithCovarianceStampedConstPtr& msg) {
  if (!adapter_) return;
  const pose_math::Matrix6d cov =
      Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(msg->pose.covariance.data());
  const bool frame_ok = msg->header.frame_id == adapter_->config().fixed_frame;
  if (!frame_ok || !cov.allFinite() || !(cov.diagonal().minCoeff() > 0.0)) {
    ++filter_poses_refused_;
    const std::string why = frame_ok ? "pose.covariance is not finite with a positive diagonal"
                                     : "header.frame_id is '" + msg->header.frame_id + "', expected '" +
                                           adapter_->config().fixed_frame + "'";
    NODELET_WARN_THROTTLE(5.0, "cone_tracker: %s: %s; its covariance is not used for the association",
                          filter_pose_sub_.getTopic().c_str(), why.c_str());
    return;
  }
  if (!filter_covs_.empty() && msg->header.stamp < filter_covs_.back().first) filter_covs_.clear();  // time jumped
  filter_covs_.emplace_back(msg->header.stamp, cov);
  while (filter_covs_.size() > 1 && (msg->header.stamp - filter_covs_.front().first).toSec() > 1.0)
    filter_covs_.pop_front();
}

// The covariance of pose_ekf's estimate nearest the image stamp, if within prediction_max_age_s.
std::optional<pose_math::Matrix6d> ConeTrackerNodelet::FilterCovariance(const ros::Time& stamp) const {
  const auto age = [&](const ros::Time& t) { return std::abs((t - stamp).toSec()); };
  const std::pair<ros::Time, pose_math::Matrix6d>* best = nullptr;
  for (const auto& c : filter_covs_)
    if (!best || age(c.first) < age(best->first)) best = &c;
  if (!best || age(best->first) > adapter_->config().prediction_max_age_s) return std::nullopt;
  return best->second;
}

// The accelerometer, turned into camera_frame, for the two-cone start's "up" (GravityWindow), through the camera-IMU
// mount pose_ekf uses too (rig_model::ImuMountCache).
void ConeTrackerNodelet::OnImu(const sensor_msgs::ImuConstPtr& msg) {
  if (!adapter_ || !tf_buffer_) return;
  std::string error;
  const std::optional<rig_model::ImuMount> mount =
      imu_mounts_.Lookup(*tf_buffer_, adapter_->config().camera_frame, msg->header.frame_id, 0.0, &error);
  if (!mount) {
    ++imu_refused_;
    NODELET_WARN_THROTTLE(5.0, "cone_tracker: %s: %s: no gravity for the two-cone start", imu_sub_.getTopic().c_str(),
                          error.c_str());
    return;
  }
  const auto& a = msg->linear_acceleration;
  if (!gravity_.Add(msg->header.stamp.toSec(), mount->q_camera_imu * Eigen::Vector3d(a.x, a.y, a.z))) {
    ++imu_refused_;
    NODELET_WARN_THROTTLE(5.0, "cone_tracker: %s: non-finite linear_acceleration or stamp, sample dropped",
                          imu_sub_.getTopic().c_str());
    return;
  }
  ++imu_samples_;
}

void ConeTrackerNodelet::OnImage(const sensor_msgs::ImageConstPtr& msg) {
  if (!adapter_) return;
  const ros::WallTime start = ros::WallTime::now();
  try {
    any_frame_ = true;
    image_freq_->Tick(msg->header.stamp);
    const NodeConfig& c = adapter_->config();
    const std::optional<pose_math::Pose> tf_prediction = TfPrediction(msg->header.stamp);
    // Gravity only for a frame the two-cone start may take: none while pose_ekf's tf predicts (the tracking case).
    const std::optional<Eigen::Vector3d> up = c.two_cone_gravity_sigma_deg > 0.0 && !tf_prediction
                                                  ? gravity_.UpAt(msg->header.stamp.toSec(), 0.5 * c.gravity_window_s)
                                                  : std::nullopt;
    const FrameResult r = adapter_->Process(msg, tf_prediction, FilterCovariance(msg->header.stamp), up);
    if (r.pose) {
      pose_freq_->Tick(r.pose->header.stamp);
      pose_pub_.publish(r.pose);
      latency_ms_.Add((ros::Time::now() - msg->header.stamp).toSec() * 1e3);
    }
    if (r.observations) observations_pub_.publish(r.observations);
    if (r.detections) detections_pub_.publish(r.detections);
    if (debug_pub_.getNumSubscribers() > 0 && r.status != FrameStatus::kUnsupportedEncoding &&
        r.status != FrameStatus::kBadImage) {
      if (auto img = MakeDebugImage(msg, adapter_->segmenter().mask(), r, adapter_->config().debug)) {
        debug_pub_.publish(img);
        ++debug_images_;
      }
    }
    Report(r, *msg);
  } catch (const std::exception& e) {
    last_problem_ = std::string("image callback failed: ") + e.what();
    NODELET_WARN_THROTTLE(1.0, "cone_tracker: %s", last_problem_.c_str());
  }
  processing_ms_.Add((ros::WallTime::now() - start).toSec() * 1e3);
}

void ConeTrackerNodelet::Report(const FrameResult& r, const sensor_msgs::Image& image) {
  last_status_ = r.status;
  if (r.time_jumped_back) NODELET_WARN("cone_tracker: image stamp went back in time; the last pose is forgotten");
  if (r.status == FrameStatus::kPose) return;
  last_problem_ = std::string(ToString(r.status)) + ": " + r.message;
  switch (r.status) {
    case FrameStatus::kUnsupportedEncoding:
      if (encodings_reported_.insert(image.encoding).second) NODELET_ERROR("cone_tracker: %s", r.message.c_str());
      break;
    case FrameStatus::kBadImage:
    case FrameStatus::kNoCameraInfo:
    case FrameStatus::kBadCameraInfo:
    case FrameStatus::kSizeMismatch:
      NODELET_WARN_THROTTLE(5.0, "cone_tracker: %s", last_problem_.c_str());
      break;
    default:
      NODELET_DEBUG("cone_tracker: %s", last_problem_.c_str());  // no cones in view is normal
  }
}

void ConeTrackerNodelet::Diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  using diagnostic_msgs::DiagnosticStatus;
  if (!adapter_) {
    stat.summary(DiagnosticStatus::ERROR, fatal_);  // not reached once RefuseConfig replaced this task
    return;
  }
  if (adapter_->has_camera_info() && !adapter_->camera_info_valid()) {
    stat.summary(DiagnosticStatus::ERROR, "invalid camera_info: " + adapter_->camera_info_error());
  } else if (!any_frame_) {
    stat.summary(DiagnosticStatus::WARN, "waiting for images");
  } else if (last_status_ == FrameStatus::kPose) {
    stat.summary(DiagnosticStatus::OK, "tracking");
  } else {
    stat.summary(DiagnosticStatus::WARN, "no pose: " + last_problem_);
  }
  const TrackerCounters& c = adapter_->counters();
  stat.add("last problem", last_problem_);
  stat.add("frames", c.frames);
  stat.add("poses published", c.poses);
  stat.add("cones found (mean per segmented frame)",
           c.segmented_frames ? double(c.cones_found_sum) / double(c.segmented_frames) : 0.0);
  stat.add("frames with no cones", c.no_cones);
  stat.add("frames with too few cones", c.too_few_cones);
  stat.add("rejected by chi-square gate", c.rejected_chi2);
  stat.add("rejected by motion gate", c.rejected_motion);
  stat.add("cold starts refused (another assignment fits too)", c.rejected_ambiguous);
  stat.add("pose solver failures", c.solver_failed);
  stat.add("observations published", c.observation_msgs);
  stat.add("observed cones (mean per observation)",
           c.observation_msgs ? double(c.observed_cones_sum) / double(c.observation_msgs) : 0.0);
  for (const auto& [n_cones, n] : c.observation_msgs_by_cones)
    stat.add("observations with " + std::to_string(n_cones) + " cone(s)", n);
  stat.add("detections left unassociated (ambiguous)", c.association_ambiguous);
  stat.add("frames whose prediction conflicted with a cone (none associated)", c.association_conflicts);
  stat.add("association/pose correspondence disagreements", c.association_disagreements);
  stat.add("frames with cones but no prediction or pose (not observed)", c.unobserved_no_prediction);
  for (const auto& [gate, n] : c.blobs_rejected_by_gate) stat.add("blobs rejected by gate " + gate, n);
  stat.add("unsupported encoding frames", c.unsupported_encoding);
  stat.add("bad images", c.bad_image);
  stat.add("frames without camera_info", c.no_camera_info);
  stat.add("frames with invalid camera_info", c.bad_camera_info_frames);
  stat.add("invalid camera_info messages", c.bad_camera_info_msgs);
  stat.add("image/camera_info size mismatches", c.size_mismatch);
  stat.add("time jumps back", c.time_jumps);
  stat.add("re-acquisitions (tf prediction ignored)", c.reacquisitions);
  stat.add("frames predicted by the re-acquired track, tf contradicting it", c.tf_overruled);
  stat.add("poses from two cones and gravity", c.two_cone_poses);
  stat.add("two-cone starts refused (no pair of layout cones fits, or two fit alike)", c.two_cone_refused);
  stat.add("two-cone frames without gravity (no imu/data_raw around the stamp)", c.two_cone_no_gravity);
  stat.add("IMU samples for gravity", imu_samples_);
  stat.add("IMU samples refused (non-finite, or no tf to camera_frame)", imu_refused_);
  stat.add("tf predictions used", tf_predictions_);
  stat.add("tf predictions extrapolated to the image stamp", tf_extrapolated_);
  stat.add("associations spread by pose_ekf's covariance", c.association_filter_covariance);
  stat.add("pose_ekf/pose messages refused (frame or covariance)", filter_poses_refused_);
  stat.add("debug images built", debug_images_);
  stat.add("latency stamp to publish last (ms)", latency_ms_.last);
  stat.add("latency stamp to publish max (ms)", latency_ms_.max);
  stat.add("processing time last (ms)", processing_ms_.last);
  stat.add("processing time mean (ms)", processing_ms_.mean());
  stat.add("processing time max (ms)", processing_ms_.max);
}

}  // namespace cone_tracker

PLUGINLIB_EXPORT_CLASS(cone_tracker::ConeTrackerNodelet, nodelet::Nodelet)
