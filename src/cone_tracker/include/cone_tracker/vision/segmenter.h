// Cone segmentation (3.1.5): colour classification through the RGB table,
// ROI from a two-level pyramid, 8-connected blobs, merging of collar-split
// fragments, gates with border rejection, peak/base line search, and
// undistortion of the image points (3.1.2). ROS-free.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cone_tracker/pose/pnp.h"
#include "cone_tracker/vision/blobs.h"
#include "cone_tracker/vision/collar_ruler.h"
#include "cone_tracker/vision/color_lut.h"
#include "cone_tracker/vision/cone_outline.h"
#include "cone_tracker/vision/cone_shape.h"
#include "cone_tracker/vision/cone_templates.h"
#include "cone_tracker/vision/cut_cone.h"
#include "cone_tracker/vision/merged_tip.h"

namespace cone_tracker {

// Refinement of the line search's peak and base (3.1.5.4).
//  kOutline (default): the two silhouette edges fitted over every row and
//    intersected (cone_outline.h). On rig_sim's 28" road cones at 2-4 m it
//    puts peak and base within ~0.3 px RMS of the truth, against ~1-2 px for
//    the templates, which are quantised to 3 px of height and 3 deg of
//    orientation, are triangles without the base ellipse's front arc, and cost
//    more (test_refinement.cpp and the bench measure both).
//  kTemplates: the thesis's nine templates around the estimate, from the
//    precomputed height x orientation set, scored by normalised
//    cross-correlation (cone_templates.h).
//  kNone: the line search's ends.
// The values are dynamic_reconfigure's (cfg/ConeTracker.cfg, peak_refinement).
enum class PeakRefinement { kOutline = 0, kTemplates = 1, kNone = 2 };
constexpr int kPeakRefinements = 3;
// Boxes per blob in SegmentationResult::orange_undist_px: around a cone's triangle, four bands of rows hold empty
// pixels over an eighth of its bounding box's area (a single box: half).
constexpr int kOrangeSlabs = 4;

// "outline", "templates", "none": the parameter's names for the values.
std::string PeakRefinementName(PeakRefinement r);

struct SegmenterConfig {
  HsiBounds hsi;
  // A learned colour table (colour_model.h, written by calibrate_cone_colour) used instead of the
  // HSI bounds when set; "" keeps the bounds.
  std::string colour_model;
  int pyramid_levels = 2;        // 3.1.5.2: down-sample twice
  int roi_margin_px = 8;         // full-resolution margin around the pyramid ROI
  int min_fragment_area_px = 4;  // smaller blobs are artifacts, dropped before merging
  double merge_lateral_frac = 0.25;
  double merge_gap_frac = 0.5;
  // Up to this gap (times the larger fragment's major axis) fragments join across a white or silver
  // band: bright (max channel >= band_min_value) unsaturated (min channel >= (1 - band_max_sat) * max)
  // pixels over most of the gap. 0: no band merging. 1.5 by measurement (cone_tracker README, "Band
  // merging on the rig"): the realistic look's wide sleeve needs it, the plain look loses nothing.
  double merge_band_gap_frac = 1.5;
  int band_min_value = 90;
  double band_max_sat = 0.45;
  // Gates (3.1.5.3).
  double min_area_px = 30.0;
  double max_area_px = 200000.0;
  // A blob within this of the edge is rejected (cut by it), unless only the tip zone of its fitted outline
  // (OutlineFit::tip_zone_px, peak_refinement outline) is there: the outline's apex comes from the edges, not
  // from the tip's last pixels. 1: the silhouette's mixed edge pixels may fail the colour test, so a cone cut by
  // the edge can end one pixel short of it; a wider margin refused whole cones coming into view (cone_tracker
  // README, "Cones at the image's edge").
  int border_px = 1;
  // A cone whose silhouette runs on past its base out of the image, over a collar no longer than
  // merge_band_gap_frac (cut_cone.h: its min_contrast), fails the border gate too; 0: no such test.
  int cut_cone_contrast = 40;
  double min_solidity = 0.75;
  double max_solidity = 1.0;
  double min_axis_ratio = 1.3;
  double max_axis_ratio = 8.0;
  // Not in the thesis: cones stand upright and the rig is held roughly level,
  // so a blob whose major axis is far from the image vertical (stripes of a
  // hi-vis vest, a box's side) is not a cone.
  double max_tilt_deg = 50.0;
  int line_search_misses = 3;  // consecutive non-cone pixels ending the line search
  // How the line search's peak and base are refined: a PeakRefinement's value, held as an int so
  // that the parameter table reads it by name or index like the others (node/params.cpp).
  int peak_refinement = static_cast<int>(PeakRefinement::kOutline);
  PeakRefinement refinement() const { return static_cast<PeakRefinement>(peak_refinement); }
  OutlineConfig outline;
  // With kOutline: a blob whose outline is not one cone's (two cones
  // overlapping in the image, a cone partly hidden) is rejected with
  // kGateOutline rather than measured wrongly. Off: it keeps the line search.
  bool reject_bad_outline = true;
  // With kOutline: a near cone's tip seen in front of a farther cone of the same colour, and merged into its blob,
  // goes back to the near cone (merged_tip.h). Off: both blobs fail the outline gate.
  bool split_merged_tips = true;
  // The silhouette must be a cone's (cone_shape.h): kGateShape otherwise.
  ConeShapeConfig shape;
  // With kOutline: a cone cut by the image's edge below its collars, refused by the border or outline gate, is
  // measured by its collars (collar_ruler.h) when `collar.collars` is set (the tracker sets the layout's) and
  // read_collars is on.
  bool read_collars = true;
  CollarRulerConfig collar;
  double template_search_px = 4.0;  // kTemplates: apex offsets tried, +- this around the line search's

  std::string Validate() const;
};

// Gate outcomes, one bit per failed gate.
enum GateBits : uint32_t {
  kGateArea = 1u << 0,
  kGateBorder = 1u << 1,
  kGateSolidity = 1u << 2,
  kGateAxisRatio = 1u << 3,
  kGateLineSearch = 1u << 4,
  kGateUndistort = 1u << 5,
  kGateTilt = 1u << 6,
  kGateOutline = 1u << 7,  // the outline is not one cone's (OutlineConfig)
  kGateShape = 1u << 8,    // not a cone's silhouette: no taper, crooked edges or holes (cone_shape.h)
};

// The gates on a blob's region properties alone (3.1.5.3): area, solidity, axis ratio, tilt.
uint32_t RegionGates(const Blob& blob, const SegmenterConfig& config);

// Names of the set bits ("area", "border", ...; an unknown bit as "bitN").
std::vector<std::string> SegmentationGateNames(uint32_t bits);

struct ConeDetection {
  Blob blob;  // runs are cleared in the output to keep it small
  uint32_t failed_gates = 0;
  // Raw (distorted) pixels and undistorted pixels (3.1.2), same intrinsics.
  Eigen::Vector2d peak_px = Eigen::Vector2d::Zero(), mid_px = Eigen::Vector2d::Zero(),
                  base_px = Eigen::Vector2d::Zero();
  Eigen::Vector2d peak_undist_px = Eigen::Vector2d::Zero(), mid_undist_px = Eigen::Vector2d::Zero(),
                  base_undist_px = Eigen::Vector2d::Zero();
  // Read by its collars (collar_ruler.h): the base is cut by the image's edge, and the points come from the lower
  // body's edges and the collars; their errors along the cone's axis (peak, mid, base: px, 1 sigma, undistorted)
  // add to the point noise. The blob is the lower body's.
  bool by_collars = false;
  Eigen::Vector3d axis_sigma_px = Eigen::Vector3d::Zero();
  bool accepted() const { return failed_gates == 0; }
};

// An image in memory; not owned. encoding uses sensor_msgs names.
struct ImageView {
  const uint8_t* data = nullptr;
  int width = 0, height = 0, step = 0;
  std::string encoding;
};

struct SegmentationResult {
  bool ok = false;
  std::string error;                    // why ok is false (bad encoding, empty image)
  std::vector<ConeDetection> cones;     // accepted, sorted by u of the peak
  std::vector<ConeDetection> rejected;  // with failed_gates set
  // Where the image is orange, in undistorted pixels: every blob's, accepted or refused, as kOrangeSlabs boxes
  // around bands of its rows (RowSlabs), each box around its undistorted corners and edge midpoints. The
  // association's negative information (rig_model::MissedInView).
  std::vector<rig_model::ImageBox> orange_undist_px;
  int roi_x = 0, roi_y = 0, roi_w = 0, roi_h = 0;
  // Wall time per stage (steady clock): colour table + ROI, connected
  // components + merging, gates + line search + refinement + undistortion.
  double classify_ms = 0.0, blobs_ms = 0.0, measure_ms = 0.0;
};

class Segmenter {
 public:
  // Throws std::invalid_argument naming the field on a bad config.
  explicit Segmenter(const SegmenterConfig& config);
  // Rebuilds the colour table only when the HSI bounds or the colour model's path changed. Throws
  // std::invalid_argument naming the model file, line and field when the model does not load.
  void SetConfig(const SegmenterConfig& config);
  const SegmenterConfig& config() const { return config_; }

  static bool SupportedEncoding(const std::string& encoding);
  // camera: intrinsics for undistortion; all-zero fx gives undistorted = raw.
  SegmentationResult Process(const ImageView& image, const CameraModel& camera);

  // The binary mask of the last Process() (valid inside the ROI only).
  const std::vector<uint8_t>& mask() const { return mask_; }

 private:
  bool Classify(const ImageView& image, SegmentationResult* result);
  // Line search, then the refinement; sets the undistorted points when the
  // refinement computed them (returns true then, and the outline's tip zone).
  // outline: the outline fit, when the refinement ran it.
  bool Measure(const MaskView& mask, const CameraModel& camera, ConeDetection* det, double* tip_zone_px,
               OutlineFit* outline = nullptr) const;
  // Every gate on one blob, and its points (3.1.5.3-3.1.5.4, 3.1.2); the blob's runs are kept. outline: as Measure's.
  ConeDetection Judge(Blob blob, const MaskView& mask, const CameraModel& camera, OutlineFit* outline = nullptr) const;
  // A near cone's tip merged into a farther cone's blob goes back to the near cone's (merged_tip.h); the two
  // detections are judged again. fits: each detection's outline fit (Judge's).
  void SplitMergedTips(std::vector<ConeDetection>* dets, const std::vector<OutlineFit>& fits, const MaskView& mask,
                       const CameraModel& camera) const;
  // A refused blob cut by the image's bottom edge: its lower body's edges and the collars up the axis (collar_ruler.h)
  // give a cone, appended accepted with by_collars set (the blob stays refused: it may hold more, another cone's
  // tip say); not when an accepted cone has the same peak.
  void ReadCutCones(std::vector<ConeDetection>* dets, const CameraModel& camera) const;
  // ReadCutCones' outline of the cone cut in blob `cut` (runs): its lower body's, with the rows above whose ends lie on
  // its edges (in `refused`, the refused blobs' runs) joined; *runs the rows it took, the bottom row first.
  OutlineFit FitCutCone(const std::vector<Run>& cut, const std::vector<const std::vector<Run>*>& refused,
                        const CameraModel& camera, std::vector<Run>* runs) const;

  SegmenterConfig config_;
  ColorLut lut_;
  // Whether the pixels between two fragments are a white band (blobs.h, BandTest).
  bool IsBand(const Eigen::Vector2d& from, const Eigen::Vector2d& to, double half_width_px) const;

  std::vector<uint8_t> rgb_;            // debayered frame (bayer input only)
  const uint8_t* frame_rgb_ = nullptr;  // the frame of the running Process(), RGB
  int frame_step_ = 0, frame_w_ = 0, frame_h_ = 0;
  std::vector<uint8_t> mask_;                         // full-size, zero outside the ROI
  std::shared_ptr<const ConeTemplateSet> templates_;  // built at start-up for kTemplates
};

// SegmentationResult::orange_undist_px of these detections (their blobs' runs not yet cleared).
std::vector<rig_model::ImageBox> OrangeRegions(const std::vector<ConeDetection>& dets, const CameraModel& camera);

// Undistorts pixel points in place to ideal pinhole pixels with the same K (3.1.2), iterating until the
// reprojection error is below tolerance_px (or 30 iterations).
bool UndistortPixels(const CameraModel& camera, std::vector<Eigen::Vector2d>* points_px, double tolerance_px = 1e-7);

}  // namespace cone_tracker
