#include "aravis_camera/device/camera_device.h"

#include <chrono>
#include <cstdio>
#include <ctime>

#include "aravis_camera/core/pixel_format.h"

namespace aravis_camera {

namespace {
constexpr guint64 kPopTimeoutUs = 100000;
constexpr int64_t kStatsPeriodNs = 500'000'000;
constexpr int64_t kOpenLogPeriodNs = 10'000'000'000;

std::string Seconds(int64_t ns) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.1f s", ns * 1e-9);
  return buf;
}
}  // namespace

int64_t HostNowNs() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

CameraDevice::CameraDevice(const CameraConfig& config, FrameCallback on_frame, LogCallback log)
    : config_(config), on_frame_(std::move(on_frame)), log_(std::move(log)) {
  live_ = LiveSettings{config.frame_rate_hz, config.exposure_auto, config.exposure_us, config.gain_db};
}

CameraDevice::~CameraDevice() { Stop(); }

void CameraDevice::Start() {
  if (thread_.joinable()) return;
  stop_ = false;
  thread_ = std::thread(&CameraDevice::Run, this);
}

void CameraDevice::Stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void CameraDevice::UpdateSettings(const LiveSettings& s) {
  std::lock_guard<std::mutex> lock(mutex_);
  live_ = s;
  live_pending_ = true;
}

DeviceStats CameraDevice::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  DeviceStats s = stats_;
  s.seconds_since_frame = last_published_ns_ > 0 ? (HostNowNs() - last_published_ns_) * 1e-9 : -1.0;
  if (stats_pool_) s.frames_in_flight = stats_pool_->in_flight();
  return s;
}

void CameraDevice::Log(LogLevel level, const std::string& msg) {
  if (log_) log_(level, msg);
}

bool CameraDevice::Ok(GError* error, const char* what) {
  if (error == nullptr) return true;
  const std::string msg = std::string(what) + ": " + error->message;
  g_error_free(error);
  std::lock_guard<std::mutex> lock(mutex_);
  stats_.last_error = msg;
  return false;
}

void CameraDevice::OnControlLost(ArvDevice*, void* self) {
  // Emitted on Aravis's heartbeat thread: only raise the flag.
  static_cast<CameraDevice*>(self)->control_lost_ = true;
}

void CameraDevice::Run() {
  int64_t last_open_log_ns = 0;
  int64_t last_stats_ns = 0;
  while (!stop_) {
    if (camera_ == nullptr) {
      if (Open()) {
        if (lost_since_ns_ > 0) {
          Log(LogLevel::kInfo, "camera '" + stats_.camera_id + "' reconnected after " +
                                   Seconds(HostNowNs() - lost_since_ns_) + "; streaming again");
        } else {
          Log(LogLevel::kInfo, "camera '" + stats_.camera_id + "' open, streaming " + encoding_ + " " +
                                   std::to_string(width_) + "x" + std::to_string(height_));
        }
        lost_since_ns_ = 0;
        continue;
      }
      const int64_t now = HostNowNs();
      if (now - last_open_log_ns > kOpenLogPeriodNs) {
        Log(LogLevel::kError, "cannot open camera '" + config_.camera_name + "': " + stats().last_error +
                                  "; retrying every " + std::to_string(config_.reconnect_period_s) + " s");
        last_open_log_ns = now;
      }
      const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(config_.reconnect_period_s);
      while (!stop_ && std::chrono::steady_clock::now() < until)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      continue;
    }

    LiveSettings live;
    bool pending = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      std::swap(pending, live_pending_);
      live = live_;
    }
    if (pending) ApplyLiveSettings(live);

    const int64_t now = HostNowNs();
    const bool timed_out = now - last_frame_ns_ > static_cast<int64_t>(config_.frame_timeout_s * 1e9);
    if (control_lost_ || timed_out) {
      Log(LogLevel::kWarn,
          "camera '" + stats_.camera_id + "' lost (" +
              (control_lost_ ? std::string("control lost") : "no frame for " + Seconds(now - last_frame_ns_)) +
              "); reconnecting");
      Close(/*camera_responds=*/false);
      lost_since_ns_ = now;
      last_open_log_ns = now;  // the reconnect attempts log only if they go on for long
      std::lock_guard<std::mutex> lock(mutex_);
      ++stats_.reconnects;
      continue;
    }

    ArvBuffer* buffer = arv_stream_timeout_pop_buffer(pool_->stream(), kPopTimeoutUs);
    if (buffer != nullptr) HandleBuffer(buffer);
    // Without a buffer, underruns still prove the camera is sending: a slow
    // subscriber holds the pool, the camera is not lost.
    if (buffer == nullptr || now - last_stats_ns > kStatsPeriodNs) {
      ReadStreamStatistics();
      last_stats_ns = now;
    }
  }
  Close();
}

void CameraDevice::HandleBuffer(ArvBuffer* buffer) {
  const int64_t now = HostNowNs();
  const bool complete = arv_buffer_get_status(buffer) == ARV_BUFFER_STATUS_SUCCESS;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    last_frame_ns_ = now;  // the camera is alive, even if this frame is incomplete
    if (!complete) ++stats_.frames_incomplete;
    if (!complete && !config_.publish_incomplete) {
      ++stats_.frames_dropped;
      pool_->Recycle(buffer);
      return;
    }
  }
  sensor_msgs::ImagePtr image = pool_->Wrap(buffer);
  if (!image) {
    Log(LogLevel::kError, "stream returned a buffer that is not from the driver's pool; dropped");
    return;
  }
  FrameInfo info;
  info.complete = complete;
  info.completion_ns = now;
  info.host_ns = static_cast<int64_t>(arv_buffer_get_system_timestamp(buffer));
  info.device_ns = arv_buffer_get_timestamp(buffer);
  if (info.host_ns == 0) info.host_ns = now;
  int64_t stamp = info.host_ns;
  if (config_.stamp_source == StampSource::kCompletion) stamp = now;
  if (config_.stamp_source == StampSource::kDevice && info.device_ns != 0)
    stamp = mapper_.Map(info.device_ns, info.host_ns);
  info.stamp_ns = stamp - static_cast<int64_t>(config_.stamp_offset_s * 1e9);

  image->header.stamp.fromNSec(static_cast<uint64_t>(info.stamp_ns));
  image->header.frame_id = config_.frame_id;
  image->width = static_cast<uint32_t>(width_);
  image->height = static_cast<uint32_t>(height_);
  image->encoding = encoding_;
  image->is_bigendian = 0;
  image->step = static_cast<uint32_t>(width_ * BytesPerPixel(config_.pixel_format));
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.frames_published;
    last_published_ns_ = now;
  }
  on_frame_(image, info);
}

void CameraDevice::ReadStreamStatistics() {
  if (!pool_) return;
  guint64 completed = 0, failures = 0, underruns = 0;
  arv_stream_get_statistics(pool_->stream(), &completed, &failures, &underruns);
  const guint64 missing = arv_stream_get_info_uint64_by_name(pool_->stream(), "n_missing_packets");
  const guint64 resent = arv_stream_get_info_uint64_by_name(pool_->stream(), "n_resent_packets");
  std::lock_guard<std::mutex> lock(mutex_);
  // Stream counters restart with every connection; keep the totals across them.
  if (base_underruns_ + underruns > stats_.underruns) last_frame_ns_ = HostNowNs();
  stats_.underruns = base_underruns_ + underruns;
  stats_.missing_packets = base_missing_ + missing;
  stats_.resent_packets = base_resent_ + resent;
}

}  // namespace aravis_camera
