// imu_driver_bench: parser throughput against a naive baseline on the same
// bytes, clock-model jitter on synthetic arrivals, and the latency from the
// last byte of a frame written to a pty to the sample callback.
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <random>
#include <vector>

#include <boost/make_shared.hpp>

#include "imu_driver/core/calibration_session.h"
#include "imu_driver/core/crista_parser.h"
#include "imu_driver/core/serial_reader.h"
#include "imu_driver/node/ros_adapter.h"
#include "imu_driver/testing/jitter_sim.h"
#include "imu_driver/testing/packet_gen.h"
#include "imu_driver/testing/pty_writer.h"

namespace imu_driver {
namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

// The usual first attempt: a growing vector, std::search for the sync, a
// bitwise CRC, and erase() from the front after every frame.
class NaiveParser {
 public:
  size_t frames = 0;
  void Feed(const uint8_t* d, size_t n) {
    buf_.insert(buf_.end(), d, d + n);
    const uint8_t sync[2] = {kSync0, kSync1};
    for (;;) {
      auto it = std::search(buf_.begin(), buf_.end(), sync, sync + 2);
      buf_.erase(buf_.begin(), it);
      if (buf_.size() < kHeaderBytes) return;
      const size_t len = buf_[3];
      const TypeInfo info = LookupType(buf_[2]);
      if (len > kMaxPayloadBytes || (info.payload_bytes && len != info.payload_bytes)) {
        buf_.erase(buf_.begin());
        continue;
      }
      const size_t frame = kHeaderBytes + len + kCrcBytes;
      if (buf_.size() < frame) return;
      uint16_t crc = 0;
      for (size_t i = 0; i < kHeaderBytes + len; ++i) {
        crc ^= buf_[i];
        for (int b = 0; b < 8; ++b) crc = (crc & 1) ? static_cast<uint16_t>((crc >> 1) ^ 0xA001) : (crc >> 1);
      }
      if (crc != ((buf_[frame - 2] << 8) | buf_[frame - 1])) {
        buf_.erase(buf_.begin());
        continue;
      }
      if (info.known) {
        DecodeHighSpeedPayload(&buf_[kHeaderBytes]);
        ++frames;
      }
      buf_.erase(buf_.begin(), buf_.begin() + static_cast<std::ptrdiff_t>(frame));
    }
  }

 private:
  std::vector<uint8_t> buf_;
};

template <class Feed>
double BestSeconds(const std::vector<uint8_t>& bytes, size_t chunk, int runs, Feed feed) {
  double best = 1e9;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = Clock::now();
    feed(bytes, chunk);
    best = std::min(best, Seconds(t0, Clock::now()));
  }
  return best;
}

void BenchParser() {
  std::mt19937 rng(1);
  std::vector<uint8_t> bytes;
  size_t frames = 0;
  while (bytes.size() < 32u << 20) {
    const test::ScriptedStream s = test::MakeScriptedStream(rng, 2000);
    bytes.insert(bytes.end(), s.bytes.begin(), s.bytes.end());
    frames += s.valid.size();
  }
  const double mb = bytes.size() / 1e6;
  const size_t chunk = 4096;
  size_t ours_frames = 0, naive_frames = 0;
  const double ours_s = BestSeconds(bytes, chunk, 3, [&](const std::vector<uint8_t>& b, size_t c) {
    size_t n = 0;
    CristaParser p([&n](const FrameView& f) {
      DecodeHighSpeedPayload(f.payload);
      ++n;
    });
    for (size_t i = 0; i < b.size(); i += c) p.Feed(&b[i], std::min(c, b.size() - i));
    ours_frames = n;
  });
  const double naive_s = BestSeconds(bytes, chunk, 3, [&](const std::vector<uint8_t>& b, size_t c) {
    NaiveParser p;
    for (size_t i = 0; i < b.size(); i += c) p.Feed(&b[i], std::min(c, b.size() - i));
    naive_frames = p.frames;
  });
  std::printf("parser: %.1f MB of fuzzed stream, %zu valid frames (ours found %zu, baseline %zu), %zu-byte reads\n", mb,
              frames, ours_frames, naive_frames, chunk);
  std::printf("BENCH imu_driver.parser_throughput %.1f MB/s\n", mb / ours_s);
  std::printf("BENCH imu_driver.parser_packets %.3g packets/s\n", ours_frames / ours_s);
  std::printf("BENCH imu_driver.baseline_parser_throughput %.1f MB/s\n", mb / naive_s);
  std::printf("BENCH imu_driver.baseline_parser_packets %.3g packets/s\n", naive_frames / naive_s);
  std::printf("BENCH imu_driver.parser_speedup %.2f x\n", naive_s / ours_s);
  // The baseline drops a frame whenever its sync pair is split across two reads.
  std::printf("BENCH imu_driver.baseline_frames_lost %zu frames\n", frames - naive_frames);
  std::printf("BENCH imu_driver.parser_frames_lost %zu frames\n", frames - ours_frames);
  std::printf("parser: 100 Hz x 24 B = 2.4 kB/s on the wire; the parser's budget share: %.2g %%\n",
              100.0 * 2400.0 / (mb * 1e6 / ours_s));
}

void BenchJitter() {
  test::JitterScenario sc;
  sc.seconds = 600.0;
  const test::JitterResult r = test::RunJitterScenario(sc);
  std::printf("clock model: %g s at 100 Hz, skew %g ppm, exponential latency mean %g ms + %g ms stalls (p=%g)\n",
              sc.seconds, sc.skew_ppm, sc.mean_latency_s * 1e3, sc.stall_s * 1e3, sc.stall_probability);
  std::printf("BENCH imu_driver.stamp_jitter_raw_std %.1f us\n", r.raw_std_s * 1e6);
  std::printf("BENCH imu_driver.stamp_jitter_raw_max %.1f us\n", r.raw_max_abs_s * 1e6);
  std::printf("BENCH imu_driver.stamp_jitter_smoothed_std %.2f us\n", r.smoothed_std_s * 1e6);
  std::printf("BENCH imu_driver.stamp_jitter_smoothed_max %.2f us\n", r.smoothed_max_abs_s * 1e6);
  std::printf("BENCH imu_driver.stamp_jitter_reduction %.0f x\n", r.raw_std_s / r.smoothed_std_s);
}

void BenchLatency() {
  char tmpl[] = "/tmp/imu_driver_bench_XXXXXX";
  if (!::mkdtemp(tmpl)) return;
  const std::string link = std::string(tmpl) + "/imu";
  test::PtyWriter imu(link);
  imu.Plug();
  std::mutex m;
  std::vector<Clock::time_point> received;
  const DriverConfig driver_config;
  const GyroCalibration gyro;
  SerialReaderConfig config;
  config.port = link;
  config.read_timeout_ms = 100;
  SerialReader reader(
      config, [] { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); },
      [&](const ImuSample& s) {
        // What the nodelet does before publish(): the REP-145 message.
        auto msg = boost::make_shared<sensor_msgs::Imu>();
        FillImuMessage(s, driver_config, gyro, msg.get());
        std::lock_guard<std::mutex> l(m);
        received.push_back(Clock::now());
      },
      [](int, const std::string&) {});
  reader.Start();
  test::WaitFor([&] { return reader.status().connected; });
  std::vector<double> latency_us;
  std::mt19937 rng(2);
  for (int k = 0; k < 500; ++k) {
    std::vector<uint8_t> f;
    test::RandomFrame(rng, static_cast<uint8_t>(k), false, &f);
    imu.Write(f.data(), f.size() - 1);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));  // the frame's body is already there
    const auto t0 = Clock::now();
    imu.Write(&f.back(), 1);  // the last byte
    test::WaitFor(
        [&] {
          std::lock_guard<std::mutex> l(m);
          return received.size() == static_cast<size_t>(k + 1);
        },
        1.0);
    std::lock_guard<std::mutex> l(m);
    if (received.size() == static_cast<size_t>(k + 1)) latency_us.push_back(Seconds(t0, received.back()) * 1e6);
    std::this_thread::sleep_for(std::chrono::milliseconds(8));
  }
  reader.Stop();
  ::unlink(link.c_str());
  ::rmdir(tmpl);
  if (latency_us.empty()) return;
  std::sort(latency_us.begin(), latency_us.end());
  std::printf(
      "latency: last byte written to the pty master -> sensor_msgs/Imu built and ready for publish(), %zu frames\n",
      latency_us.size());
  std::printf("BENCH imu_driver.added_latency_median %.1f us\n", latency_us[latency_us.size() / 2]);
  std::printf("BENCH imu_driver.added_latency_p99 %.1f us\n", latency_us[latency_us.size() * 99 / 100]);
}

}  // namespace
}  // namespace imu_driver

int main() {
  imu_driver::BenchParser();
  imu_driver::BenchJitter();
  imu_driver::BenchLatency();
  return 0;
}
