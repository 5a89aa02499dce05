#include "aravis_camera/core/timestamp_mapper.h"

#include <algorithm>
#include <cstdlib>

namespace aravis_camera {

TimestampMapper::TimestampMapper(size_t window, int64_t max_jump_ns)
    : window_(std::max<size_t>(window, 1)), max_jump_ns_(max_jump_ns) {}

void TimestampMapper::Reset() {
  offsets_ns_.clear();
  last_device_ns_ = 0;
}

int64_t TimestampMapper::Map(uint64_t device_ns, int64_t host_ns) {
  const int64_t offset = host_ns - static_cast<int64_t>(device_ns);
  if (!offsets_ns_.empty()) {
    const int64_t current = *std::min_element(offsets_ns_.begin(), offsets_ns_.end());
    if (device_ns <= last_device_ns_ || std::llabs(offset - current) > max_jump_ns_) {
      Reset();
      ++resets_;
    }
  }
  offsets_ns_.push_back(offset);
  if (offsets_ns_.size() > window_) offsets_ns_.pop_front();
  last_device_ns_ = device_ns;
  return static_cast<int64_t>(device_ns) + *std::min_element(offsets_ns_.begin(), offsets_ns_.end());
}

}  // namespace aravis_camera
