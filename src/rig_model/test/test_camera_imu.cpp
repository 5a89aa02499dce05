#include "rig_model/camera_imu.h"

#include <unistd.h>

#include <fstream>
#include <functional>

#include <gtest/gtest.h>

#include "rig_model/strict_yaml.h"
#include "test_util.h"

namespace rig_model {
namespace {

TEST(CameraImu, ShippedFilesLoad) {
  const CameraImuExtrinsics placeholder = LoadCameraImuFile(RIG_MODEL_SRC_DIR "/imu_driver/config/camera_imu.yaml");
  EXPECT_EQ(placeholder.parent_frame, "camera_optical");
  EXPECT_EQ(placeholder.child_frame, "imu");
  EXPECT_TRUE(placeholder.R_camera_imu().isIdentity(1e-15));
  LoadCameraImuFile(RIG_MODEL_SRC_DIR "/ar_bringup/config/rig_sim_camera_imu.yaml");
}

// ar_bringup's file is what a perfect calibration of the simulated rig gives: rig_sim's mount.
TEST(CameraImu, SimulatedRigFileIsTheSimulatorsMount) {
  const CameraImuExtrinsics e = LoadCameraImuFile(RIG_MODEL_SRC_DIR "/ar_bringup/config/rig_sim_camera_imu.yaml");
  EXPECT_LT((e.R_camera_imu() - MountRotation(Eigen::Vector3d(1.5, -2.0, 1.0))).norm(), 1e-12);
  EXPECT_LT((e.p_imu_in_camera_m - Eigen::Vector3d(0.02, 0.08, -0.06)).norm(), 1e-15);
}

TEST(CameraImu, NominalMountMapsImuAxesOntoTheCamera) {
  const Eigen::Matrix3d R = MountRotation(Eigen::Vector3d::Zero());
  EXPECT_TRUE((R * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitZ()));   // forward
  EXPECT_TRUE((R * Eigen::Vector3d::UnitY()).isApprox(-Eigen::Vector3d::UnitX()));  // left
  EXPECT_TRUE((R * Eigen::Vector3d::UnitZ()).isApprox(-Eigen::Vector3d::UnitY()));  // up
}

TEST(CameraImu, BadFilesAreRefusedAndNamed) {
  const std::string typo = ErrorOf([] {
    LoadCameraImuFile(WriteTestFile("camera_imu.yaml",
                                    "camera_imu:\n  parent_frame: camera_optical\n  rotation_xyz: [0, 0, 0, 1]\n"));
  });
  EXPECT_NE(typo.find(":3: unknown key 'camera_imu.rotation_xyz' (did you mean 'rotation_xyzw'?)"), std::string::npos)
      << typo;
  const std::string norm = ErrorOf(
      [] { LoadCameraImuFile(WriteTestFile("camera_imu.yaml", "camera_imu:\n  rotation_xyzw: [0, 0, 0, 2]\n")); });
  EXPECT_NE(norm.find("camera_imu.rotation_xyzw: must be a unit quaternion"), std::string::npos) << norm;
  const std::string missing =
      ErrorOf([] { LoadCameraImuFile(WriteTestFile("camera_imu.yaml", "camera_imu:\n  child_frame: imu\n")); });
  EXPECT_NE(missing.find("camera_imu.rotation_xyzw: is missing"), std::string::npos) << missing;
  const std::string len = ErrorOf([] {
    LoadCameraImuFile(
        WriteTestFile("camera_imu.yaml", "camera_imu:\n  rotation_xyzw: [0, 0, 0, 1]\n  translation_m: [1, 2]\n"));
  });
  EXPECT_NE(len.find("camera_imu.translation_m: must be a list of 3 numbers"), std::string::npos) << len;
  // A lever arm in centimetres written as metres: 12 m is no rig.
  const std::string absurd = ErrorOf([] {
    LoadCameraImuFile(
        WriteTestFile("camera_imu.yaml", "camera_imu:\n  rotation_xyzw: [0, 0, 0, 1]\n  translation_m: [2, 8, -6]\n"));
  });
  EXPECT_NE(absurd.find(":3: camera_imu.translation_m: is the IMU's origin"), std::string::npos) << absurd;
  EXPECT_NE(absurd.find("longer than 1 m"), std::string::npos) << absurd;
}

}  // namespace
}  // namespace rig_model
