#include <gtest/gtest.h>

#include "rig_sim/bag_checks.h"

namespace rig_sim {
namespace {

// A clean 3 s bag's worth of records: IMU at rest for the first second.
BagContents MakeClean() {
  BagContents b;
  const double t0 = 100.0;
  for (int k = 0; k < 300; ++k) {
    ImuRecord r;
    r.stamp_s = r.receive_s = t0 + 0.01 * k;
    r.accel_m_s2 = Eigen::Vector3d(0.3, 0.0, 9.805);
    r.gyro_rad_s = Eigen::Vector3d(0.004, -0.002, 0.001);
    r.frame = "imu";
    b.imu.push_back(r);
  }
  for (int k = 0; k < 900; ++k) {
    TruthRecord r;
    r.stamp_s = r.receive_s = t0 + k / 300.0;
    r.p = Eigen::Vector3d(2.0 + (k > 300 ? 0.001 * (k - 300) : 0.0), 0.0, 1.0);
    b.truth.push_back(r);
  }
  for (int k = 0; k < 90; ++k) {
    ImageRecord im;
    im.stamp_s = t0 + k / 30.0;
    im.receive_s = im.stamp_s + 0.04;
    im.width = 64, im.height = 48, im.step = 192, im.encoding = "rgb8", im.frame = "camera_optical";
    im.data_size = 192 * 48;
    b.images.push_back(im);
    InfoRecord info;
    info.stamp_s = im.stamp_s;
    info.receive_s = im.receive_s;
    info.width = 64, info.height = 48, info.frame = "camera_optical", info.distortion_model = "plumb_bob";
    info.d_size = 5, info.fx = 48, info.fy = 48;
    b.infos.push_back(info);
  }
  return b;
}

const Check* Find(const ValidationReport& r, const std::string& name) {
  for (const Check& c : r.checks)
    if (c.name == name) return &c;
  return nullptr;
}

}  // namespace

TEST(BagChecks, CleanRecordsPass) {
  const ValidationReport r = ValidateContents(MakeClean(), ValidateConfig());
  EXPECT_TRUE(r.ok()) << r.Text();
  EXPECT_NE(Find(r, "imu norms at rest")->message.find("1 rest stretch"), std::string::npos) << r.Text();
}

TEST(BagChecks, HalfSecondImuGapFailsWithAClearMessage) {
  BagContents b = MakeClean();
  b.imu.erase(b.imu.begin() + 150, b.imu.begin() + 200);  // 1.49 s .. 2.00 s
  const ValidationReport r = ValidateContents(b, ValidateConfig());
  EXPECT_FALSE(r.ok());
  const Check* gap = Find(r, "imu/data_raw gaps");
  ASSERT_NE(gap, nullptr);
  EXPECT_FALSE(gap->ok);
  EXPECT_NE(gap->message.find("gap of 0.510 s after t=1.490 s"), std::string::npos) << gap->message;
}

TEST(BagChecks, MismatchedCameraInfoAndWrongRateFail) {
  BagContents b = MakeClean();
  b.infos[10].width = 1024;
  ValidationReport r = ValidateContents(b, ValidateConfig());
  EXPECT_FALSE(Find(r, "camera_info matches images")->ok);
  EXPECT_NE(Find(r, "camera_info matches images")->message.find("t=0.333"), std::string::npos);
  b = MakeClean();
  b.infos.erase(b.infos.begin() + 5);
  EXPECT_NE(Find(ValidateContents(b, ValidateConfig()), "camera_info matches images")->message.find("no camera_info"),
            std::string::npos);
  ValidateConfig cfg;
  cfg.camera_rate_hz = 25.0;
  r = ValidateContents(MakeClean(), cfg);
  EXPECT_FALSE(Find(r, "camera/image_raw rate")->ok);
}

TEST(BagChecks, BackwardStampsBadRestNormsAndRep145Fail) {
  BagContents b = MakeClean();
  std::swap(b.imu[20].stamp_s, b.imu[21].stamp_s);
  EXPECT_FALSE(Find(ValidateContents(b, ValidateConfig()), "imu/data_raw monotonic stamps")->ok);
  b = MakeClean();
  for (auto& r : b.imu) r.accel_m_s2 *= 1.05;  // a scale error: 10.3 m/s^2 at rest
  const Check* rest = Find(ValidateContents(b, ValidateConfig()), "imu norms at rest");
  EXPECT_FALSE(rest->ok);
  EXPECT_NE(rest->message.find("|accel| 10.3"), std::string::npos) << rest->message;
  b = MakeClean();
  b.imu[3].orientation_covariance0 = 0.0;
  EXPECT_FALSE(Find(ValidateContents(b, ValidateConfig()), "imu REP-145 fields")->ok);
  b = MakeClean();
  b.images[7].receive_s = b.images[7].stamp_s - 0.5;  // delivered before exposure
  EXPECT_FALSE(Find(ValidateContents(b, ValidateConfig()), "camera/image_raw latency")->ok);
}

TEST(BagChecks, RestFromTheImuWhenThereIsNoTruthAndEmptyTopicsFail) {
  BagContents b = MakeClean();
  b.truth.clear();
  ValidationReport r = ValidateContents(b, ValidateConfig());
  EXPECT_TRUE(r.ok()) << r.Text();
  EXPECT_NE(Find(r, "imu norms at rest")->message.find("samples"), std::string::npos);
  b.imu.clear();
  r = ValidateContents(b, ValidateConfig());
  EXPECT_FALSE(r.ok());
  EXPECT_FALSE(Find(r, "imu/data_raw present")->ok);
}

}  // namespace rig_sim
