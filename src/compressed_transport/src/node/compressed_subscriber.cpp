#include "compressed_transport/compressed_subscriber.h"

#include <cv_bridge/cv_bridge.h>

#include "compressed_transport/core/codec.h"

namespace compressed_transport {

uint64_t CompressedSubscriber::undecodable_frames() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return undecodable_;
}

void CompressedSubscriber::internalCallback(const sensor_msgs::CompressedImage::ConstPtr& message,
                                            const Callback& user_cb) {
  DecodedImage decoded;
  std::string error;
  if (!Decode(message->format, message->data, &decoded, &error)) {
    uint64_t n;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      n = ++undecodable_;
    }
    ROS_WARN_THROTTLE(5.0, "%s: %lu compressed frame(s) did not decode and were skipped; last: %s", getTopic().c_str(),
                      static_cast<unsigned long>(n), error.c_str());
    return;
  }
  cv_bridge::CvImage image(message->header, decoded.encoding, decoded.image);
  user_cb(image.toImageMsg());
}

}  // namespace compressed_transport
