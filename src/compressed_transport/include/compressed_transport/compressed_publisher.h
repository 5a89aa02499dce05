// image_transport publisher plugin "compressed": sensor_msgs/CompressedImage on <topic>/compressed.
//
// Why not the library: ros-perception's compressed_image_transport (image_transport_plugins) is the
// standard plugin, but Debian bookworm does not package it, and this project installs only Debian
// packages. This is a small re-implementation on OpenCV's imencode/imdecode with the same lookup
// name (image_transport/compressed_pub), topic, format string and parameters (<topic>/compressed/
// format, jpeg_quality,
// jpeg_progressive, jpeg_optimize, jpeg_restart_interval, png_level, also through dynamic_reconfigure), so a stock ROS
// install on another machine decodes its messages. Do not install both on one machine: the lookup names clash.
#pragma once

#include <memory>
#include <mutex>
#include <string>

#include <dynamic_reconfigure/server.h>
#include <image_transport/simple_publisher_plugin.h>
#include <sensor_msgs/CompressedImage.h>

#include "compressed_transport/CompressedPublisherConfig.h"
#include "compressed_transport/core/codec.h"

namespace compressed_transport {

class CompressedPublisher : public image_transport::SimplePublisherPlugin<sensor_msgs::CompressedImage> {
 public:
  std::string getTransportName() const override { return "compressed"; }

 protected:
  void advertiseImpl(ros::NodeHandle& nh, const std::string& base_topic, uint32_t queue_size,
                     const image_transport::SubscriberStatusCallback& user_connect_cb,
                     const image_transport::SubscriberStatusCallback& user_disconnect_cb,
                     const ros::VoidPtr& tracked_object, bool latch) override;
  void publish(const sensor_msgs::Image& message, const PublishFn& publish_fn) const override;

 private:
  using ReconfigureServer = dynamic_reconfigure::Server<CompressedPublisherConfig>;
  void OnReconfigure(CompressedPublisherConfig& config, uint32_t level);

  std::unique_ptr<ReconfigureServer> reconfigure_server_;
  mutable std::mutex mutex_;  // config_ is written by dynamic_reconfigure's thread, read by publishers
  EncodeConfig config_;
  mutable uint64_t failures_ = 0;  // frames that could not be encoded (under mutex_)
};

}  // namespace compressed_transport
