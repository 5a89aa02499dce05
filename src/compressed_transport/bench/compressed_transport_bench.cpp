// `make bench`: the compressed transport on realistic frames. rig_sim renders the handheld scenario at
// the thesis camera's full 1024x768 with its image noise (sigma 2 DN, as a real sensor; a flat or
// noiseless image would flatter JPEG), one frame every 3 s of the 60 s walk: the bandwidth is the mean
// size over the walk, and one frame would not say it (a single frame's size varies by +-10 % with the
// view). Figures: mean and largest bytes per frame and the median encode time at the default settings
// (JPEG quality 80, optimised Huffman tables), against the raw rgb8 frame (what crosses the network
// without this plugin) and its copy time; the same for upstream's default (no optimisation), quality
// 75, and PNG level 1 (lossless) for comparison. Goal: <= 2 MB/s at 30 Hz, encode <= 5 ms per frame.
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
constexpr int kRunsPerFrame = 4;
constexpr double kRateHz = 30.0;

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// The frames of the walk, one every `step_s`.
std::vector<cv::Mat> RenderWalk(double step_s) {
  rig_sim::Scenario scenario;
  std::string err;
  if (!rig_sim::MakeScenario("handheld", 1, RIG_MODEL_LAYOUTS_DIR, &scenario, &err)) {
    std::fprintf(stderr, "compressed_transport_bench: %s\n", err.c_str());
    std::exit(1);
  }
  const rig_sim::SimStream stream(scenario, rig_sim::StreamConfig());
  std::vector<cv::Mat> frames;
  for (double t = 1.0; t < scenario.trajectory.duration_s; t += step_s) {
    cv::Mat rgb(scenario.camera.model.height_px, scenario.camera.model.width_px, CV_8UC3);
    stream.RenderFrame(stream.ImageEventAt(t), rgb.data);
    frames.push_back(rgb);
  }
  return frames;
}

// Encodes every frame kRunsPerFrame times. Bytes: mean and largest over the frames; times: medians over
// all encodes.
void Run(const std::vector<cv::Mat>& frames, const compressed_transport::EncodeConfig& config,
         const std::string& name) {
  const cv::Mat& first = frames.front();
  const double raw_bytes = static_cast<double>(first.total() * first.elemSize());
  std::vector<double> encode_ms, encode_cpu_ms, copy_ms;
  double sum_bytes = 0.0, max_bytes = 0.0;
  compressed_transport::EncodedImage encoded;
  std::string error;
  for (const cv::Mat& rgb : frames) {
    for (int i = 0; i < kRunsPerFrame; ++i) {
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
    sum_bytes += static_cast<double>(encoded.data.size());
    max_bytes = std::max(max_bytes, static_cast<double>(encoded.data.size()));
  }
  const double bytes = sum_bytes / static_cast<double>(frames.size());
  const double mb_s = bytes * kRateHz / 1e6, max_mb_s = max_bytes * kRateHz / 1e6, raw_mb_s = raw_bytes * kRateHz / 1e6;
  std::printf(
      "%s (%dx%d, %zu frames, format '%s'): mean %.0f bytes/frame (largest %.0f) vs raw %.0f (ratio %.4f); %.2f "
      "MB/s at 30 Hz (largest frame %.2f) vs raw %.1f MB/s; encode median %.2f ms CPU, %.2f ms wall vs raw copy "
      "%.2f ms (ratio %.1f)\n",
      name.c_str(), first.cols, first.rows, frames.size(), encoded.format.c_str(), bytes, max_bytes, raw_bytes,
      bytes / raw_bytes, mb_s, max_mb_s, raw_mb_s, Median(encode_cpu_ms), Median(encode_ms), Median(copy_ms),
      Median(encode_cpu_ms) / std::max(Median(copy_ms), 1e-6));
  std::printf("BENCH compressed_transport.%s_bytes_per_frame %.0f bytes\n", name.c_str(), bytes);
  static bool raw_printed = false;  // the baseline's lines once, from the first run
  if (!raw_printed) std::printf("BENCH compressed_transport.raw_bytes_per_frame %.0f bytes\n", raw_bytes);
  std::printf("BENCH compressed_transport.%s_size_ratio %.4f ratio\n", name.c_str(), bytes / raw_bytes);
  std::printf("BENCH compressed_transport.%s_mb_s_at_30hz %.2f MB/s\n", name.c_str(), mb_s);
  std::printf("BENCH compressed_transport.%s_largest_frame_mb_s_at_30hz %.2f MB/s\n", name.c_str(), max_mb_s);
  std::printf("BENCH compressed_transport.%s_encode_cpu_median %.2f ms\n", name.c_str(), Median(encode_cpu_ms));
  std::printf("BENCH compressed_transport.%s_encode_wall_median %.2f ms\n", name.c_str(), Median(encode_ms));
  if (!raw_printed) std::printf("BENCH compressed_transport.raw_copy_median %.2f ms\n", Median(copy_ms));
  raw_printed = true;
}
}  // namespace

int main() {
  const std::vector<cv::Mat> frames = RenderWalk(3.0);
  compressed_transport::EncodeConfig jpeg;  // the defaults: JPEG quality 80, optimised Huffman tables
  Run(frames, jpeg, "jpeg80");
  jpeg.jpeg_optimize = false;  // upstream's default
  Run(frames, jpeg, "jpeg80_no_optimize");
  jpeg.jpeg_optimize = true;
  jpeg.jpeg_quality = 75;  // the next step down, for the README's advice when the link is tight
  Run(frames, jpeg, "jpeg75");
  compressed_transport::EncodeConfig png;
  png.codec = compressed_transport::Codec::kPng;
  png.png_level = 1;
  Run(std::vector<cv::Mat>(frames.begin(), frames.begin() + 3), png, "png1");  // slow; three frames say enough
  return 0;
}
