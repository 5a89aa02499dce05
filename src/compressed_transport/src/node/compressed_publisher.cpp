#include "compressed_transport/compressed_publisher.h"

#include <cv_bridge/cv_bridge.h>

namespace compressed_transport {

void CompressedPublisher::advertiseImpl(ros::NodeHandle& nh, const std::string& base_topic, uint32_t queue_size,
                                        const image_transport::SubscriberStatusCallback& user_connect_cb,
                                        const image_transport::SubscriberStatusCallback& user_disconnect_cb,
                                        const ros::VoidPtr& tracked_object, bool latch) {
  SimplePublisherPlugin::advertiseImpl(nh, base_topic, queue_size, user_connect_cb, user_disconnect_cb, tracked_object,
                                       latch);
  // nh() is <topic>/compressed: the server reads format, jpeg_quality and png_level from there.
  reconfigure_server_ = std::make_unique<ReconfigureServer>(this->nh());
  reconfigure_server_->setCallback([this](CompressedPublisherConfig& c, uint32_t level) { OnReconfigure(c, level); });
}

void CompressedPublisher::OnReconfigure(CompressedPublisherConfig& config, uint32_t /*level*/) {
  EncodeConfig next;
  if (!ParseCodec(config.format, &next.codec)) {
    // dynamic_reconfigure clamps numbers, not enum strings: a rosparam can still hold anything.
    ROS_ERROR("%s/format: '%s' is not a compressed format (jpeg or png); keeping %s", this->nh().getNamespace().c_str(),
              config.format.c_str(), config_.codec == Codec::kJpeg ? "jpeg" : "png");
    std::lock_guard<std::mutex> lock(mutex_);
    config.format = config_.codec == Codec::kJpeg ? "jpeg" : "png";
    next.codec = config_.codec;
  }
  next.jpeg_quality = config.jpeg_quality;
  next.jpeg_optimize = config.jpeg_optimize;
  next.jpeg_progressive = config.jpeg_progressive;
  next.jpeg_restart_interval = config.jpeg_restart_interval;
  next.png_level = config.png_level;
  std::lock_guard<std::mutex> lock(mutex_);
  config_ = next;
}

void CompressedPublisher::publish(const sensor_msgs::Image& message, const PublishFn& publish_fn) const {
  EncodeConfig config;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    config = config_;
  }
  cv_bridge::CvImageConstPtr cv;
  try {
    // toCvShare needs a shared pointer; the Image stays alive for this call, so share without owning it.
    cv = cv_bridge::toCvShare(message, boost::shared_ptr<const void>());
  } catch (const cv_bridge::Exception& e) {
    ROS_WARN_THROTTLE(5.0, "%s: image not compressed: %s", getTopic().c_str(), e.what());
    return;
  }
  auto compressed = boost::make_shared<sensor_msgs::CompressedImage>();
  EncodedImage encoded;
  std::string error;
  if (!Encode(cv->image, message.encoding, config, &encoded, &error)) {
    uint64_t n;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      n = ++failures_;
    }
    ROS_WARN_THROTTLE(5.0, "%s: %lu image(s) not compressed: %s", getTopic().c_str(), static_cast<unsigned long>(n),
                      error.c_str());
    return;
  }
  compressed->header = message.header;
  compressed->format = std::move(encoded.format);
  compressed->data = std::move(encoded.data);
  publish_fn(*compressed);
}

}  // namespace compressed_transport
