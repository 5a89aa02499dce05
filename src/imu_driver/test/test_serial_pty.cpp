#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <chrono>
#include <mutex>
#include <random>

#include "imu_driver/core/serial_reader.h"
#include "imu_driver/testing/packet_gen.h"
#include "imu_driver/testing/pty_writer.h"

namespace imu_driver {
namespace {

double WallNow() { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); }

class PtyDriverTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/imu_driver_pty_XXXXXX";
    ASSERT_NE(::mkdtemp(tmpl), nullptr);
    dir_ = tmpl;
    config_.port = dir_ + "/imu";
    config_.retry_initial_s = 0.02;
    config_.retry_max_s = 0.1;
  }
  void TearDown() override {
    reader_.reset();
    ::unlink(config_.port.c_str());
    ::rmdir(dir_.c_str());
  }
  void StartReader() {
    reader_ = std::make_unique<SerialReader>(
        config_, WallNow,
        [this](const ImuSample& s) {
          std::lock_guard<std::mutex> l(mutex_);
          samples_.push_back(s);
        },
        [this](int level, const std::string& m) {
          std::lock_guard<std::mutex> l(mutex_);
          logs_.emplace_back(level, m);
        });
    reader_->Start();
  }
  size_t NumSamples() {
    std::lock_guard<std::mutex> l(mutex_);
    return samples_.size();
  }
  void ExpectSamples(size_t first, const std::vector<HighSpeedRaw>& want) {
    std::lock_guard<std::mutex> l(mutex_);
    ASSERT_GE(samples_.size(), first + want.size());
    for (size_t i = 0; i < want.size(); ++i) {
      const ImuSampleSi w = ToSi(want[i]);
      ASSERT_EQ(samples_[first + i].si.omega_imu_rad_s, w.omega_imu_rad_s) << i;
      ASSERT_EQ(samples_[first + i].si.accel_imu_m_s2, w.accel_imu_m_s2) << i;
      ASSERT_EQ(samples_[first + i].si.sequence, w.sequence) << i;
    }
  }

  std::string dir_;
  SerialReaderConfig config_;
  std::unique_ptr<SerialReader> reader_;
  std::mutex mutex_;
  std::vector<ImuSample> samples_;
  std::vector<std::pair<int, std::string>> logs_;
};

TEST_F(PtyDriverTest, MissingPortRetriesThenFuzzedStreamIsDecodedExactly) {
  StartReader();
  ASSERT_TRUE(test::WaitFor([&] { return reader_->status().open_failures >= 3; }));
  EXPECT_FALSE(reader_->status().connected);
  EXPECT_NE(reader_->status().last_error.find(config_.port), std::string::npos);
  {
    std::lock_guard<std::mutex> l(mutex_);
    ASSERT_FALSE(logs_.empty());
    EXPECT_EQ(logs_[0].first, 2);  // an error, naming the port
    EXPECT_NE(logs_[0].second.find("cannot open"), std::string::npos);
  }
  test::PtyWriter imu(config_.port);
  imu.Plug();
  ASSERT_TRUE(test::WaitFor([&] { return reader_->status().connected; }));

  std::mt19937 rng(21);
  const test::ScriptedStream s = test::MakeScriptedStream(rng, 300);
  imu.WritePaced(s.bytes);
  // The counts are published after each read, the samples within it: wait for both (every byte parsed).
  ASSERT_TRUE(test::WaitFor(
      [&] { return NumSamples() >= s.valid.size() && reader_->status().parser.bytes_in == s.bytes.size(); }));
  ExpectSamples(0, s.valid);
  const SerialReaderStatus st = reader_->status();
  EXPECT_EQ(st.parser.bad_crc, s.expected.bad_crc);
  EXPECT_EQ(st.parser.bad_length, s.expected.bad_length);
  EXPECT_EQ(st.parser.unknown_type, s.expected.unknown_type);
  EXPECT_EQ(st.parser.truncated, s.expected.truncated);
  EXPECT_EQ(st.parser.garbage_bytes, s.expected.garbage_bytes);
  EXPECT_EQ(st.stream.samples, s.valid.size());
  EXPECT_GT(st.stream.sequence_gaps, 0u);
  EXPECT_TRUE(st.last_error.empty());
}

TEST_F(PtyDriverTest, RandomBytesBetweenAndInsideFramesAt100Hz) {
  test::PtyWriter imu(config_.port);
  imu.Plug();
  StartReader();
  ASSERT_TRUE(test::WaitFor([&] { return reader_->status().connected; }));
  std::mt19937 rng(23);
  const test::RandomStream s = test::MakeRandomStream(rng, 300);
  imu.WritePaced(s.bytes, s.bytes.size() / 300 + 1);  // about one frame and its noise every 10 ms
  ASSERT_TRUE(test::WaitFor([&] { return reader_->status().parser.bytes_in == s.bytes.size(); }));
  imu.Unplug();  // the stream ends: whatever is pending is resolved
  ASSERT_TRUE(test::WaitFor([&] { return reader_->status().disconnects == 1; }));
  EXPECT_EQ(NumSamples(), s.valid.size());
  ExpectSamples(0, s.valid);
  const ParserCounts p = reader_->status().parser;
  EXPECT_EQ(p.bytes_accepted + p.garbage_bytes, p.bytes_in);
  EXPECT_GT(p.bad_crc + p.bad_length + p.truncated, 10u);
}

TEST_F(PtyDriverTest, UnplugAndReplugRecoversWithoutRestart) {
  test::PtyWriter imu(config_.port);
  imu.Plug();
  StartReader();
  ASSERT_TRUE(test::WaitFor([&] { return reader_->status().connected; }));
  std::mt19937 rng(22);
  std::vector<uint8_t> bytes;
  std::vector<HighSpeedRaw> before, after;
  for (int k = 0; k < 50; ++k) {
    std::vector<uint8_t> f;
    before.push_back(test::RandomFrame(rng, static_cast<uint8_t>(k), false, &f));
    bytes.insert(bytes.end(), f.begin(), f.end());
  }
  imu.WritePaced(bytes, 24);
  ASSERT_TRUE(test::WaitFor([&] { return NumSamples() >= before.size(); }));
  // Unplugged in the middle of a frame: the half frame is counted as truncated.
  imu.Write(bytes.data(), 10);
  ASSERT_TRUE(test::WaitFor([&] { return reader_->status().parser.bytes_in == bytes.size() + 10; }));
  imu.Unplug();
  ASSERT_TRUE(test::WaitFor([&] { return reader_->status().disconnects == 1; }));
  EXPECT_FALSE(reader_->status().connected);
  EXPECT_EQ(reader_->status().parser.truncated, 1u);
  imu.Plug();
  ASSERT_TRUE(test::WaitFor([&] { return reader_->status().connects == 2; }));
  bytes.clear();
  for (int k = 0; k < 50; ++k) {
    std::vector<uint8_t> f;
    after.push_back(test::RandomFrame(rng, static_cast<uint8_t>(k), false, &f));
    bytes.insert(bytes.end(), f.begin(), f.end());
  }
  imu.WritePaced(bytes, 24);
  ASSERT_TRUE(test::WaitFor([&] { return NumSamples() >= before.size() + after.size(); }));
  ExpectSamples(0, before);
  ExpectSamples(before.size(), after);
  EXPECT_EQ(NumSamples(), before.size() + after.size());
  // Stamps keep increasing across the reconnect.
  std::lock_guard<std::mutex> l(mutex_);
  for (size_t i = 1; i < samples_.size(); ++i) EXPECT_GT(samples_[i].stamp_s, samples_[i - 1].stamp_s) << i;
}

TEST_F(PtyDriverTest, RequestsConfigurationOnConnectAndChecksTheReply) {
  test::PtyWriter imu(config_.port);
  imu.Plug();
  StartReader();
  std::vector<uint8_t> got;
  ASSERT_TRUE(test::WaitFor([&] {
    uint8_t b[64];
    const size_t n = imu.Read(b, sizeof b, 10);
    got.insert(got.end(), b, b + n);
    return got.size() >= 6;
  }));
  EXPECT_EQ(got, EncodeConfigRequest());
  // The IMU answers: configured for 50 Hz, not the 100 Hz the driver assumes.
  const auto settings = EncodeSettingsPayload(50.0, 20);
  const auto res = EncodeResolutionPayload(300.0f, 10.0f);
  auto reply = EncodeFrame(static_cast<uint8_t>(MsgType::kSettings), settings.data(), settings.size());
  const auto r2 = EncodeFrame(static_cast<uint8_t>(MsgType::kResolution), res.data(), res.size());
  reply.insert(reply.end(), r2.begin(), r2.end());
  imu.Write(reply.data(), reply.size());
  ASSERT_TRUE(test::WaitFor([&] { return reader_->status().stream.device.have_resolution; }));
  EXPECT_DOUBLE_EQ(reader_->status().stream.device.output_rate_hz, 50.0);
  EXPECT_DOUBLE_EQ(reader_->status().stream.device.gyro_range_deg_s, 300.0);
  ASSERT_TRUE(test::WaitFor([&] {
    std::lock_guard<std::mutex> l(mutex_);
    for (const auto& [level, m] : logs_) {
      if (level == 2 && m.find("50 Hz") != std::string::npos) return true;
    }
    return false;
  }));
}

TEST(SerialPort, RefusesUnsupportedBaudAndNonTty) {
  SerialPort p;
  std::string err;
  EXPECT_FALSE(p.Open("/dev/null", 12345, &err));
  EXPECT_NE(err.find("baud"), std::string::npos);
  EXPECT_FALSE(p.Open("/dev/null", 115200, &err));
  EXPECT_NE(err.find("not a serial device"), std::string::npos);
  EXPECT_FALSE(p.Open("/nonexistent/tty", 115200, &err));
  EXPECT_NE(err.find("/nonexistent/tty"), std::string::npos);
}

TEST(SerialPort, SecondReaderOfTheSamePortIsRefused) {
  char tmpl[] = "/tmp/imu_driver_lock_XXXXXX";
  ASSERT_NE(::mkdtemp(tmpl), nullptr);
  const std::string link = std::string(tmpl) + "/imu";
  {
    PseudoTerminal pty(link);
    pty.Plug();
    SerialPort a, b;
    std::string err;
    ASSERT_TRUE(a.Open(link, 115200, &err)) << err;
    EXPECT_FALSE(b.Open(link, 115200, &err));
    EXPECT_NE(err.find("in use"), std::string::npos) << err;
    a.Close();
    EXPECT_TRUE(b.Open(link, 115200, &err)) << err;
    pty.Unplug();
    EXPECT_FALSE(::access(link.c_str(), F_OK) == 0);  // unplugging removes the link
  }
  ::rmdir(tmpl);
}

}  // namespace
}  // namespace imu_driver
