// Renders a scenario's camera frames 0, 1, 2, ... into freshly allocated
// image messages on a worker thread, a few frames ahead of the consumer, so
// rendering overlaps serialisation, disk writes or publishing.
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <string>
#include <thread>

#include "rig_sim/ros/messages.h"
#include "rig_sim/sim_stream.h"

namespace rig_sim {

class FramePipeline {
 public:
  FramePipeline(const SimStream& stream, double start_time_s, const std::string& frame_id, uint64_t count)
      : stream_(stream), start_time_s_(start_time_s), frame_id_(frame_id), count_(count), worker_([this] { Run(); }) {}
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
      sensor_msgs::ImagePtr img = MakeEmptyImage(s.camera, StampAt(start_time_s_, ev.stamp_s), frame_id_);
      const auto t0 = std::chrono::steady_clock::now();
      stream_.RenderFrame(ev, img->data.data());
      render_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::lock_guard<std::mutex> lock(mutex_);
      queue_.push_back(img);
      cv_.notify_all();
    }
  }

  const SimStream& stream_;
  const double start_time_s_;
  const std::string frame_id_;
  const uint64_t count_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<sensor_msgs::ImagePtr> queue_;
  bool stop_ = false;
  double render_s_ = 0.0;
  std::thread worker_;  // last: starts after the members above exist
};

// Number of frames in the scenario (stamps n / rate below the duration).
inline uint64_t FrameCount(const Scenario& s) {
  uint64_t n = 0;
  while (n / s.camera.rate_hz < s.trajectory.duration_s) ++n;
  return n;
}

}  // namespace rig_sim
