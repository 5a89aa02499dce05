// Maps camera (device) timestamps to the host clock.
//
// Why: the host time at which a frame arrives carries the network's and the
// scheduler's jitter (hundreds of µs to ms), which would reach the EKF as
// pose-time noise. The camera's own exposure timestamps are regular but on
// another clock. Each frame gives one sample of offset = host − device, which
// is the true clock offset plus a non-negative transport delay; the minimum
// over a sliding window is the least-delayed frame, so
//   stamp = device + min(offset over the last `window` frames)
// keeps the device's regularity on the host's clock (a minimum-delay filter,
// as NTP's clock filter and many sensor drivers do). A device clock that jumps
// (camera reset) or an offset that moves by more than `max_jump_ns` resets the
// window.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>

namespace aravis_camera {

class TimestampMapper {
 public:
  explicit TimestampMapper(size_t window = 64, int64_t max_jump_ns = 500'000'000);

  // Adds the observation and returns the device time on the host clock (ns).
  int64_t Map(uint64_t device_ns, int64_t host_ns);
  void Reset();
  size_t resets() const { return resets_; }

 private:
  size_t window_;
  int64_t max_jump_ns_;
  std::deque<int64_t> offsets_ns_;
  uint64_t last_device_ns_ = 0;
  size_t resets_ = 0;
};

}  // namespace aravis_camera
