// aravis_camera/CameraNodelet: publishes camera/image_raw and camera/camera_info
// from a GigE Vision camera, without copying frames to nodelets in the same
// manager. The camera is opened on CameraDevice's thread, so onInit never blocks.
#include <camera_info_manager/camera_info_manager.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include <atomic>
#include <memory>

#include "aravis_camera/CameraLiveConfig.h"
#include "aravis_camera/device/camera_device.h"
#include "aravis_camera/node/ros_config.h"
#include "rig_model/ros/diagnostics.h"

namespace aravis_camera {

class CameraNodelet : public nodelet::Nodelet {
 public:
  ~CameraNodelet() override {
    if (device_) device_->Stop();  // joins the thread before the publishers go
  }

 private:
  void onInit() override {
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    diagnostics_ = std::make_unique<rig_model::WallDiagnostics>(getNodeHandle(), pnh, getName(), "aravis_camera");
    diagnostics_->Add("camera", [this](diagnostic_updater::DiagnosticStatusWrapper& s) { Diagnose(s); });
    try {
      config_ = LoadConfig(pnh);
    } catch (const std::exception& e) {
      config_error_ = diagnostics_->RefuseConfig("camera", "aravis_camera", e.what());
      NODELET_ERROR("%s", config_error_.c_str());
      return;
    }
    ros::NodeHandle camera_nh(getNodeHandle(), "camera");
    cinfo_ = std::make_shared<camera_info_manager::CameraInfoManager>(camera_nh, config_.camera_info_name,
                                                                      config_.camera_info_url);
    image_transport::ImageTransport it(camera_nh);
    publisher_ = it.advertiseCamera("image_raw", 1);

    frequency_ = std::make_unique<rig_model::StampRateTask>(
        "frame rate", rig_model::RateCheckConfig::Around(config_.camera.frame_rate_hz, kRateTolerance));
    diagnostics_->Add(*frequency_);

    device_ = std::make_unique<CameraDevice>(
        config_.camera, [this](const sensor_msgs::ImagePtr& image, const FrameInfo&) { Publish(image); },
        [this](LogLevel level, const std::string& msg) { LogFromDevice(level, msg); });

    reconfigure_ = std::make_unique<dynamic_reconfigure::Server<CameraLiveConfig>>(pnh);
    reconfigure_->updateConfig(ToLive(config_));  // seeded from the table, as the parameters loaded
    reconfigure_->setCallback([this](CameraLiveConfig& live, uint32_t) {
      const CameraConfig c = FromLive(live, config_).camera;
      frequency_->SetRateLimits(c.frame_rate_hz * (1.0 - kRateTolerance), c.frame_rate_hz * (1.0 + kRateTolerance));
      device_->UpdateSettings(LiveSettings{c.frame_rate_hz, c.exposure_auto, c.exposure_us, c.gain_db});
    });
    device_->Start();
  }

  void Publish(const sensor_msgs::ImagePtr& image) {
    auto info = boost::make_shared<sensor_msgs::CameraInfo>(cinfo_->getCameraInfo());
    if (info->width != 0 && (info->width != image->width || info->height != image->height)) {
      ++calibration_mismatches_;
      NODELET_WARN_THROTTLE(10.0, "camera_info is for %ux%u but frames are %ux%u: check ~camera_info_url", info->width,
                            info->height, image->width, image->height);
    }
    info->header = image->header;
    frequency_->Tick(image->header.stamp);
    publisher_.publish(image, info);  // image is never touched again here
  }

  void LogFromDevice(LogLevel level, const std::string& msg) {
    if (level == LogLevel::kError) {
      NODELET_ERROR("%s", msg.c_str());
    } else if (level == LogLevel::kWarn) {
      NODELET_WARN("%s", msg.c_str());
    } else {
      NODELET_INFO("%s", msg.c_str());
    }
  }

  void Diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
    if (!config_error_.empty()) {
      stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, config_error_);
      return;
    }
    const DeviceStats s = device_->stats();
    if (!s.connected) {
      stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "camera not connected: " + s.last_error);
    } else if (s.frames_dropped > 0 || s.underruns > 0) {
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "streaming, with dropped frames or underruns");
    } else {
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "streaming");
    }
    stat.add("camera", s.camera_id);
    stat.add("frames published", s.frames_published);
    stat.add("frames incomplete", s.frames_incomplete);
    stat.add("frames dropped (incomplete)", s.frames_dropped);
    stat.add("missing packets", s.missing_packets);
    stat.add("resent packets", s.resent_packets);
    stat.add("buffer underruns", s.underruns);
    stat.add("frames held by subscribers", s.frames_in_flight);
    stat.add("reconnects", s.reconnects);
    stat.add("open failures", s.open_failures);
    stat.add("settings not applied", s.settings_failures);
    stat.add("camera_info size mismatches", calibration_mismatches_.load());
    stat.add("seconds since last frame", s.seconds_since_frame);
    stat.add("last error", s.last_error);
  }

  NodeConfig config_;
  std::string config_error_;
  std::shared_ptr<camera_info_manager::CameraInfoManager> cinfo_;
  image_transport::CameraPublisher publisher_;
  static constexpr double kRateTolerance = 0.1;
  std::unique_ptr<rig_model::WallDiagnostics> diagnostics_;
  std::unique_ptr<rig_model::StampRateTask> frequency_;
  std::unique_ptr<dynamic_reconfigure::Server<CameraLiveConfig>> reconfigure_;
  std::atomic<uint64_t> calibration_mismatches_{0};
  std::unique_ptr<CameraDevice> device_;  // last: destroyed (and joined) first
};

}  // namespace aravis_camera

PLUGINLIB_EXPORT_CLASS(aravis_camera::CameraNodelet, nodelet::Nodelet)
