// image_transport subscriber plugin "compressed": decodes <topic>/compressed (JPEG or PNG, the format
// string of compressed_image_transport) back into sensor_msgs/Image. See compressed_publisher.h for why
// this is not the upstream library. A frame that does not decode is counted and skipped, with one
// throttled warning naming the topic and the count.
#pragma once

#include <cstdint>
#include <mutex>
#include <string>

#include <image_transport/simple_subscriber_plugin.h>
#include <sensor_msgs/CompressedImage.h>

namespace compressed_transport {

class CompressedSubscriber : public image_transport::SimpleSubscriberPlugin<sensor_msgs::CompressedImage> {
 public:
  std::string getTransportName() const override { return "compressed"; }
  // Frames received that did not decode (skipped), since subscribing.
  uint64_t undecodable_frames() const;

 protected:
  void internalCallback(const sensor_msgs::CompressedImage::ConstPtr& message, const Callback& user_cb) override;

 private:
  mutable std::mutex mutex_;  // callbacks may run on several spinner threads
  uint64_t undecodable_ = 0;
};

}  // namespace compressed_transport
