#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "compressed_transport/core/codec.h"

using compressed_transport::Codec;
using compressed_transport::DecodedImage;
using compressed_transport::EncodeConfig;
using compressed_transport::EncodedImage;

namespace {
// A textured colour image: gradients and shapes, so a channel swap or a lossy mistake shows.
cv::Mat TestImage(int type = CV_8UC3) {
  cv::Mat img(48, 64, CV_8UC3);
  for (int v = 0; v < img.rows; ++v)
    for (int u = 0; u < img.cols; ++u) img.at<cv::Vec3b>(v, u) = cv::Vec3b(u * 4, v * 5, 200);  // R, G, B in rgb8
  cv::circle(img, {32, 24}, 10, cv::Scalar(255, 120, 0), -1);
  if (type == CV_8UC1) cv::cvtColor(img, img, cv::COLOR_RGB2GRAY);
  return img;
}

double MeanAbsDiff(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat d;
  cv::absdiff(a, b, d);
  const cv::Scalar s = cv::mean(d);
  return (s[0] + s[1] + s[2] + s[3]) / a.channels();
}
}  // namespace

TEST(FormatString, UpstreamConventions) {
  std::string err;
  EXPECT_EQ(compressed_transport::FormatString("rgb8", Codec::kJpeg, &err), "rgb8; jpeg compressed bgr8");
  EXPECT_EQ(compressed_transport::FormatString("bgr8", Codec::kPng, &err), "bgr8; png compressed bgr8");
  EXPECT_EQ(compressed_transport::FormatString("mono8", Codec::kJpeg, &err), "mono8; jpeg compressed ");
  EXPECT_EQ(compressed_transport::FormatString("rgb16", Codec::kPng, &err), "rgb16; png compressed bgr16");
  EXPECT_EQ(compressed_transport::FormatString("bayer_rggb8", Codec::kPng, &err), "bayer_rggb8; png compressed ");
}

TEST(FormatString, RefusesWhatTheCodecCannotCarry) {
  std::string err;
  EXPECT_EQ(compressed_transport::FormatString("mono16", Codec::kJpeg, &err), "");
  EXPECT_NE(err.find("mono16"), std::string::npos) << err;
  err.clear();
  EXPECT_EQ(compressed_transport::FormatString("32FC1", Codec::kPng, &err), "");
  EXPECT_NE(err.find("32FC1"), std::string::npos) << err;
  Codec c;
  EXPECT_TRUE(compressed_transport::ParseCodec("png", &c));
  EXPECT_EQ(c, Codec::kPng);
  EXPECT_FALSE(compressed_transport::ParseCodec("theora", &c));
}

TEST(RoundTrip, PngIsLosslessAndKeepsRgbOrder) {
  const cv::Mat rgb = TestImage();
  EncodeConfig config;
  config.codec = Codec::kPng;
  EncodedImage enc;
  DecodedImage dec;
  std::string err;
  ASSERT_TRUE(compressed_transport::Encode(rgb, "rgb8", config, &enc, &err)) << err;
  EXPECT_EQ(enc.format, "rgb8; png compressed bgr8");
  ASSERT_TRUE(compressed_transport::Decode(enc.format, enc.data, &dec, &err)) << err;
  EXPECT_EQ(dec.encoding, "rgb8");
  ASSERT_EQ(dec.image.type(), CV_8UC3);
  EXPECT_EQ(MeanAbsDiff(rgb, dec.image), 0.0);
  // The file itself is BGR (what a stock decoder expects): its first pixel's blue is the image's B = 200.
  const cv::Mat file = cv::imdecode(enc.data, cv::IMREAD_UNCHANGED);
  EXPECT_EQ(file.at<cv::Vec3b>(0, 0)[0], 200);
}

TEST(RoundTrip, Png16BitMono) {
  cv::Mat mono16(20, 30, CV_16UC1);
  cv::randu(mono16, 0, 65535);
  EncodeConfig config;
  config.codec = Codec::kPng;
  EncodedImage enc;
  DecodedImage dec;
  std::string err;
  ASSERT_TRUE(compressed_transport::Encode(mono16, "mono16", config, &enc, &err)) << err;
  ASSERT_TRUE(compressed_transport::Decode(enc.format, enc.data, &dec, &err)) << err;
  EXPECT_EQ(dec.encoding, "mono16");
  ASSERT_EQ(dec.image.type(), CV_16UC1);
  EXPECT_EQ(cv::norm(mono16, dec.image, cv::NORM_INF), 0.0);
}

TEST(RoundTrip, JpegCloseAndQualityMatters) {
  const cv::Mat rgb = TestImage();
  EncodeConfig config;
  EncodedImage enc80, enc20;
  DecodedImage dec;
  std::string err;
  ASSERT_TRUE(compressed_transport::Encode(rgb, "rgb8", config, &enc80, &err)) << err;
  EXPECT_EQ(enc80.format, "rgb8; jpeg compressed bgr8");
  ASSERT_TRUE(compressed_transport::Decode(enc80.format, enc80.data, &dec, &err)) << err;
  EXPECT_EQ(dec.encoding, "rgb8");
  EXPECT_LT(MeanAbsDiff(rgb, dec.image), 8.0);  // lossy (4:2:0 chroma), but not a channel swap (~60)
  config.jpeg_quality = 20;
  ASSERT_TRUE(compressed_transport::Encode(rgb, "rgb8", config, &enc20, &err)) << err;
  EXPECT_LT(enc20.data.size(), enc80.data.size());
}

TEST(RoundTrip, JpegMonoAndRgba) {
  const cv::Mat mono = TestImage(CV_8UC1);
  EncodedImage enc;
  DecodedImage dec;
  std::string err;
  ASSERT_TRUE(compressed_transport::Encode(mono, "mono8", EncodeConfig(), &enc, &err)) << err;
  ASSERT_TRUE(compressed_transport::Decode(enc.format, enc.data, &dec, &err)) << err;
  EXPECT_EQ(dec.encoding, "mono8");
  EXPECT_EQ(dec.image.type(), CV_8UC1);
  cv::Mat rgba;
  cv::cvtColor(TestImage(), rgba, cv::COLOR_RGB2RGBA);
  ASSERT_TRUE(compressed_transport::Encode(rgba, "rgba8", EncodeConfig(), &enc, &err)) << err;
  EXPECT_EQ(enc.format, "rgba8; jpeg compressed bgr8");
  ASSERT_TRUE(compressed_transport::Decode(enc.format, enc.data, &dec, &err)) << err;
  EXPECT_EQ(dec.image.type(), CV_8UC4);
  EXPECT_LT(MeanAbsDiff(rgba, dec.image), 8.0);
}

TEST(Decode, OldStyleFormatString) {
  // Publishers before the "enc; codec compressed target" convention sent just "jpeg": BGR pixels.
  cv::Mat bgr = TestImage();
  std::vector<uint8_t> data;
  ASSERT_TRUE(cv::imencode(".png", bgr, data));
  DecodedImage dec;
  std::string err;
  ASSERT_TRUE(compressed_transport::Decode("png", data, &dec, &err)) << err;
  EXPECT_EQ(dec.encoding, "bgr8");
  EXPECT_EQ(MeanAbsDiff(bgr, dec.image), 0.0);
}

TEST(Decode, RefusesBadPayloadsWithReasons) {
  DecodedImage dec;
  std::string err;
  EXPECT_FALSE(compressed_transport::Decode("rgb8; jpeg compressed bgr8", {}, &dec, &err));
  EXPECT_NE(err.find("empty"), std::string::npos) << err;
  EXPECT_FALSE(compressed_transport::Decode("rgb8; jpeg compressed bgr8", {1, 2, 3, 4, 5}, &dec, &err));
  EXPECT_NE(err.find("5 bytes"), std::string::npos) << err;
  // A valid mono PNG that claims to be rgb8.
  std::vector<uint8_t> data;
  ASSERT_TRUE(cv::imencode(".png", TestImage(CV_8UC1), data));
  EXPECT_FALSE(compressed_transport::Decode("rgb8; png compressed bgr8", data, &dec, &err));
  EXPECT_NE(err.find("1"), std::string::npos) << err;
  EXPECT_FALSE(compressed_transport::Decode("32FC1; png compressed ", data, &dec, &err));
  EXPECT_NE(err.find("32FC1"), std::string::npos) << err;
}

TEST(Encode, RefusesMismatchedImage) {
  EncodedImage enc;
  std::string err;
  EXPECT_FALSE(compressed_transport::Encode(TestImage(CV_8UC1), "rgb8", EncodeConfig(), &enc, &err));
  EXPECT_NE(err.find("rgb8"), std::string::npos) << err;
}
