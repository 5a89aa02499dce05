// imu_driver/ImuDriverNodelet: the Crista IMU on a serial port -> imu/data_raw.
// The port is read on the SerialReader's thread (onInit never blocks); samples
// are published from that thread (ros::Publisher is thread-safe).
#include <diagnostic_updater/diagnostic_updater.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <std_msgs/Bool.h>
#include <std_srvs/Trigger.h>

#include <fstream>
#include <memory>
#include <pluginlib/class_list_macros.hpp>

#include "imu_driver/core/calibration_session.h"
#include "imu_driver/core/serial_reader.h"
#include "imu_driver/node/ros_adapter.h"
#include "imu_driver_diagnostics.h"
#include "rig_model/ros/diagnostics.h"

namespace imu_driver {

class ImuDriverNodelet : public nodelet::Nodelet {
 public:
  ~ImuDriverNodelet() override {
    // Callbacks that use reader_ and the publishers stop first: the timer and
    // service (stop() waits for a running callback), then the I/O thread (joined).
    diagnostics_.reset();
    calibrate_srv_.shutdown();
    if (reader_) reader_->Stop();
  }

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    diagnostics_ = std::make_unique<rig_model::WallDiagnostics>(nh, pnh, getName(), "crista", 0.25);
    try {
      config_ = LoadConfig(pnh);
    } catch (const std::exception& e) {
      NODELET_FATAL("%s", diagnostics_->RefuseConfig("Crista IMU", "imu_driver", e.what()).c_str());
      return;
    }
    calibration_ = std::make_unique<CalibrationSession>(
        GyroCalibration{config_.gyro_bias_rad_s, config_.gyro_noise_sigma_rad_s, config_.gyro_bias_calibrated});
    imu_pub_ = nh.advertise<sensor_msgs::Imu>("imu/data_raw", 100);
    calibrated_pub_ = nh.advertise<std_msgs::Bool>("imu/is_calibrated", 1, true);
    PublishCalibrated();
    calibrate_srv_ = nh.advertiseService("imu/calibrate", &ImuDriverNodelet::OnCalibrate, this);

    diagnostics_->SetHardwareID("crista:" + config_.reader.port);
    rig_model::RateCheckConfig rate =
        rig_model::RateCheckConfig::Around(config_.reader.stream.rate_hz, config_.rate_tolerance);
    rate.stale_after_s = config_.stale_after_s;
    rate_diag_ = std::make_unique<rig_model::StampRateTask>("imu/data_raw rate", rate);
    diagnostics_->Add(*rate_diag_);
    diagnostics_->Add("Crista IMU", [this](diagnostic_updater::DiagnosticStatusWrapper& s) {
      driver_diagnostics_.Fill(reader_->status(), config_, calibration_->current(), ros::Time::now().toSec(), &s);
    });

    reader_ = std::make_unique<SerialReader>(
        config_.reader, [] { return ros::Time::now().toSec(); }, [this](const ImuSample& s) { OnSample(s); },
        [this](int level, const std::string& m) { Log(level, m); });
    if (config_.calibrate_on_start) {
      std::string m;
      calibration_->Start(config_.calibration_duration_s, &m);
      NODELET_INFO("%s", m.c_str());
    }
    reader_->Start();
  }

  void OnSample(const ImuSample& s) {
    if (const auto result = calibration_->Add(s)) OnCalibrationDone(*result);
    auto msg = boost::make_shared<sensor_msgs::Imu>();
    FillImuMessage(s, config_, calibration_->current(), msg.get());
    rate_diag_->Tick(msg->header.stamp);
    imu_pub_.publish(msg);
  }

  bool OnCalibrate(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    res.success = calibration_->Start(config_.calibration_duration_s, &res.message);
    if (res.success) NODELET_INFO("imu/calibrate: %s", res.message.c_str());
    return true;
  }

  void OnCalibrationDone(const GyroBiasResult& r) {
    if (!r.ok) {
      NODELET_ERROR("gyro bias calibration failed, keeping the previous bias: %s", r.message.c_str());
      return;
    }
    NODELET_INFO("gyro bias calibration: %s", r.message.c_str());
    PublishCalibrated();
    if (config_.calibration_output_file.empty()) return;
    std::ofstream out(config_.calibration_output_file);
    out << GyroCalibrationYaml(r);
    if (!out) NODELET_ERROR("cannot write %s", config_.calibration_output_file.c_str());
  }

  void PublishCalibrated() {
    std_msgs::Bool b;
    b.data = calibration_->current().calibrated;
    calibrated_pub_.publish(b);
  }

  void Log(int level, const std::string& m) {
    if (level >= 2) {
      NODELET_ERROR_THROTTLE(5.0, "%s", m.c_str());
    } else if (level == 1) {
      NODELET_WARN_THROTTLE(5.0, "%s", m.c_str());
    } else {
      NODELET_INFO("%s", m.c_str());
    }
  }

  DriverConfig config_;
  std::unique_ptr<CalibrationSession> calibration_;
  ros::Publisher imu_pub_, calibrated_pub_;
  ros::ServiceServer calibrate_srv_;
  std::unique_ptr<rig_model::StampRateTask> rate_diag_;
  DriverDiagnostics driver_diagnostics_;
  std::unique_ptr<rig_model::WallDiagnostics> diagnostics_;
  std::unique_ptr<SerialReader> reader_;  // last: destroyed first, after Stop()
};

}  // namespace imu_driver

PLUGINLIB_EXPORT_CLASS(imu_driver::ImuDriverNodelet, nodelet::Nodelet)
