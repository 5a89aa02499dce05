#include "imu_driver/core/serial_reader.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <sstream>

namespace imu_driver {
namespace {

StreamConfig WithBaud(StreamConfig s, int baud) {
  s.baud = baud;
  return s;
}

}  // namespace

SerialReader::SerialReader(const SerialReaderConfig& config, Clock clock, SampleCallback on_sample, LogCallback log)
    : config_(config),
      clock_(std::move(clock)),
      on_sample_(std::move(on_sample)),
      log_(std::move(log)),
      stream_(WithBaud(config.stream, config.baud), [this](const ImuSample& s) { Publish(s); }) {}

SerialReader::~SerialReader() { Stop(); }

void SerialReader::Start() {
  if (thread_.joinable()) return;
  stop_ = false;
  thread_ = std::thread([this] { Run(); });
}

void SerialReader::Stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  port_.Close();
}

SerialReaderStatus SerialReader::status() const {
  std::lock_guard<std::mutex> lock(status_mutex_);
  return status_;
}

void SerialReader::UpdateStatus(const std::function<void(SerialReaderStatus&)>& f) {
  std::lock_guard<std::mutex> lock(status_mutex_);
  f(status_);
}

bool SerialReader::SleepUnlessStopped(double seconds) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!stop_ && std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return !stop_;
}

void SerialReader::Publish(const ImuSample& s) {
  {
    std::lock_guard<std::mutex> lock(status_mutex_);
    status_.last_sample_host_s = s.arrival_s;
  }
  on_sample_(s);
}

void SerialReader::Run() {
  double backoff_s = config_.retry_initial_s;
  std::array<uint8_t, 4096> buf;
  while (!stop_) {
    if (!port_.is_open()) {
      std::string error;
      if (!port_.Open(config_.port, config_.baud, &error)) {
        uint64_t failures = 0;
        UpdateStatus([&](SerialReaderStatus& st) {
          st.connected = false;
          st.last_error = error;
          failures = ++st.open_failures;
        });
        // Log the first failure and then every doubling, not every retry.
        if ((failures & (failures - 1)) == 0) {
          std::ostringstream m;
          m << error << " (attempt " << failures << ", retrying every " << backoff_s << " s)";
          log_(2, m.str());
        }
        if (!SleepUnlessStopped(backoff_s)) break;
        backoff_s = std::min(backoff_s * 2.0, config_.retry_max_s);
        continue;
      }
      backoff_s = config_.retry_initial_s;
      UpdateStatus([&](SerialReaderStatus& st) {
        st.connected = true;
        st.last_error.clear();
        st.open_failures = 0;
        ++st.connects;
      });
      log_(0, "opened " + config_.port + " at " + std::to_string(config_.baud) + " baud");
      if (config_.request_config_on_connect) {
        const std::vector<uint8_t> request = EncodeConfigRequest();
        std::string werr;
        if (!port_.Write(request.data(), request.size(), 100, &werr)) log_(1, "configuration request: " + werr);
      }
    }
    const SerialPort::ReadResult r = port_.Read(buf.data(), buf.size(), config_.read_timeout_ms);
    if (r.status == SerialPort::ReadStatus::kData) {
      stream_.Feed(buf.data(), r.bytes, clock_());
    } else if (r.status != SerialPort::ReadStatus::kTimeout) {
      stream_.EndOfStream();
      port_.Close();
      UpdateStatus([&](SerialReaderStatus& st) {
        st.connected = false;
        st.last_error = r.error;
        ++st.disconnects;
      });
      log_(2, r.error + "; device lost, reopening " + config_.port);
    }
    const std::string problem = CheckDeviceInfo(stream_.counts().device, config_.stream.rate_hz);
    if (problem != device_problem_ && !problem.empty()) log_(2, problem);
    device_problem_ = problem;
    const std::string reset = stream_.time_sync().TakeResetReason();
    if (!reset.empty()) log_(1, "timestamp model reset: " + reset);
    UpdateStatus([&](SerialReaderStatus& st) {
      st.parser = stream_.parser_counts();
      st.stream = stream_.counts();
      st.time_sync_resets = stream_.time_sync().resets();
      st.skew_ppm = stream_.time_sync().skew_ppm();
    });
  }
}

}  // namespace imu_driver
