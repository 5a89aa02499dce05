// Parameters of the pose_ekf nodelet: frames, output rate and the core's EkfConfig.
#pragma once

#include <string>
#include <vector>

#include "pose_ekf/core/config.h"

namespace ros {
class NodeHandle;
}

namespace pose_ekf {

struct NodeConfig {
  std::string cones_frame = "cones";            // fixed frame {M}, z up
  std::string camera_frame = "camera_optical";  // {C}
  bool publish_tf = true;
  double output_rate_hz = 0.0;  // > 0: also publish the pose predicted to now at this rate (thesis: 40 Hz)
  double imu_expected_rate_hz = 100.0;
  double camera_expected_rate_hz = 30.0;
  double tf_timeout_s = 0.05;                                         // wait for the camera-IMU static transform
  AccelMode accel_mode_when_on = AccelMode::kPositionAndOrientation;  // for the use_accel switch
  EkfConfig ekf;
};

// Where parameters come from: the ROS parameter server or a YAML file (ekf_replay).
// Each Get leaves *value untouched when the parameter is absent.
class ParamSource {
 public:
  virtual ~ParamSource() = default;
  virtual void Get(const std::string& name, double* value) const = 0;
  virtual void Get(const std::string& name, bool* value) const = 0;
  virtual void Get(const std::string& name, std::string* value) const = 0;
};

// Reads the parameters (names as in NodeConfig/EkfConfig; enums as strings:
// accel_mode off|orientation|position_orientation, quat_integration
// first_order|exact). Throws std::invalid_argument naming the bad parameter.
NodeConfig LoadConfig(const ParamSource& params);
// From the private namespace; a parameter there that LoadConfig does not read is refused
// ("parameter ~sigma_gyr_rad_s is unknown (did you mean ~sigma_gyro_rad_s?)"), naming ~config_file,
// the YAML the launch file loaded, when it is set (and checking that file's keys line by line).
NodeConfig LoadConfig(const ros::NodeHandle& private_nh);
// The same from a YAML file of config/pose_ekf.yaml's form; an unknown key is refused with the file,
// its line and the nearest known key.
NodeConfig LoadConfigFile(const std::string& yaml_path);
// Every parameter name LoadConfig reads (recorded from LoadConfig itself).
std::vector<std::string> ParamNames();

// Parsers shared with dynamic_reconfigure and tools; throw std::invalid_argument.
AccelMode ParseAccelMode(const std::string& s);
QuatIntegration ParseQuatIntegration(const std::string& s);

}  // namespace pose_ekf
