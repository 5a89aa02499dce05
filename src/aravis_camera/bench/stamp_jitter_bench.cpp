// Timestamp jitter of each stamp source on arv-fake-gv-camera-0.8 at 30 Hz:
// the standard deviation of the frame-to-frame stamp interval. The driver's
// default (the camera's timestamp mapped to the host clock) is compared with
// the host clock at the first packet and at frame completion.
#include <cmath>
#include <cstdio>
#include <mutex>
#include <thread>
#include <vector>

#include "aravis_camera/device/camera_device.h"
#include "aravis_camera/testing/fake_camera.h"

namespace {

double IntervalStdDevMs(const std::vector<int64_t>& stamps_ns) {
  std::vector<double> d;
  for (size_t k = 1; k < stamps_ns.size(); ++k) d.push_back((stamps_ns[k] - stamps_ns[k - 1]) * 1e-6);
  double mean = 0.0, var = 0.0;
  for (double x : d) mean += x / d.size();
  for (double x : d) var += (x - mean) * (x - mean) / (d.size() - 1);
  return std::sqrt(var);
}

}  // namespace

int main() {
  using namespace aravis_camera;
  const int lock = test::LockFakeCameraPort();
  test::FakeCamera fake;
  std::mutex mutex;
  std::vector<int64_t> device, host, completion;
  CameraConfig c;
  c.camera_name = test::kFakeCameraAddress;
  c.width_px = 1024;
  c.height_px = 768;
  c.frame_rate_hz = 30.0;
  CameraDevice camera(
      c,
      [&](const sensor_msgs::ImagePtr&, const FrameInfo& f) {
        std::lock_guard<std::mutex> l(mutex);
        device.push_back(f.stamp_ns);
        host.push_back(f.host_ns);
        completion.push_back(f.completion_ns);
      },
      nullptr);
  camera.Start();
  std::this_thread::sleep_for(std::chrono::seconds(12));
  camera.Stop();
  if (lock >= 0) close(lock);
  std::lock_guard<std::mutex> l(mutex);
  if (device.size() < 200) {
    std::fprintf(stderr, "stamp_jitter_bench: only %zu frames from the fake camera\n", device.size());
    return 1;
  }
  // The first two seconds fill the mapper's window; leave them out.
  const auto tail = [](const std::vector<int64_t>& v) { return std::vector<int64_t>(v.begin() + 60, v.end()); };
  const double dev = IntervalStdDevMs(tail(device)), hst = IntervalStdDevMs(tail(host)),
               cmp = IntervalStdDevMs(tail(completion));
  std::printf("frame interval std dev over %zu frames at 30 Hz (1024x768 BayerRG8, fake GigE camera)\n",
              device.size() - 60);
  std::printf("  device stamp mapped to host (default) %.4f ms\n", dev);
  std::printf("  host clock at first packet            %.4f ms\n", hst);
  std::printf("  host clock at frame completion        %.4f ms\n", cmp);
  std::printf(
      "  (the fake camera stamps frames from a software timer, so its own scheduling jitter is in\n"
      "   every column; a real camera latches the timestamp in hardware)\n");
  std::printf("BENCH aravis_camera.stamp_jitter_device %.4f ms\n", dev);
  std::printf("BENCH aravis_camera.stamp_jitter_host %.4f ms\n", hst);
  std::printf("BENCH aravis_camera.stamp_jitter_completion %.4f ms\n", cmp);
  std::printf("BENCH aravis_camera.stamp_jitter_ratio %.3f x\n", dev / hst);
  return 0;
}
