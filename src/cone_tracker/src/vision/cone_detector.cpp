#include "cone_tracker/vision/cone_detector.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace cone_tracker {
namespace {

// The frame as 8-bit BGR for the DNN (shared, not copied, when it is bgr8 already).
cv::Mat ToBgr(const ImageView& im) {
  const cv::Mat src(im.height, im.width, im.encoding == "rgb8" || im.encoding == "bgr8" ? CV_8UC3 : CV_8UC1,
                    const_cast<uint8_t*>(im.data), size_t(im.step));
  cv::Mat bgr;
  if (im.encoding == "bgr8") return src;
  if (im.encoding == "rgb8") cv::cvtColor(src, bgr, cv::COLOR_RGB2BGR);
  // OpenCV names a Bayer pattern by its second row's first two pixels.
  else if (im.encoding == "bayer_rggb8")
    cv::cvtColor(src, bgr, cv::COLOR_BayerBG2BGR);
  else if (im.encoding == "bayer_bggr8")
    cv::cvtColor(src, bgr, cv::COLOR_BayerRG2BGR);
  else if (im.encoding == "bayer_gbrg8")
    cv::cvtColor(src, bgr, cv::COLOR_BayerGR2BGR);
  else if (im.encoding == "bayer_grbg8")
    cv::cvtColor(src, bgr, cv::COLOR_BayerGB2BGR);
  return bgr;
}

// The share of the box's pixels that the colour table classified as cone (mask: full-size, row-major).
double ColourFraction(const std::vector<uint8_t>& mask, int width, int height, const DnnBox& d) {
  const int x0 = std::max(0, int(d.x)), y0 = std::max(0, int(d.y));
  const int x1 = std::min(width, int(d.x + d.w)), y1 = std::min(height, int(d.y + d.h));
  if (x1 <= x0 || y1 <= y0 || mask.size() < size_t(width) * height) return 0.0;
  size_t on = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) on += mask[size_t(y) * width + x] != 0;
  return double(on) / (double(x1 - x0) * (y1 - y0));
}

double BlobIou(const Blob& b, const DnnBox& d) {
  return BoxIou({double(b.bbox_x), double(b.bbox_y), double(b.bbox_w), double(b.bbox_h), 0.0}, d);
}

}  // namespace

std::string DetectorKindName(DetectorKind kind) { return kind == DetectorKind::kDnn ? "dnn" : "colour"; }

std::string ConeDetectorConfig::Validate() const {
  if (detector < 0 || detector >= kDetectorKinds) return "detector must be colour or dnn";
  if (!(dnn_score_min > 0.0 && dnn_score_min < 1.0)) return "dnn_score_min must be in (0, 1)";
  if (!(dnn_min_colour_frac >= 0.0 && dnn_min_colour_frac <= 1.0)) return "dnn_min_colour_frac must be in [0, 1]";
  return "";
}

std::string DefaultDnnModelFile() { return std::string(CONE_TRACKER_MODEL_DIR) + "/cone_detector.onnx"; }

ConeDetector::ConeDetector(const SegmenterConfig& segmenter, const ConeDetectorConfig& config)
    : config_(config), segmenter_(segmenter) {
  const std::string bad = config.Validate();
  if (!bad.empty()) throw std::invalid_argument(bad);
  if (config.kind() == DetectorKind::kDnn) {
    DnnDetectorConfig dc;
    dc.model_file = config.dnn_model.empty() ? DefaultDnnModelFile() : config.dnn_model;
    dc.score_min = config.dnn_score_min;
    dnn_ = std::make_unique<DnnDetector>(dc);
  }
}

void ConeDetector::SetConfig(const SegmenterConfig& segmenter, double dnn_score_min) {
  ConeDetectorConfig c = config_;
  c.dnn_score_min = dnn_score_min;
  const std::string bad = c.Validate();
  if (!bad.empty()) throw std::invalid_argument(bad);
  segmenter_.SetConfig(segmenter);
  if (dnn_) dnn_->SetThresholds(dnn_score_min, dnn_->config().nms_iou);
  config_ = c;
}

ConeDetectorResult ConeDetector::Process(const ImageView& image, const CameraModel& camera) {
  ConeDetectorResult r;
  r.segmentation = segmenter_.Process(image, camera);
  if (r.segmentation.ok && dnn_) {
    AddDnnCones(image, camera, &r);
  } else {
    r.scores.assign(r.segmentation.cones.size(), 1.0);
    r.points_from_colour.assign(r.segmentation.cones.size(), true);
  }
  return r;
}

void ConeDetector::AddDnnCones(const ImageView& image, const CameraModel& camera, ConeDetectorResult* r) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<DnnBox> boxes = dnn_->Detect(ToBgr(image));
  r->dnn_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  const std::vector<ConeDetection> colour = std::move(r->segmentation.cones);
  std::vector<bool> used(colour.size(), false);
  r->segmentation.cones.clear();
  for (const DnnBox& box : boxes) {  // in score order: the surer box takes the blob
    int best = -1;
    double best_iou = 0.5;
    for (size_t i = 0; i < colour.size(); ++i) {
      const double iou = BlobIou(colour[i].blob, box);
      if (!used[i] && iou >= best_iou) best = int(i), best_iou = iou;
    }
    ConeDetection det;
    if (best >= 0) {
      used[best] = true;
      det = colour[best];
    } else {  // the box's own points: apex at the top centre, base at the bottom centre
      if (ColourFraction(segmenter_.mask(), image.width, image.height, box) < config_.dnn_min_colour_frac) continue;
      det.peak_px = {box.x + box.w / 2, box.y};
      det.mid_px = {box.x + box.w / 2, box.y + box.h / 2};
      det.base_px = {box.x + box.w / 2, box.y + box.h};
      det.blob.centroid = det.mid_px;
      std::vector<Eigen::Vector2d> pts = {det.peak_px, det.mid_px, det.base_px};
      if (!UndistortPixels(camera, &pts)) continue;  // outside the lens model's range
      det.peak_undist_px = pts[0], det.mid_undist_px = pts[1], det.base_undist_px = pts[2];
    }
    det.blob.bbox_x = int(std::lround(box.x)), det.blob.bbox_y = int(std::lround(box.y));
    det.blob.bbox_w = int(std::lround(box.w)), det.blob.bbox_h = int(std::lround(box.h));
    r->segmentation.cones.push_back(det);
    r->scores.push_back(box.score);
    r->points_from_colour.push_back(best >= 0);
  }
}

}  // namespace cone_tracker
