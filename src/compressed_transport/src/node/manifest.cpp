#include <pluginlib/class_list_macros.hpp>

#include "compressed_transport/compressed_publisher.h"
#include "compressed_transport/compressed_subscriber.h"

PLUGINLIB_EXPORT_CLASS(compressed_transport::CompressedPublisher, image_transport::PublisherPlugin)
PLUGINLIB_EXPORT_CLASS(compressed_transport::CompressedSubscriber, image_transport::SubscriberPlugin)
