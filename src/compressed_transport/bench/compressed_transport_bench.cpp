// `make bench`: the compressed transport on a realistic frame. rig_sim renders the handheld scenario at
// the thesis camera's full 1024x768 with its image noise (sigma 2 DN, as a real sensor; a flat or
// noiseless image would flatter JPEG). Figures: bytes per frame and encode time at JPEG quality 80
// (the default), against the raw rgb8 frame (what crosses the network without this plugin) and
// its copy time; the same for PNG level 1 (lossless) for comparison. Goal: <= 2 MB/s at 30 Hz, encode
// <= 5 ms per frame.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include <time.h>

#include <opencv2/core.hpp>

#include "compressed_transport/core/codec.h"
#include "rig_sim/sim_stream.h"

namespace {
using Clock = std::chrono::steady_clock;

// This thread's CPU time (ms): what one encode costs a core, also while other processes load the machine
// (the wall time below then includes the waits for a core).
double ThreadCpuMs() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}
constexpr int kRuns = 40;
constexpr double kRateHz = 30.0;

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

cv::Mat RenderFrame() {
  rig_sim::Scenario scenario;
  std::string err;
  if (!rig_sim::MakeScenario("handheld", 1, RIG_MODEL_LAYOUTS_DIR, &scenario, &err)) {
    std::fprintf(stderr, "compressed_transport_bench: %s\n", err.c_str());
    std::exit(1);
  }
  const rig_sim::SimStream stream(scenario, rig_sim::StreamConfig());
  rig_sim::SimEvent ev;
  ev.kind = rig_sim::EventKind::kImage;
  ev.stamp_s = 5.0;  // in the handheld motion, cones in view
  ev.pose = stream.trajectory().At(ev.stamp_s);
  cv::Mat rgb(scenario.camera.model.height_px, scenario.camera.model.width_px, CV_8UC3);
  stream.RenderFrame(ev, rgb.data);
  return rgb;
}

void Run(const cv::Mat& rgb, const compressed_transport::EncodeConfig& config, const std::string& name) {
  const double raw_bytes = static_cast<double>(rgb.total() * rgb.elemSize());
  std::vector<double> encode_ms, encode_cpu_ms, copy_ms;
  compressed_transport::EncodedImage encoded;
  std::string error;
  for (int i = 0; i < kRuns; ++i) {
    const double c0 = ThreadCpuMs();
    const auto t0 = Clock::now();
    if (!compressed_transport::Encode(rgb, "rgb8", config, &encoded, &error)) {
      std::fprintf(stderr, "compressed_transport_bench: %s\n", error.c_str());
      std::exit(1);
    }
    const auto t1 = Clock::now();
    encode_cpu_ms.push_back(ThreadCpuMs() - c0);
    std::vector<uint8_t> raw(rgb.data, rgb.data + static_cast<size_t>(raw_bytes));  // the raw transport's copy
    const auto t2 = Clock::now();
    encode_ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    copy_ms.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
  }
  const double bytes = static_cast<double>(encoded.data.size());
  const double mb_s = bytes * kRateHz / 1e6, raw_mb_s = raw_bytes * kRateHz / 1e6;
  std::printf(
      "%s (%dx%d, format '%s'): %.0f bytes/frame vs raw %.0f (ratio %.4f); %.2f MB/s at 30 Hz vs raw %.1f "
      "MB/s; encode median %.2f ms CPU, %.2f ms wall vs raw copy %.2f ms (ratio %.1f)\n",
      name.c_str(), rgb.cols, rgb.rows, encoded.format.c_str(), bytes, raw_bytes, bytes / raw_bytes, mb_s, raw_mb_s,
      Median(encode_cpu_ms), Median(encode_ms), Median(copy_ms),
      Median(encode_cpu_ms) / std::max(Median(copy_ms), 1e-6));
  std::printf("BENCH compressed_transport.%s_bytes_per_frame %.0f bytes\n", name.c_str(), bytes);
  static bool raw_printed = false;  // the baseline's lines once, from the first run
  if (!raw_printed) std::printf("BENCH compressed_transport.raw_bytes_per_frame %.0f bytes\n", raw_bytes);
  std::printf("BENCH compressed_transport.%s_size_ratio %.4f ratio\n", name.c_str(), bytes / raw_bytes);
  std::printf("BENCH compressed_transport.%s_mb_s_at_30hz %.2f MB/s\n", name.c_str(), mb_s);
  std::printf("BENCH compressed_transport.%s_encode_cpu_median %.2f ms\n", name.c_str(), Median(encode_cpu_ms));
  std::printf("BENCH compressed_transport.%s_encode_wall_median %.2f ms\n", name.c_str(), Median(encode_ms));
  if (!raw_printed) std::printf("BENCH compressed_transport.raw_copy_median %.2f ms\n", Median(copy_ms));
  raw_printed = true;
}
}  // namespace

int main() {
  const cv::Mat rgb = RenderFrame();
  compressed_transport::EncodeConfig jpeg;  // defaults: JPEG quality 80
  Run(rgb, jpeg, "jpeg80");
  jpeg.jpeg_optimize = true;
  Run(rgb, jpeg, "jpeg80_optimize");
  jpeg.jpeg_optimize = false;
  jpeg.jpeg_quality = 75;  // the next step down, for the README's advice when the link is tight
  Run(rgb, jpeg, "jpeg75");
  compressed_transport::EncodeConfig png;
  png.codec = compressed_transport::Codec::kPng;
  png.png_level = 1;
  Run(rgb, png, "png1");
  return 0;
}
