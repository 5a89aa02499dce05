// The subscriber plugin's callback on good and corrupt messages: a corrupt frame is counted and
// skipped (the user callback never sees it), and the next good frame still arrives.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "compressed_transport/compressed_subscriber.h"
#include "compressed_transport/core/codec.h"

namespace {
// internalCallback is protected: a test subclass calls it without a master.
class TestableSubscriber : public compressed_transport::CompressedSubscriber {
 public:
  void Feed(const sensor_msgs::CompressedImage::ConstPtr& m, const Callback& cb) { internalCallback(m, cb); }
};

sensor_msgs::CompressedImage::Ptr GoodFrame() {
  cv::Mat rgb(30, 40, CV_8UC3, cv::Scalar(10, 120, 250));
  compressed_transport::EncodedImage enc;
  std::string err;
  EXPECT_TRUE(compressed_transport::Encode(rgb, "rgb8", compressed_transport::EncodeConfig(), &enc, &err)) << err;
  auto m = boost::make_shared<sensor_msgs::CompressedImage>();
  m->header.frame_id = "camera_optical";
  m->header.stamp = ros::Time(12, 5);
  m->format = enc.format;
  m->data = enc.data;
  return m;
}
}  // namespace

TEST(CompressedSubscriber, CorruptFrameCountedAndSkipped) {
  TestableSubscriber sub;
  std::vector<sensor_msgs::ImageConstPtr> received;
  auto cb = [&](const sensor_msgs::ImageConstPtr& img) { received.push_back(img); };

  sub.Feed(GoodFrame(), cb);
  ASSERT_EQ(received.size(), 1u);
  EXPECT_EQ(received[0]->encoding, "rgb8");
  EXPECT_EQ(received[0]->width, 40u);
  EXPECT_EQ(received[0]->height, 30u);
  EXPECT_EQ(received[0]->header.frame_id, "camera_optical");
  EXPECT_EQ(received[0]->header.stamp, ros::Time(12, 5));
  EXPECT_NEAR(received[0]->data[0], 10, 3);  // R first: rgb8 restored from the BGR JPEG
  EXPECT_EQ(sub.undecodable_frames(), 0u);

  auto corrupt = GoodFrame();
  corrupt->data.resize(20);  // truncated in transit
  sub.Feed(corrupt, cb);
  auto garbage = GoodFrame();
  std::fill(garbage->data.begin(), garbage->data.end(), 0x5A);
  sub.Feed(garbage, cb);
  EXPECT_EQ(received.size(), 1u);
  EXPECT_EQ(sub.undecodable_frames(), 2u);

  sub.Feed(GoodFrame(), cb);
  EXPECT_EQ(received.size(), 2u);
  EXPECT_EQ(sub.undecodable_frames(), 2u);
}
