// The camera behind one Aravis connection, kept streaming: opens it (retrying
// while it is absent), applies the settings, runs the acquisition thread that
// hands out zero-copy frames, and reopens the camera in the same process when
// it is lost (the "control-lost" signal, or no frame for frame_timeout_s),
// restoring the settings. No ROS runtime: logging and frames go through
// callbacks.
#pragma once

#include <arv.h>
#include <sensor_msgs/Image.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "aravis_camera/core/camera_config.h"
#include "aravis_camera/core/timestamp_mapper.h"
#include "aravis_camera/device/frame_pool.h"

namespace aravis_camera {

enum class LogLevel { kInfo, kWarn, kError };

struct FrameInfo {
  int64_t stamp_ns = 0;       // the stamp to publish (config.stamp_source)
  int64_t host_ns = 0;        // host clock at the frame's first packet
  uint64_t device_ns = 0;     // the camera's timestamp
  int64_t completion_ns = 0;  // host clock when the frame was complete and popped
  bool complete = true;
};

struct DeviceStats {
  bool connected = false;
  std::string camera_id;
  uint64_t frames_published = 0;
  uint64_t frames_incomplete = 0;  // any status but success
  uint64_t frames_dropped = 0;     // incomplete frames not published
  uint64_t underruns = 0;          // no free buffer: a slow subscriber holds the pool
  uint64_t missing_packets = 0;
  uint64_t resent_packets = 0;
  uint64_t reconnects = 0;
  uint64_t open_failures = 0;
  uint64_t settings_failures = 0;
  int frames_in_flight = 0;
  double seconds_since_frame = -1.0;  // -1 before the first frame
  std::string last_error;
};

// Live-tunable settings (dynamic_reconfigure).
struct LiveSettings {
  double frame_rate_hz = 30.0;
  bool exposure_auto = false;
  double exposure_us = 10000.0;
  double gain_db = 0.0;
};

class CameraDevice {
 public:
  // The callback runs on the acquisition thread. The image's header stamp,
  // size, encoding and step are filled in; frame_id is the config's.
  using FrameCallback = std::function<void(const sensor_msgs::ImagePtr&, const FrameInfo&)>;
  using LogCallback = std::function<void(LogLevel, const std::string&)>;

  CameraDevice(const CameraConfig& config, FrameCallback on_frame, LogCallback log);
  ~CameraDevice();  // stops and joins the thread, closes the camera
  CameraDevice(const CameraDevice&) = delete;
  CameraDevice& operator=(const CameraDevice&) = delete;

  void Start();  // returns at once; the camera is opened on the acquisition thread
  void Stop();

  void UpdateSettings(const LiveSettings& s);  // applied by the acquisition thread
  DeviceStats stats() const;

 private:
  void Run();
  bool Open();
  void Close(bool camera_responds = true);
  bool ApplySettings();
  void ApplyLiveSettings(const LiveSettings& s);
  void HandleBuffer(ArvBuffer* buffer);
  void ReadStreamStatistics();
  static void OnControlLost(ArvDevice* device, void* self);
  void Log(LogLevel level, const std::string& msg);
  bool Ok(GError* error, const char* what);

  const CameraConfig config_;
  FrameCallback on_frame_;
  LogCallback log_;

  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> control_lost_{false};

  // Owned by the acquisition thread.
  ArvCamera* camera_ = nullptr;
  std::shared_ptr<FramePool> pool_;
  TimestampMapper mapper_;
  std::string encoding_;
  int width_ = 0, height_ = 0;
  int64_t last_frame_ns_ = 0;  // any buffer, complete or not (written under mutex_)
  int64_t lost_since_ns_ = 0;

  // Guards what the ROS side reads or writes (stats, live settings); the
  // acquisition thread owns everything above.
  mutable std::mutex mutex_;
  DeviceStats stats_;
  uint64_t base_underruns_ = 0, base_missing_ = 0, base_resent_ = 0;  // totals of earlier connections
  int64_t last_published_ns_ = 0;
  std::shared_ptr<FramePool> stats_pool_;  // the current pool, for frames_in_flight
  LiveSettings live_;
  bool live_pending_ = false;
};

// Host clock (CLOCK_REALTIME, as ROS wall time) in ns.
int64_t HostNowNs();

}  // namespace aravis_camera
