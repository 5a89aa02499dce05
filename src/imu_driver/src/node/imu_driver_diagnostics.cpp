#include "imu_driver_diagnostics.h"

#include <diagnostic_msgs/DiagnosticStatus.h>

#include <string>

#include "imu_driver/core/crista_messages.h"

namespace imu_driver {

void DriverDiagnostics::Fill(const SerialReaderStatus& st, const DriverConfig& config, const GyroCalibration& gyro,
                             double now_s, diagnostic_updater::DiagnosticStatusWrapper* s) {
  using diagnostic_msgs::DiagnosticStatus;
  const ParserCounts& p = st.parser;
  const uint64_t rejects = p.bad_crc + p.bad_length + p.unknown_type + p.truncated;
  const double age_s = st.last_sample_host_s < 0.0 ? -1.0 : now_s - st.last_sample_host_s;

  if (!st.connected) {
    s->summaryf(DiagnosticStatus::ERROR, "port %s unavailable: %s", config.reader.port.c_str(), st.last_error.c_str());
  } else if (age_s < 0.0) {
    s->summary(DiagnosticStatus::WARN, "port open, no IMU data yet");
  } else if (age_s > config.stale_after_s) {
    s->summaryf(DiagnosticStatus::ERROR, "no IMU data for %.2f s", age_s);
  } else if (!CheckDeviceInfo(st.stream.device, config.reader.stream.rate_hz).empty()) {
    s->summary(DiagnosticStatus::ERROR, CheckDeviceInfo(st.stream.device, config.reader.stream.rate_hz));
  } else if (rejects > last_rejects_ || st.stream.sequence_gaps > last_gaps_) {
    s->summaryf(DiagnosticStatus::WARN, "%lu corrupt frame(s), %lu sequence gap(s) since the last report",
                static_cast<unsigned long>(rejects - last_rejects_),
                static_cast<unsigned long>(st.stream.sequence_gaps - last_gaps_));
  } else {
    s->summary(DiagnosticStatus::OK, "streaming");
  }
  last_rejects_ = rejects;
  last_gaps_ = st.stream.sequence_gaps;

  s->add("port", config.reader.port);
  s->add("baud", config.reader.baud);
  s->add("connected", st.connected);
  s->add("open failures (consecutive)", st.open_failures);
  s->add("disconnects", st.disconnects);
  s->add("time since last sample (s)", age_s);
  s->add("samples", st.stream.samples);
  s->add("sequence gaps", st.stream.sequence_gaps);
  s->add("samples missed", st.stream.samples_missed);
  s->add("sequence repeats", st.stream.sequence_repeats);
  s->add("host clock jumps", st.stream.host_clock_jumps);
  s->add("bytes received", p.bytes_in);
  s->add("garbage bytes", p.garbage_bytes);
  s->add("rejected: bad CRC", p.bad_crc);
  s->add("rejected: bad length", p.bad_length);
  s->add("rejected: unknown type", p.unknown_type);
  s->add("rejected: truncated", p.truncated);
  s->add("other message types", p.frames_ok - st.stream.frames_by_type[0xFF]);
  s->add("clock skew (ppm)", st.skew_ppm);
  s->add("timestamp model resets", st.time_sync_resets);
  const DeviceInfo& dev = st.stream.device;
  s->add("IMU output rate (Hz, reported)", dev.have_settings ? std::to_string(dev.output_rate_hz) : "not reported");
  s->add("IMU ranges (reported)", dev.have_resolution ? std::to_string(dev.gyro_range_deg_s) + " deg/s, " +
                                                            std::to_string(dev.accel_range_g) + " g"
                                                      : "not reported");
  s->add("IMU software", dev.software_version.empty() ? "not reported" : dev.software_version);
  s->add("gyro calibrated", gyro.calibrated);
  s->addf("gyro bias (rad/s)", "%.6f %.6f %.6f", gyro.bias_rad_s(0), gyro.bias_rad_s(1), gyro.bias_rad_s(2));
  s->addf("gyro noise sigma (rad/s)", "%.6f %.6f %.6f", gyro.sigma_rad_s(0), gyro.sigma_rad_s(1), gyro.sigma_rad_s(2));
}

}  // namespace imu_driver
