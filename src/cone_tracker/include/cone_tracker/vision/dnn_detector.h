// A small learned cone detector for ordinary photographs (not in the thesis): a CenterNet-style
// network trained from scratch on the TraCon photos by scripts/train_cone_detector.py, run through
// OpenCV's dnn module. ROS-free. The rig's calibrated colour pipeline (segmenter.h) stays the
// default; this one finds cones of any colour balance and size in uncontrolled photos.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/dnn/dnn.hpp>

namespace cone_tracker {

struct DnnDetectorConfig {
  std::string model_file;  // ONNX file; required
  double score_min = 0.3;  // a cone-centre peak below this is no detection
  double nms_iou = 0.5;    // a box overlapping a higher-scored one by more is dropped
  // A box that is part of a larger one's cone (the network also boxes a striped cone's upper band
  // beside the whole cone) is merged into the larger box: at least contain_frac of its area lies
  // inside the larger box and its centre is within contain_axis_frac x the larger box's width of the
  // larger box's vertical centre line (one cone axis). 1 < contain_frac: no merging. The defaults
  // were chosen on the development photos' training split (README, "Learned detector for photos").
  double contain_frac = 0.7;
  double contain_axis_frac = 0.1;
  // Also run the network on the mirrored image and average the two views (FuseMirroredViews): twice
  // the network's time, fewer single-view false boxes (README, "Learned detector for photos").
  bool flip_average = true;
  std::string Validate() const;  // "" or what is wrong, naming the field
};

// One detection in the image's pixels (the box spans the whole cone, sleeve and base).
struct DnnBox {
  double x = 0, y = 0, w = 0, h = 0;
  double score = 0;  // the cone-centre heat, in (0, 1)
};

// The network's fixed input: the image scaled so its long side is kInputPx, top-left aligned,
// padded with grey kPadGrey, RGB / 255 (as train_cone_detector.py's letterbox()).
constexpr int kDnnInputPx = 320;
constexpr int kDnnStride = 8;  // one output cell per 8 x 8 input pixels
constexpr int kDnnPadGrey = 114;
constexpr int kDnnChannels = 5;  // heat, log(w / stride), log(h / stride), offset x, offset y

class DnnDetector {
 public:
  // Loads and checks the model (input kDnnInputPx square, output kDnnChannels x grid x grid).
  // Throws std::runtime_error naming the file when it is missing or not a usable model, and
  // std::invalid_argument naming the field on a bad config.
  explicit DnnDetector(const DnnDetectorConfig& config);
  const DnnDetectorConfig& config() const { return config_; }
  // Only the thresholds change; the model file must stay the same.
  void SetThresholds(double score_min, double nms_iou);

  // bgr: 8-bit, 3 channels. Boxes in score order.
  std::vector<DnnBox> Detect(const cv::Mat& bgr);

 private:
  DnnDetectorConfig config_;
  cv::dnn::Net net_;
};

// Decoding, separate for the tests: cone centres are the 3x3 local maxima of the heat channel at or
// above score_min; each gives a box from its cell's size and offset, divided by `scale` (input
// pixels per image pixel), clipped to image_w x image_h; then greedy NMS. heads: kDnnChannels planes
// of grid_h x grid_w floats.
std::vector<DnnBox> DecodeDnnHeads(const float* heads, int grid_h, int grid_w, double scale, int image_w, int image_h,
                                   double score_min, double nms_iou);
// The boxes of the image and of its mirror image (already mirrored back into the image's pixels),
// each decoded at score_min / 2: a box of one view that overlaps one of the other by IoU >= 0.5
// (greedy, in score order) becomes their mean box with their mean score; a box seen in one view only
// keeps half its score (the other view's score taken as 0). Returns the boxes scoring >= score_min,
// in score order (overlaps not yet suppressed).
std::vector<DnnBox> FuseMirroredViews(const std::vector<DnnBox>& image_view, const std::vector<DnnBox>& mirror_view,
                                      double score_min);
// Merges each box into the largest larger box (by area) that contains it as DnnDetectorConfig's
// contain_frac and contain_axis_frac say: the larger box stays, with the higher of the two scores.
// Returns the boxes in score order.
std::vector<DnnBox> MergeContainedBoxes(std::vector<DnnBox> boxes, double contain_frac, double contain_axis_frac);
// Greedy non-maximum suppression: sorts by score, drops a box whose IoU with a kept one exceeds nms_iou.
std::vector<DnnBox> SuppressOverlaps(std::vector<DnnBox> boxes, double nms_iou);
double BoxIou(const DnnBox& a, const DnnBox& b);

}  // namespace cone_tracker
