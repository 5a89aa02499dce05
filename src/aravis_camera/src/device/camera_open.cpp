// Opening, configuring and closing the camera (CameraDevice's connection half).
#include "aravis_camera/core/pixel_format.h"
#include "aravis_camera/device/camera_device.h"

namespace aravis_camera {

namespace {
// The device id to open for `name`: the first camera when empty; else `name`
// itself if Aravis opens it (an id or an address), else the id of the
// discovered camera whose serial number is `name`.
std::string FindBySerial(const std::string& name) {
  arv_update_device_list();
  for (unsigned i = 0; i < arv_get_n_devices(); ++i) {
    const char* serial = arv_get_device_serial_nbr(i);
    if (name.empty() || (serial != nullptr && name == serial)) return arv_get_device_id(i);
  }
  return "";
}
}  // namespace

bool CameraDevice::Open() {
  GError* error = nullptr;
  control_lost_ = false;
  if (config_.enable_fake_interface) arv_enable_interface("Fake");
  if (!config_.camera_name.empty()) camera_ = arv_camera_new(config_.camera_name.c_str(), &error);
  if (camera_ == nullptr) {
    if (error != nullptr) g_clear_error(&error);
    const std::string id = FindBySerial(config_.camera_name);
    if (!id.empty()) camera_ = arv_camera_new(id.c_str(), &error);
    if (camera_ == nullptr) {
      Ok(error, "open");
      std::lock_guard<std::mutex> lock(mutex_);
      if (error == nullptr) stats_.last_error = config_.camera_name.empty() ? "no camera found" : "no such camera";
      ++stats_.open_failures;
      return false;
    }
  }
  const char* id = arv_camera_get_device_id(camera_, nullptr);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.camera_id = id != nullptr ? id : config_.camera_name;
  }
  if (!ApplySettings()) {
    Close();
    return false;
  }
  const guint payload = arv_camera_get_payload(camera_, &error);
  ArvStream* stream = Ok(error, "payload") ? arv_camera_create_stream(camera_, nullptr, nullptr, &error) : nullptr;
  if (stream == nullptr) {
    Ok(error, "create stream");
    Close();
    return false;
  }
  pool_ = FramePool::Create(stream, static_cast<size_t>(config_.n_buffers), payload);
  pool_->Prime();
  g_signal_connect(arv_camera_get_device(camera_), "control-lost", G_CALLBACK(&CameraDevice::OnControlLost), this);
  arv_camera_set_acquisition_mode(camera_, ARV_ACQUISITION_MODE_CONTINUOUS, &error);
  if (Ok(error, "acquisition mode")) arv_camera_start_acquisition(camera_, &error);
  if (!Ok(error, "start acquisition")) {
    Close();
    return false;
  }
  mapper_.Reset();
  std::lock_guard<std::mutex> lock(mutex_);
  last_frame_ns_ = HostNowNs();  // the frame timeout counts from here
  stats_pool_ = pool_;
  stats_.connected = true;
  return true;
}

bool CameraDevice::ApplySettings() {
  GError* error = nullptr;
  arv_camera_set_pixel_format_from_string(camera_, config_.pixel_format.c_str(), &error);
  if (!Ok(error, ("pixel format " + config_.pixel_format).c_str())) return false;  // without it the encoding is wrong
  gint x = 0, y = 0, w = 0, h = 0;
  arv_camera_get_region(camera_, &x, &y, &w, &h, &error);
  if (!Ok(error, "read region")) return false;
  if (config_.width_px > 0 || config_.height_px > 0 || config_.offset_x_px > 0 || config_.offset_y_px > 0) {
    arv_camera_set_region(camera_, config_.offset_x_px, config_.offset_y_px,
                          config_.width_px > 0 ? config_.width_px : w, config_.height_px > 0 ? config_.height_px : h,
                          &error);
    if (!Ok(error, "region")) return false;
    arv_camera_get_region(camera_, &x, &y, &w, &h, &error);
    if (!Ok(error, "read region")) return false;
  }
  width_ = w;
  height_ = h;
  encoding_ = EncodingForPixelFormat(config_.pixel_format);
  if (arv_camera_is_gv_device(camera_)) {
    int failures = 0;
    if (config_.packet_size_bytes > 0) {
      arv_camera_gv_set_packet_size(camera_, config_.packet_size_bytes, &error);
    } else {
      arv_camera_gv_auto_packet_size(camera_, &error);
    }
    failures += !Ok(error, "packet size");
    arv_camera_gv_set_packet_delay(camera_, config_.inter_packet_delay_ns, &error);
    failures += !Ok(error, "packet delay");
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.settings_failures += failures;
  }
  LiveSettings live;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    live = live_;  // restores the latest tuned values after a reconnect
  }
  ApplyLiveSettings(live);
  return true;
}

void CameraDevice::ApplyLiveSettings(const LiveSettings& s) {
  // A camera without one of these features keeps streaming; the failure is
  // counted and logged, never fatal.
  GError* error = nullptr;
  int failures = 0;
  arv_camera_set_frame_rate(camera_, s.frame_rate_hz, &error);
  failures += !Ok(error, "frame rate");
  if (s.exposure_auto) {
    arv_camera_set_exposure_time_auto(camera_, ARV_AUTO_CONTINUOUS, &error);
    failures += !Ok(error, "auto exposure");
  } else {
    if (arv_camera_is_exposure_auto_available(camera_, nullptr)) {
      arv_camera_set_exposure_time_auto(camera_, ARV_AUTO_OFF, &error);
      failures += !Ok(error, "auto exposure off");
    }
    arv_camera_set_exposure_time(camera_, s.exposure_us, &error);
    failures += !Ok(error, "exposure");
  }
  arv_camera_set_gain(camera_, s.gain_db, &error);
  failures += !Ok(error, "gain");
  if (failures > 0) {
    Log(LogLevel::kWarn, "camera '" + stats_.camera_id + "': " + std::to_string(failures) +
                             " setting(s) not applied, last: " + stats().last_error);
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.settings_failures += failures;
  }
}

void CameraDevice::Close(bool camera_responds) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.connected = false;
  }
  if (camera_ != nullptr) {
    // On a lost camera every register write waits out GVCP's retries; skip it.
    if (camera_responds) arv_camera_stop_acquisition(camera_, nullptr);
    g_signal_handlers_disconnect_by_data(arv_camera_get_device(camera_), this);
  }
  if (pool_) {
    ReadStreamStatistics();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      base_underruns_ = stats_.underruns;
      base_missing_ = stats_.missing_packets;
      base_resent_ = stats_.resent_packets;
    }
    pool_->Close();  // joins the stream thread; frames still held by subscribers stay valid
    pool_.reset();
    std::lock_guard<std::mutex> lock(mutex_);
    stats_pool_.reset();
  }
  if (camera_ != nullptr) {
    g_object_unref(camera_);
    camera_ = nullptr;
  }
}

}  // namespace aravis_camera
