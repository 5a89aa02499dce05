// The overlay nodelet: a thin adapter around Overlay (overlay.h).
//
// Threading: EGL contexts are current per thread, and nodelet callbacks run on
// whichever thread of the manager's pool is free. So the nodelet owns one
// render thread that creates the GL context, renders every frame and destroys
// the context; the ROS callbacks only hand it the newest image (mutex_ +
// wake_). A slow render drops stale frames instead of queueing them (counted).
#include <cv_bridge/cv_bridge.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <atomic>
#include <boost/make_shared.hpp>
#include <cmath>
#include <condition_variable>
#include <map>
#include <opencv2/highgui.hpp>
#include <opencv2/imgproc.hpp>
#include <pluginlib/class_list_macros.hpp>
#include <set>
#include <thread>

#include "ar_overlay/core/composite.h"
#include "ar_overlay/core/overlay.h"
#include "ar_overlay/core/pose_extrapolation.h"
#include "ar_overlay/node/ros_config.h"
#include "rig_model/ros/diagnostics.h"

namespace ar_overlay {
namespace {

// Why a frame cannot be drawn, as a short reason that diagnostics count by; "" when it can.
std::string BadFrameReason(const sensor_msgs::Image& image, const sensor_msgs::CameraInfo& info, bool with_pose) {
  namespace enc = sensor_msgs::image_encodings;
  static const std::set<std::string> kSupported = {enc::RGB8,        enc::BGR8,        enc::RGBA8,
                                                   enc::BGRA8,       enc::MONO8,       enc::BAYER_RGGB8,
                                                   enc::BAYER_BGGR8, enc::BAYER_GBRG8, enc::BAYER_GRBG8};
  if (!kSupported.count(image.encoding)) return "unsupported encoding '" + image.encoding + "'";
  if (image.width == 0 || image.height == 0) return "empty image";
  const size_t row = size_t(image.width) * size_t(enc::numChannels(image.encoding));
  if (image.step < row || image.data.size() < size_t(image.step) * image.height)
    return "image data shorter than height x step";
  if (!with_pose) return "";
  if (info.width != image.width || info.height != image.height) return "camera_info size differs from the image";
  if (!(info.K[0] > 0.0 && info.K[4] > 0.0 && std::isfinite(info.K[2]) && std::isfinite(info.K[5])))
    return "camera_info without a valid focal length";
  return "";
}

}  // namespace

class OverlayNodelet : public nodelet::Nodelet {
 public:
  ~OverlayNodelet() override {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    if (render_thread_.joinable()) render_thread_.join();
  }

 private:
  struct Frame {
    sensor_msgs::ImageConstPtr image;
    sensor_msgs::CameraInfoConstPtr info;
    uint64_t seq = 0;
  };

  void onInit() override {
    diagnostics_ =
        std::make_unique<rig_model::WallDiagnostics>(getNodeHandle(), getPrivateNodeHandle(), getName(), "ar_overlay");
    const std::string error = LoadConfig(getPrivateNodeHandle(), config_);
    if (!error.empty()) {
      NODELET_FATAL("%s", diagnostics_->RefuseConfig("overlay", "ar_overlay", "bad parameter: " + error).c_str());
      return;
    }
    tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_);
    diagnostics_->Add("overlay", [this](diagnostic_updater::DiagnosticStatusWrapper& s) { Diagnose(s); });
    in_freq_ = std::make_unique<rig_model::StampRateTask>("camera input", rig_model::RateCheckConfig{});
    rig_model::RateCheckConfig out_rate;
    out_rate.min_hz = 1.0, out_rate.max_hz = 1000.0;
    out_rate.stale_level = diagnostic_msgs::DiagnosticStatus::WARN;  // the input's own check says why
    out_freq_ = std::make_unique<rig_model::StampRateTask>("image", out_rate);
    diagnostics_->Add(*in_freq_);
    diagnostics_->Add(*out_freq_);
    render_thread_ = std::thread(&OverlayNodelet::RenderLoop, this);  // joined in the destructor
    it_ = std::make_unique<image_transport::ImageTransport>(getNodeHandle());
    pub_ = image_transport::ImageTransport(getPrivateNodeHandle()).advertise("image", 1);
    camera_sub_ = it_->subscribeCamera("camera/image_raw", 2, &OverlayNodelet::OnCamera, this);
    joints_sub_ = getNodeHandle().subscribe("joint_states", 10, &OverlayNodelet::OnJoints, this);
  }

  void OnCamera(const sensor_msgs::ImageConstPtr& image, const sensor_msgs::CameraInfoConstPtr& info) {
    in_freq_->Tick(image->header.stamp);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      latest_ = Frame{image, info, latest_.seq + 1};
    }
    wake_.notify_one();
  }

  void OnJoints(const sensor_msgs::JointStateConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (size_t i = 0; i < msg->name.size() && i < msg->position.size(); ++i)
      if (std::isfinite(msg->position[i])) joints_[msg->name[i]] = msg->position[i];
  }

  void RenderLoop() {
    std::unique_ptr<Overlay> overlay;
    try {
      RenderConfig rc;
      rc.near_m = config_.near_m;
      rc.far_m = config_.far_m;
      rc.lod_max_error_px = config_.lod_max_error_px;
      overlay = std::make_unique<Overlay>(rc);
      std::vector<std::string> errors;
      if (!config_.scene_yaml.empty()) errors = overlay->LoadScene(config_.scene_yaml);
      for (const std::string& e : errors)
        NODELET_ERROR("ar_overlay: model not loaded, drawing the rest: %s", e.c_str());
      NODELET_INFO("ar_overlay: %zu model(s) on %s", overlay->model_count() - errors.size(),
                   overlay->gl_renderer().c_str());
      std::lock_guard<std::mutex> lock(mutex_);
      model_errors_ = errors;
      gl_renderer_ = overlay->gl_renderer();
    } catch (const std::exception& e) {
      NODELET_ERROR("ar_overlay: cannot render, publishing the camera image only: %s", e.what());
      std::lock_guard<std::mutex> lock(mutex_);
      init_error_ = e.what();
      overlay.reset();
    }
    bool window = config_.show_window;
    if (window) {
      try {
        cv::namedWindow(config_.window_name, cv::WINDOW_NORMAL);
        cv::setWindowProperty(config_.window_name, cv::WND_PROP_FULLSCREEN, cv::WINDOW_FULLSCREEN);
      } catch (const cv::Exception& e) {
        NODELET_WARN("ar_overlay: no window (no display?): %s", e.what());
        window = false;
      }
    }
    const bool predicted = config_.pose_mode == PoseMode::kPredicted;
    const auto period = std::chrono::duration<double>(1.0 / config_.render_rate_hz);
    auto next = std::chrono::steady_clock::now();
    uint64_t done_seq = 0;
    while (true) {
      Frame f;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        if (predicted) {
          next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
          wake_.wait_until(lock, next, [this] { return stop_; });
          if (std::chrono::steady_clock::now() > next + period) next = std::chrono::steady_clock::now();
        } else {
          wake_.wait(lock, [&] { return stop_ || latest_.seq != done_seq; });
        }
        if (stop_) break;
        f = latest_;
        if (overlay) overlay->SetJointPositions(joints_);
      }
      if (!f.image) continue;
      if (!predicted && f.seq > done_seq + 1) dropped_ += f.seq - done_seq - 1;
      done_seq = f.seq;
      try {
        RenderOne(overlay.get(), f, window);
      } catch (const std::exception& e) {  // never let the render thread die (it would take the manager)
        CountBadFrame(std::string("render failed: ") + e.what());
        NODELET_ERROR_THROTTLE(5.0, "ar_overlay: frame failed: %s", e.what());
      }
    }
    if (window) cv::destroyWindow(config_.window_name);
  }

  // T_camera_cones for the frame; false (counted) when tf has none.
  bool LookupPose(const Frame& f, ros::Time& stamp, Eigen::Isometry3d& T_camera_cones) {
    const std::string& camera = config_.camera_frame.empty() ? f.image->header.frame_id : config_.camera_frame;
    try {
      if (config_.pose_mode == PoseMode::kImageStamp) {
        stamp = f.image->header.stamp;
        T_camera_cones = tf2::transformToEigen(
            tf_buffer_->lookupTransform(camera, config_.fixed_frame, stamp, ros::Duration(config_.tf_timeout_s)));
        return true;
      }
      stamp = ros::Time::now();
      const auto latest = tf_buffer_->lookupTransform(camera, config_.fixed_frame, ros::Time(0));
      T_camera_cones = tf2::transformToEigen(latest);
      const ros::Time t1 = latest.header.stamp;  // 0 for a static transform: nothing to predict
      if (t1.toSec() <= config_.velocity_window_s) return true;
      const ros::Time t0 = t1 - ros::Duration(config_.velocity_window_s);
      if (tf_buffer_->canTransform(camera, config_.fixed_frame, t0)) {
        const auto older = tf_buffer_->lookupTransform(camera, config_.fixed_frame, t0);
        T_camera_cones =
            ExtrapolatePose(tf2::transformToEigen(older), older.header.stamp.toSec(), T_camera_cones, t1.toSec(),
                            stamp.toSec() + config_.display_latency_s, config_.max_prediction_s);
      }
      return true;
    } catch (const tf2::TransformException& e) {
      ++without_pose_;
      NODELET_WARN_THROTTLE(5.0, "ar_overlay: no pose %s -> %s, showing the camera image alone: %s",
                            config_.fixed_frame.c_str(), camera.c_str(), e.what());
      return false;
    }
  }

  void RenderOne(Overlay* overlay, const Frame& f, bool window) {
    ros::Time stamp;
    Eigen::Isometry3d T_camera_cones;
    const bool have_pose = overlay != nullptr && LookupPose(f, stamp, T_camera_cones);
    if (!have_pose) stamp = f.image->header.stamp;
    const std::string bad = BadFrameReason(*f.image, *f.info, have_pose);
    if (!bad.empty()) {
      CountBadFrame(bad);
      NODELET_WARN_THROTTLE(5.0, "ar_overlay: frame skipped: %s (camera/image_raw)", bad.c_str());
      return;
    }
    // The output message's own memory is the composite's canvas: no copy on publish.
    auto out = boost::make_shared<sensor_msgs::Image>();
    out->header = f.image->header;
    out->header.stamp = stamp;
    out->height = f.image->height;
    out->width = f.image->width;
    out->step = 3 * out->width;
    out->data.resize(static_cast<size_t>(out->step) * out->height);
    cv::Mat canvas(static_cast<int>(out->height), static_cast<int>(out->width), CV_8UC3, out->data.data(), out->step);
    const auto start = std::chrono::steady_clock::now();
    try {
      const cv::Mat image = cv_bridge::toCvShare(f.image)->image;
      if (have_pose)
        overlay->Process(image, f.image->encoding, FromCameraInfo(*f.info), T_camera_cones, canvas, out->encoding);
      else
        ToColor(image, f.image->encoding, canvas, out->encoding);
      if (canvas.data != out->data.data()) throw std::logic_error("composite did not write into the message");
    } catch (const std::exception& e) {
      CountBadFrame(e.what());
      NODELET_WARN_THROTTLE(5.0, "ar_overlay: frame skipped: %s", e.what());
      return;
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (have_pose) {
      ++rendered_;
      render_ms_sum_ = render_ms_sum_ + ms;
      render_ms_max_ = std::max(render_ms_max_.load(), ms);
      triangles_drawn_ = overlay->renderer().drawn_triangles();
    }
    if (window) {
      cv::Mat shown;
      if (out->encoding == "rgb8") cv::cvtColor(canvas, shown, cv::COLOR_RGB2BGR);
      cv::imshow(config_.window_name, shown.empty() ? canvas : shown);
      cv::waitKey(1);
    }
    out_freq_->Tick(stamp);
    pub_.publish(out);  // not touched after this
  }

  // Counted by reason; reasons past the first kMaxReasons share one bucket so the map stays small.
  void CountBadFrame(const std::string& reason) {
    static constexpr size_t kMaxReasons = 16;
    std::lock_guard<std::mutex> lock(mutex_);
    ++bad_input_;
    if (bad_frames_.count(reason) || bad_frames_.size() < kMaxReasons)
      ++bad_frames_[reason];
    else
      ++bad_frames_["other reasons"];
    last_bad_reason_ = reason;
  }

  void Diagnose(diagnostic_updater::DiagnosticStatusWrapper& s) {
    std::lock_guard<std::mutex> lock(mutex_);
    const uint64_t rendered = rendered_, without = without_pose_;
    std::string models_not_loaded;
    for (const std::string& e : model_errors_) models_not_loaded += (models_not_loaded.empty() ? "" : "; ") + e;
    const uint64_t bad = bad_input_;
    if (!init_error_.empty())
      s.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "no renderer: " + init_error_);
    else if (bad > last_bad_input_)
      s.summaryf(diagnostic_msgs::DiagnosticStatus::WARN, "%lu bad frame(s) skipped since the last report, last: %s",
                 static_cast<unsigned long>(bad - last_bad_input_), last_bad_reason_.c_str());
    else if (without > last_without_pose_)
      s.summary(diagnostic_msgs::DiagnosticStatus::WARN, "frames without a pose");
    else if (!model_errors_.empty())
      s.summary(diagnostic_msgs::DiagnosticStatus::WARN, "some models did not load: " + models_not_loaded);
    else
      s.summary(diagnostic_msgs::DiagnosticStatus::OK, "rendering");
    last_without_pose_ = without;
    last_bad_input_ = bad;
    s.add("frames rendered", rendered);
    s.add("frames without pose", without);
    s.add("frames skipped (bad input)", bad);
    for (const auto& [reason, n] : bad_frames_) s.add("frames skipped: " + reason, n);
    s.add("frames dropped (render slower than camera)", dropped_.load());
    s.add("render+composite mean ms", rendered ? render_ms_sum_.load() / rendered : 0.0);
    s.add("render+composite max ms", render_ms_max_.load());
    s.add("triangles drawn (last frame, after the level of detail)", triangles_drawn_.load());
    s.add("GL renderer", gl_renderer_);
    s.add("models not loaded", model_errors_.size());
    if (!model_errors_.empty()) s.add("model not loaded", models_not_loaded);  // every one, with its reason
  }

  OverlayConfig config_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::unique_ptr<image_transport::ImageTransport> it_;
  image_transport::CameraSubscriber camera_sub_;
  image_transport::Publisher pub_;
  ros::Subscriber joints_sub_;
  std::unique_ptr<rig_model::WallDiagnostics> diagnostics_;
  std::unique_ptr<rig_model::StampRateTask> in_freq_, out_freq_;  // thread-safe ticks

  // Shared between the callbacks, the render thread and diagnostics.
  std::mutex mutex_;
  std::condition_variable wake_;
  Frame latest_;
  std::map<std::string, double> joints_;
  bool stop_ = false;
  std::vector<std::string> model_errors_;
  std::string init_error_, gl_renderer_;
  uint64_t last_without_pose_ = 0, last_bad_input_ = 0;
  std::map<std::string, uint64_t> bad_frames_;  // by reason
  std::string last_bad_reason_;
  std::thread render_thread_;

  std::atomic<uint64_t> rendered_{0}, without_pose_{0}, bad_input_{0}, dropped_{0}, triangles_drawn_{0};
  std::atomic<double> render_ms_sum_{0}, render_ms_max_{0};
};

}  // namespace ar_overlay

PLUGINLIB_EXPORT_CLASS(ar_overlay::OverlayNodelet, nodelet::Nodelet)
