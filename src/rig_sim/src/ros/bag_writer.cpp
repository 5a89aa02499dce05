#include "rig_sim/ros/bag_writer.h"

#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>

#include <rosbag/bag.h>

namespace rig_sim {
namespace {

// Renders frames 0, 1, 2, ... on its own thread, a few frames ahead of the
// writer, so rendering overlaps serialisation and disk writes.
class FramePipeline {
 public:
  FramePipeline(const SimStream& stream, const BagOptions& opt, uint64_t count)
      : stream_(stream), opt_(opt), count_(count), worker_([this] { Run(); }) {}
  ~FramePipeline() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    cv_.notify_all();
    worker_.join();
  }
  sensor_msgs::ImagePtr Pop() {
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait(lock, [this] { return !queue_.empty(); });
    sensor_msgs::ImagePtr img = queue_.front();
    queue_.pop_front();
    cv_.notify_all();
    return img;
  }
  double render_s() const { return render_s_; }

 private:
  void Run() {
    const Scenario& s = stream_.scenario();
    for (uint64_t n = 0; n < count_; ++n) {
      {
        std::unique_lock<std::mutex> lock(mutex_);
        cv_.wait(lock, [this] { return stop_ || queue_.size() < 3; });
        if (stop_) return;
      }
      SimEvent ev;
      ev.kind = EventKind::kImage;
      ev.index = n;
      ev.stamp_s = n / s.camera.rate_hz;
      ev.pose = stream_.trajectory().At(ev.stamp_s);
      sensor_msgs::ImagePtr img = MakeEmptyImage(s.camera, StampAt(opt_.start_time_s, ev.stamp_s), opt_.frames.camera);
      const auto t0 = std::chrono::steady_clock::now();
      stream_.RenderFrame(ev, img->data.data());
      render_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::lock_guard<std::mutex> lock(mutex_);
      queue_.push_back(img);
      cv_.notify_all();
    }
  }

  const SimStream& stream_;
  const BagOptions& opt_;
  const uint64_t count_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<sensor_msgs::ImagePtr> queue_;
  bool stop_ = false;
  double render_s_ = 0.0;
  std::thread worker_;  // last: starts after the members above exist
};

uint64_t FrameCount(const Scenario& s) {
  uint64_t n = 0;
  while (n / s.camera.rate_hz < s.trajectory.duration_s) ++n;
  return n;
}

}  // namespace

bool WriteScenarioBag(const Scenario& scenario, const BagOptions& opt, const std::string& path, BagStats* stats,
                      std::string* error) {
  try {
    rosbag::Bag bag;
    bag.open(path, rosbag::bagmode::Write);
    if (opt.compression == "lz4") bag.setCompression(rosbag::compression::LZ4);
    else if (opt.compression == "bz2") bag.setCompression(rosbag::compression::BZ2);
    else if (opt.compression != "none") throw std::invalid_argument("compression must be none, lz4 or bz2");
    SimStream stream(scenario, opt.stream);
    const ros::Time t0 = StampAt(opt.start_time_s, 0.0);
    auto latched = boost::make_shared<ros::M_string>();
    (*latched)["latching"] = "1";
    (*latched)["callerid"] = "/rig_sim";
    bag.write("/tf_static", t0, MakeStaticTruth(scenario.imu, t0, opt.frames), latched);
    bag.write(opt.topics.markers, t0, MakeConeMarkers(scenario.scene, t0, opt.frames.cones), latched);
    BagStats local;
    FramePipeline frames(stream, opt, FrameCount(scenario));
    const uint64_t truth_per_imu =
        std::max<uint64_t>(1, static_cast<uint64_t>(std::llround(opt.stream.truth_rate_hz / scenario.imu.rate_hz)));
    SimEvent ev;
    while (stream.Next(&ev)) {
      const ros::Time stamp = StampAt(opt.start_time_s, ev.stamp_s);
      const ros::Time deliver = StampAt(opt.start_time_s, ev.deliver_s);
      switch (ev.kind) {
        case EventKind::kImu:
          bag.write(opt.topics.imu, deliver, MakeImu(ev.imu, scenario.imu, stamp, opt.frames.imu));
          bag.write(opt.topics.imu_bias, deliver, MakeImuBias(ev.imu, stamp, opt.frames.imu));
          ++local.imu;
          break;
        case EventKind::kTruth:
          bag.write(opt.topics.truth, deliver, MakeTruthPose(ev.pose, stamp, opt.frames.cones));
          if (opt.truth_tf && ev.index % truth_per_imu == 0) {
            tf2_msgs::TFMessage tf;
            tf.transforms.push_back(MakeTruthTransform(ev.pose, stamp, opt.frames));
            bag.write("/tf", deliver, tf);
          }
          ++local.truth;
          break;
        case EventKind::kImage: {
          const sensor_msgs::ImagePtr img = frames.Pop();
          if (img->header.stamp != stamp) throw std::logic_error("frame pipeline out of order");
          bag.write(opt.topics.image, deliver, img);
          bag.write(opt.topics.camera_info, deliver, MakeCameraInfo(scenario.camera, stamp, opt.frames.camera));
          ++local.images;
          break;
        }
      }
    }
    local.render_s = frames.render_s();
    bag.close();
    if (stats) *stats = local;
    return true;
  } catch (const std::exception& e) {
    if (error) *error = std::string("writing '") + path + "': " + e.what();
    return false;
  }
}

}  // namespace rig_sim
