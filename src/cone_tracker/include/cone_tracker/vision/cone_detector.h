// The one place that chooses how cones are found in a frame, shared by the nodelet (through
// TrackerAdapter) and detect_cones: the thesis's colour segmentation (3.1.5, segmenter.h), or the
// learned detector for photographs (dnn_detector.h) with the colour pipeline's points. ROS-free.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cone_tracker/vision/dnn_detector.h"
#include "cone_tracker/vision/segmenter.h"

namespace cone_tracker {

// kColour: the segmentation alone (the rig: calibrated cone colour, 2 ms per frame).
// kDnn: the learned detector's boxes; each cone's peak/mid/base are those of the accepted colour
//   blob whose box overlaps the DNN box by IoU >= 0.5 (the best, each blob used once), else the
//   box's top centre, centre and bottom centre.
enum class DetectorKind { kColour = 0, kDnn = 1 };
constexpr int kDetectorKinds = 2;
std::string DetectorKindName(DetectorKind kind);  // "colour", "dnn"

struct ConeDetectorConfig {
  int detector = static_cast<int>(DetectorKind::kColour);  // a DetectorKind (an int for the parameter table)
  std::string dnn_model;                                   // ONNX file; empty: DefaultDnnModelFile()
  double dnn_score_min = 0.3;  // see DnnDetectorConfig (chosen on the held-out photos, README)
  // A DNN box with no colour blob of its own is kept only when at least this share of its pixels is
  // cone-coloured (the segmenter's colour table): the network finds cones of any colour (yellow and
  // blue race cones), the fiducials are orange. 0 keeps every box.
  double dnn_min_colour_frac = 0.05;
  DetectorKind kind() const { return static_cast<DetectorKind>(detector); }
  std::string Validate() const;  // "" or what is wrong, naming the parameter
};

// The committed model, cone_tracker/models/cone_detector.onnx (found by the package's source path).
std::string DefaultDnnModelFile();

struct ConeDetectorResult {
  // cones: the colour pipeline's, or one per DNN box (blob.bbox_* the DNN's box, rounded; the
  // matched colour blob's other properties, else zero). rejected: the colour pipeline's.
  SegmentationResult segmentation;
  std::vector<double> scores;            // per segmentation.cones: the DNN's score; 1 for colour
  std::vector<bool> points_from_colour;  // per segmentation.cones: peak/mid/base from a colour blob
  double dnn_ms = 0.0;                   // wall time of the DNN (steady clock), 0 for kColour
};

class ConeDetector {
 public:
  // Throws std::invalid_argument naming the parameter on a bad config, std::runtime_error naming
  // the file when the model cannot be loaded.
  ConeDetector(const SegmenterConfig& segmenter, const ConeDetectorConfig& config);
  // The segmentation's settings and the DNN's threshold (reconfigurable); the detector kind and the
  // model file are fixed at construction.
  void SetConfig(const SegmenterConfig& segmenter, double dnn_score_min);
  const ConeDetectorConfig& config() const { return config_; }
  const Segmenter& segmenter() const { return segmenter_; }

  ConeDetectorResult Process(const ImageView& image, const CameraModel& camera);

 private:
  void AddDnnCones(const ImageView& image, const CameraModel& camera, ConeDetectorResult* result);

  ConeDetectorConfig config_;
  Segmenter segmenter_;
  std::unique_ptr<DnnDetector> dnn_;  // kDnn only
};

}  // namespace cone_tracker
