// The zero-copy pool: each stream buffer *is* the data vector of a
// sensor_msgs/Image. Aravis writes a frame straight into the message's memory
// (arv_buffer_new_full with preallocated data), the driver publishes that
// message as an ImageConstPtr whose deleter hands the buffer back to the
// stream, and a nodelet in the same manager receives the same pointer. The
// buffer is reused only after its last holder lets go.
//
// sensor_msgs::Image is a plain data type here, not the ROS runtime: the
// message has to be the buffer for the frame to travel without a copy.
#pragma once

#include <arv.h>
#include <sensor_msgs/Image.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

namespace aravis_camera {

class FramePool : public std::enable_shared_from_this<FramePool> {
 public:
  // Takes over the caller's reference to `stream`. Allocates n buffers of payload_bytes.
  static std::shared_ptr<FramePool> Create(ArvStream* stream, size_t n_buffers, size_t payload_bytes);
  ~FramePool();
  FramePool(const FramePool&) = delete;
  FramePool& operator=(const FramePool&) = delete;

  // Pushes every buffer into the stream. Call once, before acquisition starts.
  void Prime();

  // The stream, for popping completed buffers (from the acquisition thread only).
  ArvStream* stream() const { return stream_; }

  // Wraps a buffer popped from the stream: returns the message that owns its
  // memory, with a deleter that gives the buffer back. The caller fills the
  // header and image fields before publishing. nullptr if `buffer` is not ours.
  sensor_msgs::ImagePtr Wrap(ArvBuffer* buffer);

  // Gives a popped buffer back without publishing it.
  void Recycle(ArvBuffer* buffer);

  // Detaches from the stream (the camera is being closed): buffers still held
  // by subscribers are freed when they come back instead of being re-queued.
  void Close();

  // Frames currently held outside the stream (published, not yet released).
  int in_flight() const { return in_flight_.load(); }

  // True if `data` is the memory of a buffer of any live pool in this process:
  // how a consumer proves it got the frame without a copy.
  static bool IsPoolMemory(const void* data);

 private:
  friend struct ReturnToPool;
  struct Slot {
    sensor_msgs::Image image;
    ArvBuffer* buffer = nullptr;
  };
  FramePool() = default;
  void Return(Slot* slot);
  Slot* FindSlot(ArvBuffer* buffer);

  std::mutex mutex_;  // guards stream_ against Return() from subscriber threads
  ArvStream* stream_ = nullptr;
  std::vector<std::unique_ptr<Slot>> slots_;
  std::atomic<int> in_flight_{0};
};

}  // namespace aravis_camera
