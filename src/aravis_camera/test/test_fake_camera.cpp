// The driver core against arv-fake-gv-camera-0.8 on loopback: rate, size and
// encoding, zero copy, lost packets, reconnection, absence at start and a
// subscriber that holds every buffer.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include "aravis_camera/device/camera_device.h"
#include "aravis_camera/testing/fake_camera.h"

namespace aravis_camera {
namespace {

using namespace std::chrono_literals;
using test::FakeCamera;

// Collects what the device hands out; optionally keeps the frames.
struct Collector {
  std::mutex mutex;
  std::condition_variable cv;
  std::vector<FrameInfo> frames;
  std::vector<sensor_msgs::ImagePtr> held;
  std::vector<std::string> log;
  sensor_msgs::ImagePtr last_header_only;  // header fields of the latest frame
  std::string encoding;
  uint32_t width = 0, height = 0, step = 0;
  size_t data_size = 0;
  bool all_zero_copy = true;
  size_t hold = 0;  // keep this many frames

  void OnFrame(const sensor_msgs::ImagePtr& image, const FrameInfo& info) {
    std::lock_guard<std::mutex> lock(mutex);
    frames.push_back(info);
    encoding = image->encoding;
    width = image->width;
    height = image->height;
    step = image->step;
    data_size = image->data.size();
    all_zero_copy = all_zero_copy && FramePool::IsPoolMemory(image->data.data());
    if (held.size() < hold) held.push_back(image);
    cv.notify_all();
  }
  void OnLog(LogLevel, const std::string& msg) {
    std::lock_guard<std::mutex> lock(mutex);
    log.push_back(msg);
  }
  // Waits until `n` frames in all have arrived; false on timeout.
  bool WaitFrames(size_t n, std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex);
    return cv.wait_for(lock, timeout, [&] { return frames.size() >= n; });
  }
  size_t Count() {
    std::lock_guard<std::mutex> lock(mutex);
    return frames.size();
  }
  std::string Log() {
    std::lock_guard<std::mutex> lock(mutex);
    std::string all;
    for (const auto& l : log) all += l + "\n";
    return all;
  }
  bool Logged(const std::string& needle) {
    std::lock_guard<std::mutex> lock(mutex);
    for (const auto& l : log) {
      if (l.find(needle) != std::string::npos) return true;
    }
    return false;
  }
};

CameraConfig TestConfig(const std::string& format) {
  CameraConfig c;
  c.camera_name = test::kFakeCameraAddress;
  c.pixel_format = format;
  c.width_px = 1024;
  c.height_px = 768;
  c.frame_rate_hz = 30.0;
  c.reconnect_period_s = 0.2;
  c.frame_timeout_s = 1.0;
  return c;
}

std::unique_ptr<CameraDevice> MakeDevice(const CameraConfig& c, Collector* col) {
  return std::make_unique<CameraDevice>(
      c, [col](const sensor_msgs::ImagePtr& i, const FrameInfo& f) { col->OnFrame(i, f); },
      [col](LogLevel l, const std::string& m) { col->OnLog(l, m); });
}

// 12 Hz rather than the rig's 30: the fake camera draws its frames in
// software and falls behind on a saturated machine; the point is that the
// configured rate is applied, not the fake's top speed.
TEST(FakeCamera, FramesArriveAtTheConfiguredRateWithSizeAndEncoding) {
  FakeCamera fake;
  Collector col;
  CameraConfig c = TestConfig("BayerRG8");
  c.frame_rate_hz = 12.0;
  auto device = MakeDevice(c, &col);
  device->Start();
  ASSERT_TRUE(col.WaitFrames(40, 60s)) << "frames: " << col.Count();
  device->Stop();
  EXPECT_EQ(col.encoding, "bayer_rggb8");
  EXPECT_EQ(col.width, 1024u);
  EXPECT_EQ(col.height, 768u);
  EXPECT_EQ(col.step, 1024u);
  EXPECT_EQ(col.data_size, 1024u * 768u);
  // Rate over the last 30 frames, from the host completion times.
  const auto& f = col.frames;
  const double span_s = (f[39].completion_ns - f[9].completion_ns) * 1e-9;
  EXPECT_NEAR(30.0 / span_s, 12.0, 1.0);
  // Stamps increase and are on the host clock.
  for (size_t k = 10; k < 40; ++k) EXPECT_GT(f[k].stamp_ns, f[k - 1].stamp_ns);
  EXPECT_NEAR((f[39].stamp_ns - f[39].completion_ns) * 1e-9, 0.0, 0.5);
}

// Waits until `pred` holds, polling; false after `timeout`.
template <typename Pred>
bool Eventually(Pred pred, std::chrono::milliseconds timeout) {
  const auto until = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < until) {
    if (pred()) return true;
    std::this_thread::sleep_for(20ms);
  }
  return pred();
}

// Discovery: Aravis's in-process fake camera is listed like a networked one.
TEST(FakeCamera, OpensTheFirstCameraFoundOrOneBySerialNumber) {
  for (const std::string name : {"", "1"}) {  // the first camera found; serial number 1
    Collector col;
    CameraConfig c = TestConfig("Mono8");
    c.camera_name = name;
    c.enable_fake_interface = true;
    c.width_px = c.height_px = 0;
    auto device = MakeDevice(c, &col);
    device->Start();
    ASSERT_TRUE(col.WaitFrames(3, 60s)) << "camera_name '" << name << "': " << col.Log();
    EXPECT_TRUE(device->stats().connected);
    device->Stop();
  }
  Collector col;
  CameraConfig c = TestConfig("Mono8");
  c.camera_name = "NO-SUCH-SERIAL";
  c.enable_fake_interface = true;
  auto device = MakeDevice(c, &col);
  device->Start();
  // Until it has looked for the camera and failed twice (a condition, not a second of wall time).
  ASSERT_TRUE(Eventually([&] { return device->stats().open_failures >= 2; }, 60s));
  EXPECT_EQ(col.Count(), 0u);
  EXPECT_FALSE(device->stats().connected);
  device->Stop();
}

TEST(FakeCamera, EachPixelFormatHasItsEncoding) {
  FakeCamera fake;
  for (const auto& [format, encoding, bpp] :
       std::vector<std::tuple<std::string, std::string, uint32_t>>{{"RGB8", "rgb8", 3}, {"Mono8", "mono8", 1}}) {
    Collector col;
    auto device = MakeDevice(TestConfig(format), &col);
    device->Start();
    ASSERT_TRUE(col.WaitFrames(3, 60s)) << format;
    device->Stop();
    EXPECT_EQ(col.encoding, encoding);
    EXPECT_EQ(col.step, 1024u * bpp);
    EXPECT_EQ(col.data_size, 1024u * 768u * bpp);
  }
}

TEST(FakeCamera, FramesAreThePoolsMemoryAndComeBack) {
  FakeCamera fake;
  Collector col;
  CameraConfig c = TestConfig("BayerRG8");
  c.n_buffers = 4;  // 30 frames through 4 buffers: each must come back to the stream
  auto device = MakeDevice(c, &col);
  device->Start();
  ASSERT_TRUE(col.WaitFrames(30, 60s));
  device->Stop();
  EXPECT_TRUE(col.all_zero_copy);
}

// 2 lost packets per thousand: with 560 packets a frame, about a third of the
// frames arrive whole. The rest are counted and dropped (or published, on request).
TEST(FakeCamera, LostPacketsAreCountedAndStreamingGoesOn) {
  FakeCamera fake(/*lost_packets_per_thousand=*/2);
  for (bool publish_incomplete : {false, true}) {
    Collector col;
    CameraConfig c = TestConfig("BayerRG8");
    c.publish_incomplete = publish_incomplete;
    auto device = MakeDevice(c, &col);
    device->Start();
    ASSERT_TRUE(col.WaitFrames(20, 60s)) << "frames: " << col.Count();
    ASSERT_TRUE(Eventually([&] { return device->stats().missing_packets > 0; }, 60s));
    const DeviceStats s = device->stats();
    device->Stop();
    EXPECT_TRUE(s.connected);
    EXPECT_EQ(s.reconnects, 0u);
    EXPECT_GT(s.frames_incomplete, 0u);
    if (publish_incomplete) {
      EXPECT_EQ(s.frames_dropped, 0u);
      std::lock_guard<std::mutex> lock(col.mutex);
      EXPECT_TRUE(std::any_of(col.frames.begin(), col.frames.end(), [](const FrameInfo& f) { return !f.complete; }));
    } else {
      EXPECT_EQ(s.frames_dropped, s.frames_incomplete);
      std::lock_guard<std::mutex> lock(col.mutex);
      EXPECT_TRUE(std::all_of(col.frames.begin(), col.frames.end(), [](const FrameInfo& f) { return f.complete; }));
    }
  }
}

TEST(FakeCamera, ReconnectsAfterTheCameraIsKilledAndRestarted) {
  FakeCamera fake;
  Collector col;
  auto device = MakeDevice(TestConfig("BayerRG8"), &col);
  device->Start();
  ASSERT_TRUE(col.WaitFrames(10, 60s));
  fake.Kill();
  ASSERT_TRUE(Eventually([&] { return !device->stats().connected; }, 60s));  // no frame for frame_timeout_s
  const size_t before = col.Count();
  const auto restart = std::chrono::steady_clock::now();
  fake.Start();
  ASSERT_TRUE(col.WaitFrames(before + 5, 60s)) << "no frames after the restart; log:\n" << col.Log();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - restart).count();
  RecordProperty("reconnect_s", std::to_string(seconds));
  EXPECT_TRUE(col.Logged("reconnecting"));
  EXPECT_TRUE(col.Logged("reconnected"));
  EXPECT_GE(device->stats().reconnects, 1u);
  device->Stop();
}

TEST(FakeCamera, AbsentAtStartIsRetriedAndReported) {
  Collector col;
  auto device = MakeDevice(TestConfig("BayerRG8"), &col);
  device->Start();
  ASSERT_TRUE(Eventually([&] { return device->stats().open_failures >= 2; }, 60s));
  DeviceStats s = device->stats();
  EXPECT_FALSE(s.connected);
  EXPECT_FALSE(s.last_error.empty());
  EXPECT_TRUE(col.Logged("cannot open camera"));
  FakeCamera fake;
  ASSERT_TRUE(col.WaitFrames(5, 60s));
  EXPECT_TRUE(device->stats().connected);
  device->Stop();
}

TEST(FakeCamera, SubscriberHoldingEveryBufferCausesCountedUnderruns) {
  FakeCamera fake;
  Collector col;
  col.hold = 4;
  CameraConfig c = TestConfig("BayerRG8");
  c.n_buffers = 4;
  c.frame_timeout_s = 5.0;  // starved on purpose: not a lost camera
  auto device = MakeDevice(c, &col);
  device->Start();
  ASSERT_TRUE(col.WaitFrames(4, 60s));
  // Until the camera has offered frames the full pool could not take (a condition, not a wall time).
  ASSERT_TRUE(Eventually([&] { return device->stats().underruns >= 3; }, 60s));
  EXPECT_EQ(col.Count(), 4u);  // nothing more while the pool is held
  EXPECT_GT(device->stats().underruns, 0u);
  EXPECT_EQ(device->stats().frames_in_flight, 4);
  {
    std::lock_guard<std::mutex> lock(col.mutex);
    col.hold = 0;
    col.held.clear();  // the subscriber lets go
  }
  ASSERT_TRUE(col.WaitFrames(20, 60s)) << "frames " << col.Count() << ", in flight " << device->stats().frames_in_flight
                                       << ", underruns " << device->stats().underruns << "; log:\n"
                                       << col.Log();
  device->Stop();
}

}  // namespace
}  // namespace aravis_camera

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  const int lock_fd = aravis_camera::test::LockFakeCameraPort();  // held until exit
  const int result = RUN_ALL_TESTS();
  if (lock_fd >= 0) close(lock_fd);
  return result;
}
