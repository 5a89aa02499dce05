#include "cone_tracker/vision/dnn_detector.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace cone_tracker {

std::string DnnDetectorConfig::Validate() const {
  if (model_file.empty()) return "dnn_model must name an ONNX file";
  if (!(score_min > 0.0 && score_min < 1.0)) return "dnn_score_min must be in (0, 1)";
  if (!(nms_iou > 0.0 && nms_iou <= 1.0)) return "dnn_nms_iou must be in (0, 1]";
  if (!(contain_frac > 0.0)) return "DnnDetectorConfig.contain_frac must be > 0";
  if (!(contain_axis_frac >= 0.0)) return "DnnDetectorConfig.contain_axis_frac must be >= 0";
  return "";
}

DnnDetector::DnnDetector(const DnnDetectorConfig& config) : config_(config) {
  const std::string bad = config.Validate();
  if (!bad.empty()) throw std::invalid_argument(bad);
  const std::string& file = config.model_file;
  if (!std::ifstream(file, std::ios::binary)) throw std::runtime_error("cone detector model " + file + ": cannot open");
  try {
    net_ = cv::dnn::readNetFromONNX(file);
  } catch (const cv::Exception& e) {
    throw std::runtime_error("cone detector model " + file + ": not a model OpenCV can load: " + e.what());
  }
  if (net_.empty()) throw std::runtime_error("cone detector model " + file + ": not a model OpenCV can load");
  // One forward pass checks the input and output shapes the decoder assumes.
  cv::Mat probe;
  try {
    net_.setInput(cv::Mat(std::vector<int>{1, 3, kDnnInputPx, kDnnInputPx}, CV_32F, cv::Scalar(0.5)));
    probe = net_.forward();
  } catch (const cv::Exception& e) {
    throw std::runtime_error("cone detector model " + file + ": does not take a 1x3x" + std::to_string(kDnnInputPx) +
                             "x" + std::to_string(kDnnInputPx) + " image: " + e.what());
  }
  const int grid = kDnnInputPx / kDnnStride;
  if (probe.dims != 4 || probe.size[1] != kDnnChannels || probe.size[2] != grid || probe.size[3] != grid) {
    throw std::runtime_error("cone detector model " + file + ": output is not 1x" + std::to_string(kDnnChannels) + "x" +
                             std::to_string(grid) + "x" + std::to_string(grid));
  }
}

void DnnDetector::SetThresholds(double score_min, double nms_iou) {
  DnnDetectorConfig c = config_;
  c.score_min = score_min;
  c.nms_iou = nms_iou;
  const std::string bad = c.Validate();
  if (!bad.empty()) throw std::invalid_argument(bad);
  config_ = c;
}

std::vector<DnnBox> DnnDetector::Detect(const cv::Mat& bgr) {
  if (bgr.empty() || bgr.type() != CV_8UC3)
    throw std::invalid_argument("DnnDetector::Detect: needs an 8-bit BGR image");
  // Letterbox as train_cone_detector.py: long side to kDnnInputPx, top-left, grey padding.
  const double scale = double(kDnnInputPx) / std::max(bgr.cols, bgr.rows);
  const int w = std::max(1, int(std::lround(bgr.cols * scale))), h = std::max(1, int(std::lround(bgr.rows * scale)));
  cv::Mat input(kDnnInputPx, kDnnInputPx, CV_8UC3, cv::Scalar::all(kDnnPadGrey));
  cv::resize(bgr, input(cv::Rect(0, 0, w, h)), cv::Size(w, h), 0, 0, scale < 1.0 ? cv::INTER_AREA : cv::INTER_LINEAR);
  const auto run = [&](const cv::Mat& letterboxed, double score_min) {
    net_.setInput(cv::dnn::blobFromImage(letterboxed, 1.0 / 255.0, cv::Size(), cv::Scalar(), /*swapRB=*/true));
    const cv::Mat out = net_.forward();
    return DecodeDnnHeads(out.ptr<float>(), out.size[2], out.size[3], scale, bgr.cols, bgr.rows, score_min,
                          config_.nms_iou);
  };
  std::vector<DnnBox> boxes;
  if (!config_.flip_average) {
    boxes = run(input, config_.score_min);
  } else {
    // The mirror image: the photo's part of the letterbox flipped, the padding where it was.
    cv::Mat mirrored = input.clone();
    cv::flip(input(cv::Rect(0, 0, w, h)), mirrored(cv::Rect(0, 0, w, h)), 1);
    std::vector<DnnBox> back = run(mirrored, config_.score_min / 2);
    const double width_px = w / scale;  // the photo's width as the network saw it, in image pixels
    for (DnnBox& b : back) b.x = std::clamp(width_px - (b.x + b.w), 0.0, double(bgr.cols));
    boxes = SuppressOverlaps(FuseMirroredViews(run(input, config_.score_min / 2), back, config_.score_min),
                             config_.nms_iou);
  }
  return MergeContainedBoxes(std::move(boxes), config_.contain_frac, config_.contain_axis_frac);
}

std::vector<DnnBox> DecodeDnnHeads(const float* heads, int grid_h, int grid_w, double scale, int image_w, int image_h,
                                   double score_min, double nms_iou) {
  const size_t plane = size_t(grid_h) * grid_w;
  const float* heat = heads;
  std::vector<DnnBox> boxes;
  for (int y = 0; y < grid_h; ++y) {
    for (int x = 0; x < grid_w; ++x) {
      const float v = heat[size_t(y) * grid_w + x];
      if (v < score_min) continue;
      bool peak = true;  // 3x3 local maximum (ties kept, as max_pool2d == heat in training)
      for (int dy = -1; dy <= 1 && peak; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int yy = y + dy, xx = x + dx;
          if (yy >= 0 && xx >= 0 && yy < grid_h && xx < grid_w && heat[size_t(yy) * grid_w + xx] > v) peak = false;
        }
      if (!peak) continue;
      const size_t i = size_t(y) * grid_w + x;
      const double bw = kDnnStride * std::exp(heads[plane + i]), bh = kDnnStride * std::exp(heads[2 * plane + i]);
      const double cx = kDnnStride * (x + heads[3 * plane + i]), cy = kDnnStride * (y + heads[4 * plane + i]);
      const double x0 = std::clamp((cx - bw / 2) / scale, 0.0, double(image_w));
      const double y0 = std::clamp((cy - bh / 2) / scale, 0.0, double(image_h));
      const double x1 = std::clamp((cx + bw / 2) / scale, 0.0, double(image_w));
      const double y1 = std::clamp((cy + bh / 2) / scale, 0.0, double(image_h));
      if (x1 - x0 < 1.0 || y1 - y0 < 1.0) continue;  // centre in the padding
      boxes.push_back({x0, y0, x1 - x0, y1 - y0, v});
    }
  }
  return SuppressOverlaps(std::move(boxes), nms_iou);
}

double BoxIou(const DnnBox& a, const DnnBox& b) {
  const double ix = std::max(0.0, std::min(a.x + a.w, b.x + b.w) - std::max(a.x, b.x));
  const double iy = std::max(0.0, std::min(a.y + a.h, b.y + b.h) - std::max(a.y, b.y));
  const double inter = ix * iy, uni = a.w * a.h + b.w * b.h - inter;
  return uni > 0 ? inter / uni : 0.0;
}

std::vector<DnnBox> FuseMirroredViews(const std::vector<DnnBox>& image_view, const std::vector<DnnBox>& mirror_view,
                                      double score_min) {
  std::vector<bool> taken(mirror_view.size(), false);
  std::vector<DnnBox> fused;
  const auto keep = [&](const DnnBox& b) {
    if (b.score >= score_min) fused.push_back(b);
  };
  for (const DnnBox& a : image_view) {  // both lists are in score order (DecodeDnnHeads)
    int best = -1;
    double best_iou = 0.5;
    for (size_t j = 0; j < mirror_view.size(); ++j) {
      const double iou = BoxIou(a, mirror_view[j]);
      if (!taken[j] && iou >= best_iou) best = int(j), best_iou = iou;
    }
    if (best < 0) {
      keep({a.x, a.y, a.w, a.h, a.score / 2});
      continue;
    }
    taken[best] = true;
    const DnnBox& b = mirror_view[best];
    keep({(a.x + b.x) / 2, (a.y + b.y) / 2, (a.w + b.w) / 2, (a.h + b.h) / 2, (a.score + b.score) / 2});
  }
  for (size_t j = 0; j < mirror_view.size(); ++j) {
    const DnnBox& b = mirror_view[j];
    if (!taken[j]) keep({b.x, b.y, b.w, b.h, b.score / 2});
  }
  std::stable_sort(fused.begin(), fused.end(), [](const DnnBox& a, const DnnBox& b) { return a.score > b.score; });
  return fused;
}

std::vector<DnnBox> MergeContainedBoxes(std::vector<DnnBox> boxes, double contain_frac, double contain_axis_frac) {
  const auto area = [](const DnnBox& b) { return b.w * b.h; };
  std::stable_sort(boxes.begin(), boxes.end(), [&](const DnnBox& a, const DnnBox& b) { return area(a) > area(b); });
  std::vector<DnnBox> kept;  // larger first: the first container found is the largest
  for (const DnnBox& b : boxes) {
    const auto container = std::find_if(kept.begin(), kept.end(), [&](const DnnBox& k) {
      const double ix = std::max(0.0, std::min(b.x + b.w, k.x + k.w) - std::max(b.x, k.x));
      const double iy = std::max(0.0, std::min(b.y + b.h, k.y + k.h) - std::max(b.y, k.y));
      const double off_axis = std::abs((b.x + b.w / 2) - (k.x + k.w / 2));
      return area(b) > 0 && ix * iy >= contain_frac * area(b) && off_axis <= contain_axis_frac * k.w;
    });
    if (container == kept.end())
      kept.push_back(b);
    else
      container->score = std::max(container->score, b.score);
  }
  std::stable_sort(kept.begin(), kept.end(), [](const DnnBox& a, const DnnBox& b) { return a.score > b.score; });
  return kept;
}

std::vector<DnnBox> SuppressOverlaps(std::vector<DnnBox> boxes, double nms_iou) {
  std::stable_sort(boxes.begin(), boxes.end(), [](const DnnBox& a, const DnnBox& b) { return a.score > b.score; });
  std::vector<DnnBox> kept;
  for (const DnnBox& b : boxes) {
    if (std::none_of(kept.begin(), kept.end(), [&](const DnnBox& k) { return BoxIou(b, k) > nms_iou; }))
      kept.push_back(b);
  }
  return kept;
}

}  // namespace cone_tracker
