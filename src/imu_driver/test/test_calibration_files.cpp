// The calibration files (3.2.1, 3.2.2): the shipped ones load, and a file that cannot be used is
// refused with its name, the line and the field (a misspelt key also with the nearest known key).
#include <gtest/gtest.h>

#include <fstream>

#include "imu_driver/core/calibration_files.h"
#include "rig_model/strict_yaml.h"

namespace imu_driver {
namespace {

std::string Write(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "imu_driver_calibration_files_" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

template <typename Read>
std::string RefusalOf(Read read, const std::string& path) {
  try {
    read(path);
  } catch (const rig_model::FileError& e) {
    return e.what();
  }
  return "";
}

TEST(CalibrationFiles, ShippedFilesLoad) {
  const std::string dir = IMU_DRIVER_SOURCE_DIR;
  const CameraImuFile placeholder = ReadCameraImuFile(dir + "/config/camera_imu.yaml");
  EXPECT_EQ(placeholder.parent_frame, "camera_optical");
  EXPECT_EQ(placeholder.child_frame, "imu");
  EXPECT_DOUBLE_EQ(placeholder.q_camera_imu.w(), 1.0);
  const CameraImuFile sim = ReadCameraImuFile(dir + "/../ar_bringup/config/rig_sim_camera_imu.yaml");
  EXPECT_NEAR(sim.translation_m.y(), 0.08, 1e-12);
  EXPECT_NEAR(sim.q_camera_imu.norm(), 1.0, 1e-12);
  const GyroCalibrationFile gyro = ReadGyroCalibrationFile(dir + "/config/gyro_calibration.yaml");
  EXPECT_FALSE(gyro.gyro_bias_rad_s);  // the placeholder: not calibrated
}

TEST(CalibrationFiles, CalibrateCameraImuOutputLoads) {
  // The keys calibrate_camera_imu writes beside the rotation are its report, not typos.
  const std::string path = Write("tool.yaml",
                                 "camera_imu:\n  parent_frame: camera_optical\n  child_frame: imu\n"
                                 "  translation_m: [0.0, 0.0, 0.0]\n  rotation_xyzw: [0, 0, 0.6, 0.8]\n"
                                 "  method: svd_of_moment_matrix\n  rms_residual_deg: 0.1\n"
                                 "  euler_minimisation_rotation_xyzw: [0, 0, 0.6, 0.8]\n"
                                 "  euler_minimisation_rms_residual_deg: 0.1\n  svd_vs_euler_deg: 0.001\n"
                                 "  poses: 6\n");
  EXPECT_NEAR(ReadCameraImuFile(path).q_camera_imu.z(), 0.6, 1e-12);
}

TEST(CalibrationFiles, MisspeltKeyNamesFileLineAndNearestKey) {
  const std::string path =
      Write("misspelt.yaml", "camera_imu:\n  parent_frame: camera_optical\n  rotaton_xyzw: [0, 0, 0, 1]\n");
  EXPECT_EQ(RefusalOf(ReadCameraImuFile, path),
            path + ":3: unknown key 'camera_imu.rotaton_xyzw' (did you mean 'rotation_xyzw'?)");
  const std::string gyro =
      Write("gyro_misspelt.yaml", "# bias\ngyro_bias_rad_s: [0, 0, 0]\ngyro_nose_sigma_rad_s: [0, 0, 0]\n");
  EXPECT_EQ(RefusalOf(ReadGyroCalibrationFile, gyro),
            gyro + ":3: unknown key 'gyro_nose_sigma_rad_s' (did you mean 'gyro_noise_sigma_rad_s'?)");
}

TEST(CalibrationFiles, ZeroOrNonFiniteQuaternionIsRefused) {
  const std::string zero = Write("zero.yaml", "camera_imu:\n  rotation_xyzw: [0, 0, 0, 0]\n");
  EXPECT_NE(RefusalOf(ReadCameraImuFile, zero).find(zero + ":2: camera_imu.rotation_xyzw: must be a unit quaternion"),
            std::string::npos)
      << RefusalOf(ReadCameraImuFile, zero);
  const std::string nan = Write("nan.yaml", "camera_imu:\n  rotation_xyzw: [.nan, 0, 0, 1]\n");
  EXPECT_NE(RefusalOf(ReadCameraImuFile, nan).find(nan + ":2: camera_imu.rotation_xyzw: must be finite"),
            std::string::npos)
      << RefusalOf(ReadCameraImuFile, nan);
  const std::string missing = Write("missing.yaml", "camera_imu:\n  parent_frame: camera_optical\n");
  EXPECT_NE(RefusalOf(ReadCameraImuFile, missing).find("camera_imu.rotation_xyzw: is missing"), std::string::npos);
}

TEST(CalibrationFiles, RandomBytesNameTheFile) {
  const std::string path = Write("random.yaml", std::string("\xfe\xff\x00\x13\x80garbage", 12));
  EXPECT_EQ(RefusalOf(ReadCameraImuFile, path), path + ": not a text file (invalid UTF-8); expected YAML");
  EXPECT_EQ(RefusalOf(ReadGyroCalibrationFile, path), path + ": not a text file (invalid UTF-8); expected YAML");
  EXPECT_EQ(RefusalOf(ReadCameraImuFile, "/nonexistent/camera_imu.yaml"),
            "/nonexistent/camera_imu.yaml: cannot open the file");
}

}  // namespace
}  // namespace imu_driver
