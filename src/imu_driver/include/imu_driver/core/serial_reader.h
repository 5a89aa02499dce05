// The driver's I/O loop on its own thread: open the port (retrying with
// exponential backoff while it is missing), read, feed the CristaStream, and
// close and reopen when the device goes away. ROS-free; the nodelet supplies
// the clock and the sample callback and polls status() for diagnostics.
#pragma once

#include <atomic>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "imu_driver/core/crista_stream.h"
#include "imu_driver/core/serial_port.h"

namespace imu_driver {

struct SerialReaderConfig {
  std::string port = "/dev/ttyUSB0";
  int baud = 115200;
  double retry_initial_s = 0.1;           // first wait after a failed open
  double retry_max_s = 2.0;               // backoff doubles up to this
  int read_timeout_ms = 50;               // how often the loop checks for Stop()
  bool request_config_on_connect = true;  // send kReqConfig so the IMU reports its rate and ranges
  StreamConfig stream;                    // its baud is overwritten with `baud`
};

// Thread-safe copy of what diagnostics need.
struct SerialReaderStatus {
  bool connected = false;
  std::string last_error;      // empty while healthy
  uint64_t open_failures = 0;  // consecutive, reset on success
  uint64_t disconnects = 0;    // device lost while open
  uint64_t connects = 0;
  double last_sample_host_s = -1.0;  // host clock of the last sample, -1 before any
  ParserCounts parser;
  StreamCounts stream;
  size_t time_sync_resets = 0;
  double skew_ppm = 0.0;
};

class SerialReader {
 public:
  using Clock = std::function<double()>;  // host time, seconds
  using SampleCallback = std::function<void(const ImuSample&)>;
  // A line for the log (error or recovery); level 0 info, 1 warning, 2 error.
  using LogCallback = std::function<void(int level, const std::string&)>;

  SerialReader(const SerialReaderConfig& config, Clock clock, SampleCallback on_sample, LogCallback log);
  ~SerialReader();  // stops and joins
  SerialReader(const SerialReader&) = delete;
  SerialReader& operator=(const SerialReader&) = delete;

  void Start();
  void Stop();
  SerialReaderStatus status() const;

 private:
  void Run();
  bool SleepUnlessStopped(double seconds);
  void Publish(const ImuSample& s);
  void UpdateStatus(const std::function<void(SerialReaderStatus&)>& f);

  SerialReaderConfig config_;
  Clock clock_;
  SampleCallback on_sample_;
  LogCallback log_;
  CristaStream stream_;
  SerialPort port_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  mutable std::mutex status_mutex_;  // status_ is written by the I/O thread, read by diagnostics
  SerialReaderStatus status_;
  std::string device_problem_;  // last CheckDeviceInfo result, logged when it changes
};

}  // namespace imu_driver
