#include "cone_tracker/vision/segmenter.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <utility>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace cone_tracker {

namespace {

// OpenCV names Bayer patterns by the second row's first two pixels; these are
// the pairs cv_bridge uses for the sensor_msgs encodings.
int BayerCode(const std::string& e) {
  if (e == "bayer_rggb8") return cv::COLOR_BayerBG2RGB;
  if (e == "bayer_bggr8") return cv::COLOR_BayerRG2RGB;
  if (e == "bayer_gbrg8") return cv::COLOR_BayerGR2RGB;
  if (e == "bayer_grbg8") return cv::COLOR_BayerGB2RGB;
  return -1;
}

// Refinement of the line search's peak (in place of 3.1.5.4's nine
// correlated templates, which fit a triangle at 3-pixel steps): the cone's
// outline edges are straight, so the blob's extent across the axis falls
// linearly to zero at the apex, whatever the collars do inside the outline.
// Least-squares lines through the extent profile of the peak side, and
// through its centre line, give the apex to a fraction of a pixel; the
// binary tip alone ends ~2-3 px short, where the silhouette gets narrower
// than a pixel.
// Returns false when the extent does not taper to the line search's end;
// *peak is the search's end then.
bool RefinePeak(const Blob& b, const Eigen::Vector2d& dir, double reach, Eigen::Vector2d* peak) {
  *peak = b.centroid + reach * dir;
  const int bins = int(std::ceil(reach)) + 2;
  if (bins < 8) return true;  // too small to judge the shape
  std::vector<double> lo(size_t(bins), INFINITY), hi(size_t(bins), -INFINITY);
  for (const Run& r : b.runs)
    for (int x : {r.x0, r.x1}) {  // a run's ends carry its extent
      const Eigen::Vector2d d = Eigen::Vector2d(x, r.y) - b.centroid;
      const double t = d.dot(dir);
      if (t < 0.0 || t >= bins) continue;
      const double s = d.x() * dir.y() - d.y() * dir.x();
      lo[size_t(t)] = std::min(lo[size_t(t)], s), hi[size_t(t)] = std::max(hi[size_t(t)], s);
    }
  double n = 0, st = 0, stt = 0, sw = 0, stw = 0, ss = 0, sts = 0;
  for (int i = int(0.3 * reach); i < bins; ++i) {
    const double w = hi[size_t(i)] - lo[size_t(i)] + 1.0;
    if (!(w >= 3.0)) continue;  // collar gaps, and the last pixels where the tip is binary
    const double t = i + 0.5, s = 0.5 * (hi[size_t(i)] + lo[size_t(i)]);
    n += 1, st += t, stt += t * t, sw += w, stw += t * w, ss += s, sts += t * s;
  }
  const double det = n * stt - st * st;
  if (n < 4 || det <= 0.0) return true;
  const double slope = (n * stw - st * sw) / det, icpt = (sw - slope * st) / n;
  if (!(slope < 0.0)) return false;
  const double t0 = -icpt / slope;
  if (!(t0 > 0.7 * reach && t0 < reach + 6.0)) return false;  // no apex near the search's end
  const double s_slope = (n * sts - st * ss) / det, s0 = (ss - s_slope * st) / n + s_slope * t0;
  *peak = b.centroid + t0 * dir + s0 * Eigen::Vector2d(dir.y(), -dir.x());
  return true;
}

// Cone pixels on the axis beyond the base, within a height of it (a few
// pixels either side of the axis).
bool OrangeBelowBase(const MaskView& mask, const Eigen::Vector2d& peak, const Eigen::Vector2d& base) {
  const Eigen::Vector2d axis = base - peak;
  const double h = axis.norm();
  if (!(h > 0.0 && h < 1e5)) return false;
  return MaskHitAlong(mask, base, axis / h, 3.0, std::max(8.0, h), 1.0, 2.0);
}

// Whether every pixel of the blob within bp of the image's edge lies within tip_zone_px (along the axis) of the
// apex: the edge cuts off only the part of the tip that the outline's apex does not rest on (OutlineFit).
bool OnlyTipAtEdge(const std::vector<Run>& runs, int width, int height, int bp, const Eigen::Vector2d& peak,
                   const Eigen::Vector2d& base, double tip_zone_px) {
  const Eigen::Vector2d d = (base - peak).normalized();
  if (!d.allFinite() || !(tip_zone_px > 0.0)) return false;
  const auto at_tip = [&](int x, int y) { return (Eigen::Vector2d(x, y) - peak).dot(d) <= tip_zone_px; };
  for (const Run& r : runs) {
    if (r.y <= bp || r.y >= height - 1 - bp) {  // the whole run is on the edge; its ends bound it along the axis
      if (!at_tip(r.x0, r.y) || !at_tip(r.x1, r.y)) return false;
      continue;
    }
    if ((r.x0 <= bp && !at_tip(r.x0, r.y)) || (r.x1 >= width - 1 - bp && !at_tip(r.x1, r.y))) return false;
  }
  return true;
}

}  // namespace

uint32_t RegionGates(const Blob& d, const SegmenterConfig& c) {
  uint32_t failed = 0;
  if (d.area < c.min_area_px || d.area > c.max_area_px) failed |= kGateArea;
  if (d.solidity < c.min_solidity || d.solidity > c.max_solidity) failed |= kGateSolidity;
  if (d.axis_ratio < c.min_axis_ratio || d.axis_ratio > c.max_axis_ratio) failed |= kGateAxisRatio;
  if (std::abs(std::cos(d.orientation_rad)) > std::sin(c.max_tilt_deg * M_PI / 180.0))
    failed |= kGateTilt;  // |angle from vertical| > max_tilt
  return failed;
}

std::string SegmenterConfig::Validate() const {
  const std::string hsi_error = hsi.Validate();
  if (!hsi_error.empty()) return hsi_error;
  if (pyramid_levels < 0 || pyramid_levels > 4) return "pyramid_levels must be in [0, 4]";
  if (roi_margin_px < 0) return "roi_margin_px must be >= 0";
  if (min_fragment_area_px < 1) return "min_fragment_area_px must be >= 1";
  if (!(merge_lateral_frac >= 0.0) || !(merge_gap_frac >= 0.0) || !(merge_band_gap_frac >= 0.0))
    return "merge fractions must be >= 0";
  if (band_min_value < 0 || band_min_value > 255) return "band_min_value must be in [0, 255]";
  if (cut_cone_contrast < 0 || cut_cone_contrast > 255) return "cut_cone_contrast must be in [0, 255]";
  if (!(band_max_sat >= 0.0 && band_max_sat <= 1.0)) return "band_max_sat must be in [0, 1]";
  if (!(min_area_px >= 0.0) || !(max_area_px >= min_area_px)) return "area bounds must satisfy 0 <= min <= max";
  if (border_px < 0) return "border_px must be >= 0";
  if (!(min_solidity >= 0.0) || !(max_solidity >= min_solidity)) return "solidity bounds invalid";
  if (!(min_axis_ratio >= 1.0) || !(max_axis_ratio >= min_axis_ratio)) return "axis ratio bounds invalid";
  if (!(max_tilt_deg >= 0.0 && max_tilt_deg <= 90.0)) return "max_tilt_deg must be in [0, 90]";
  if (line_search_misses < 1) return "line_search_misses must be >= 1";
  if (peak_refinement < 0 || peak_refinement >= kPeakRefinements)
    return "peak_refinement must be 0 (outline), 1 (templates) or 2 (none)";
  if (!(outline.outlier_px > 0.0) || !(outline.max_edge_rms_px > 0.0)) return "outline pixel bounds must be > 0";
  if (!(outline.min_inlier_frac >= 0.0 && outline.min_inlier_frac <= 1.0))
    return "outline.min_inlier_frac must be in [0, 1]";
  if (!(shape.min_height_px >= 0.0)) return "shape_min_height_px must be >= 0";
  if (!(shape.max_top_width_frac > 0.0)) return "shape_max_top_width_frac must be > 0";
  if (!(shape.max_width_rms_frac > 0.0)) return "shape_max_width_rms_frac must be > 0";
  const std::string collar_error = collar.Validate();
  if (!collar_error.empty()) return collar_error;
  if (!(shape.max_hole_frac >= 0.0 && shape.max_hole_frac <= 1.0)) return "shape_max_hole_frac must be in [0, 1]";
  if (!(template_search_px >= 0.0 && template_search_px <= 32.0)) return "template_search_px must be in [0, 32]";
  return "";
}

namespace {
// The colour bounds of a config that passed Validate() as a whole, so a bad
// config is refused before the table is filled.
const HsiBounds& ValidatedHsi(const SegmenterConfig& config) {
  const std::string error = config.Validate();
  if (!error.empty()) throw std::invalid_argument("SegmenterConfig: " + error);
  return config.hsi;
}
}  // namespace

// The table is filled once, from the config's bounds (not from the defaults
// and then again): the fill takes ~0.1 s.
Segmenter::Segmenter(const SegmenterConfig& config) : lut_(ValidatedHsi(config)) { SetConfig(config); }

void Segmenter::SetConfig(const SegmenterConfig& config) {
  if (config.colour_model.empty()) {
    lut_.Build(ValidatedHsi(config));  // a no-op when the bounds are unchanged
  } else if (lut_.model_path() != config.colour_model) {
    ValidatedHsi(config);
    try {
      lut_.BuildFromModel(LoadColourModel(config.colour_model));
    } catch (const std::runtime_error& e) {  // rig_model::FileError: names the file, line and field
      throw std::invalid_argument(std::string("colour_model: ") + e.what());
    }
  }
  if (config.refinement() == PeakRefinement::kTemplates && !templates_) {
    TemplateSetConfig tc;
    tc.max_tilt_deg = std::max(config.max_tilt_deg, 3.0);
    templates_ = std::make_shared<const ConeTemplateSet>(tc);  // 3.1.5.4: the whole set at start-up
  }
  config_ = config;
}

bool Segmenter::SupportedEncoding(const std::string& e) { return e == "rgb8" || e == "bgr8" || BayerCode(e) >= 0; }

bool Segmenter::Classify(const ImageView& in, SegmentationResult* out) {
  if (!in.data || in.width <= 0 || in.height <= 0) {
    out->error = "empty image";
    return false;
  }
  if (!SupportedEncoding(in.encoding)) {
    out->error = "unsupported encoding '" + in.encoding + "' (rgb8, bgr8 and bayer_*8 are supported)";
    return false;
  }
  const uint8_t* rgb = in.data;
  int step = in.step;
  int r_off = 0, b_off = 2;
  if (in.encoding == "bgr8") std::swap(r_off, b_off);
  const int bayer = BayerCode(in.encoding);
  if (bayer >= 0) {
    if (in.step < in.width) {
      out->error = "bayer image step smaller than its width";
      return false;
    }
    rgb_.resize(size_t(in.width) * in.height * 3);
    const cv::Mat raw(in.height, in.width, CV_8UC1, const_cast<uint8_t*>(in.data), size_t(in.step));
    cv::Mat dst(in.height, in.width, CV_8UC3, rgb_.data());
    cv::cvtColor(raw, dst, bayer);
    rgb = rgb_.data(), step = in.width * 3;
  } else if (in.step < in.width * 3) {
    out->error = "image step smaller than 3 * width";
    return false;
  }
  const int w = in.width, h = in.height;
  frame_rgb_ = rgb, frame_step_ = step, frame_w_ = w, frame_h_ = h;
  auto is_cone = [&](int x, int y) {
    const uint8_t* p = rgb + size_t(y) * step + 3 * x;
    return lut_.IsCone(p[r_off], p[1], p[b_off]);
  };
  // ROI (3.1.5.2): classify the image down-sampled twice (odd rows and
  // columns kept), take the rectangle around its cone pixels.
  const int s = 1 << config_.pyramid_levels;
  int x_lo = w, x_hi = -1, y_lo = h, y_hi = -1;
  for (int y = s - 1; y < h; y += s)
    for (int x = s - 1; x < w; x += s)
      if (is_cone(x, y)) x_lo = std::min(x_lo, x), x_hi = std::max(x_hi, x), y_lo = std::min(y_lo, y), y_hi = y;
  mask_.assign(size_t(w) * h, 0);
  if (x_hi < 0) return true;
  const int pad = s + config_.roi_margin_px;
  out->roi_x = std::max(0, x_lo - pad), out->roi_y = std::max(0, y_lo - pad);
  out->roi_w = std::min(w, x_hi + pad + 1) - out->roi_x, out->roi_h = std::min(h, y_hi + pad + 1) - out->roi_y;
  for (int y = out->roi_y; y < out->roi_y + out->roi_h; ++y) {
    uint8_t* m = mask_.data() + size_t(y) * w;
    for (int x = out->roi_x; x < out->roi_x + out->roi_w; ++x) m[x] = is_cone(x, y);
  }
  return true;
}

bool Segmenter::IsBand(const Eigen::Vector2d& from, const Eigen::Vector2d& to, double half_width_px) const {
  const Eigen::Vector2d d = to - from;
  const double len = d.norm();
  if (!frame_rgb_ || !(len > 0.0)) return false;
  const Eigen::Vector2d e = Eigen::Vector2d(d.y(), -d.x()) / len;
  int band = 0, total = 0;
  const int steps = std::clamp(int(len / 2.0), 3, 12);
  for (int i = 0; i < steps; ++i)
    for (double s : {-1.0, 0.0, 1.0}) {
      const Eigen::Vector2d p = from + (i + 0.5) / steps * d + s * half_width_px * e;
      const int x = int(std::lround(p.x())), y = int(std::lround(p.y()));
      if (x < 0 || y < 0 || x >= frame_w_ || y >= frame_h_) continue;
      const uint8_t* q = frame_rgb_ + size_t(y) * frame_step_ + 3 * x;
      const int mx = std::max({q[0], q[1], q[2]}), mn = std::min({q[0], q[1], q[2]});
      ++total;
      band += mx >= config_.band_min_value && mn >= (1.0 - config_.band_max_sat) * mx;
    }
  return total > 0 && band >= 0.6 * total;
}

bool Segmenter::Measure(const MaskView& mask, const CameraModel& camera, ConeDetection* det, double* tip_zone_px,
                        OutlineFit* outline) const {
  const Blob& b = det->blob;
  const Eigen::Vector2d axis(std::cos(b.orientation_rad), std::sin(b.orientation_rad));
  // Extent of the blob along its axis; a merged blob's line search may cross
  // the collar gaps up to there.
  double extent[2] = {0.0, 0.0};
  for (const Run& r : b.runs)
    for (int x : {r.x0, r.x1}) {
      const double t = (Eigen::Vector2d(x, r.y) - b.centroid).dot(axis);
      extent[0] = std::max(extent[0], t), extent[1] = std::max(extent[1], -t);
    }
  double reach[2];
  for (int side = 0; side < 2; ++side) {
    const Eigen::Vector2d dir = side == 0 ? axis : Eigen::Vector2d(-axis);
    int last_hit = 0, misses = 0;
    const int limit = int(extent[side]) + config_.line_search_misses + 2;
    for (int t = 1; t <= limit; ++t) {
      const Eigen::Vector2d p = b.centroid + t * dir;
      if (mask.At(int(std::lround(p.x())), int(std::lround(p.y())))) {
        last_hit = t, misses = 0;
      } else if (++misses >= config_.line_search_misses && (b.fragments == 1 || t > extent[side])) {
        break;
      }
    }
    reach[side] = last_hit + 0.5;  // the silhouette ends half a pixel past the last cone pixel centre
  }
  if (std::min(reach[0], reach[1]) < 1.5) det->failed_gates |= kGateLineSearch;
  // A cone's centroid lies nearer its base (a third of the height for a triangle).
  const int peak_side = reach[0] >= reach[1] ? 0 : 1;
  const Eigen::Vector2d dir_peak = peak_side == 0 ? axis : Eigen::Vector2d(-axis);
  const Eigen::Vector2d search_peak = b.centroid + reach[peak_side] * dir_peak;
  det->peak_px = search_peak;
  det->base_px = b.centroid - reach[1 - peak_side] * dir_peak;
  det->mid_px = 0.5 * (det->peak_px + det->base_px);
  if (det->failed_gates != 0) return false;
  switch (config_.refinement()) {
    case PeakRefinement::kOutline: {
      const OutlineFit fit = FitConeOutline(b.runs, search_peak, det->base_px, camera, config_.outline);
      if (outline) *outline = fit;
      if (fit.ok && OrangeBelowBase(mask, fit.peak_px, fit.base_px)) {
        // The tip of a collared cone whose body did not merge (it is hidden,
        // or merged with something orange and rejected): its collar's rim
        // looks like a base arc.
        det->failed_gates |= kGateOutline;
        return false;
      }
      if (fit.ok) {
        det->peak_px = fit.peak_px, det->base_px = fit.base_px;
        det->peak_undist_px = fit.peak_undist_px, det->base_undist_px = fit.base_undist_px;
        *tip_zone_px = fit.tip_zone_px;
        return true;
      }
      if (fit.why.find("distortion") != std::string::npos) {  // a broken camera model, not a bad blob
        det->failed_gates |= kGateUndistort;
        return false;
      }
      if (config_.reject_bad_outline) {
        det->failed_gates |= kGateOutline;
        return false;
      }
      // Kept for photos: the apex from the blob's extent profile.
      RefinePeak(b, dir_peak, reach[peak_side], &det->peak_px);
      det->mid_px = 0.5 * (det->peak_px + det->base_px);
      return false;
    }
    case PeakRefinement::kTemplates: {
      const TemplateMatch m =
          templates_->Refine(mask, search_peak, det->base_px, int(std::lround(config_.template_search_px)));
      if (m.ok) det->peak_px = m.peak_px, det->base_px = m.base_px;
      det->mid_px = 0.5 * (det->peak_px + det->base_px);
      return false;
    }
    case PeakRefinement::kNone:
      break;
  }
  return false;
}

namespace {
double MsSince(std::chrono::steady_clock::time_point* t) {
  const auto now = std::chrono::steady_clock::now();
  const double ms = std::chrono::duration<double, std::milli>(now - *t).count();
  *t = now;
  return ms;
}
}  // namespace

ConeDetection Segmenter::Judge(Blob blob, const MaskView& mask, const CameraModel& camera, OutlineFit* outline) const {
  const SegmenterConfig& c = config_;
  ConeDetection det;
  det.blob = std::move(blob);
  const Blob& d = det.blob;
  det.failed_gates = RegionGates(d, c);
  const int bp = c.border_px, width = mask.width, height = mask.height;
  const bool at_border =
      d.bbox_x <= bp || d.bbox_y <= bp || d.bbox_x + d.bbox_w >= width - bp || d.bbox_y + d.bbox_h >= height - bp;
  double tip_zone_px = 0.0;
  const bool undistorted = det.failed_gates == 0 && Measure(mask, camera, &det, &tip_zone_px, outline);
  // Part of the cone may be outside the image; not when only the tip zone of its outline is on the edge.
  if (at_border && !(undistorted && OnlyTipAtEdge(d.runs, width, height, bp, det.peak_px, det.base_px, tip_zone_px)))
    det.failed_gates |= kGateBorder;
  if (det.failed_gates == 0 && !CheckConeShape(d.runs, det.peak_px, det.base_px, c.shape).ok)
    det.failed_gates |= kGateShape;
  if (det.failed_gates == 0 &&
      SilhouetteRunsOutOfImage(RgbView{frame_rgb_, frame_w_, frame_h_, frame_step_}, det.peak_px, det.base_px,
                               0.5 * WidthAcross(d.runs, det.peak_px, (det.base_px - det.peak_px).normalized()),
                               c.cut_cone_contrast, c.merge_band_gap_frac))
    det.failed_gates |= kGateBorder;  // the top of a cone whose collar runs out of the image
  if (undistorted) {
    // The mid-height point on the axis; it is not a measured point.
    det.mid_undist_px = 0.5 * (det.peak_undist_px + det.base_undist_px);
    std::vector<Eigen::Vector2d> mid = {det.mid_undist_px};
    if (DistortPixels(camera, &mid))
      det.mid_px = mid[0];
    else
      det.failed_gates |= kGateUndistort;
  } else if (det.failed_gates == 0) {
    std::vector<Eigen::Vector2d> pts = {det.peak_px, det.mid_px, det.base_px};
    if (UndistortPixels(camera, &pts))
      det.peak_undist_px = pts[0], det.mid_undist_px = pts[1], det.base_undist_px = pts[2];
    else
      det.failed_gates |= kGateUndistort;
  }
  return det;
}

SegmentationResult Segmenter::Process(const ImageView& image, const CameraModel& camera) {
  SegmentationResult result;
  auto t = std::chrono::steady_clock::now();
  if (!Classify(image, &result)) return result;
  result.classify_ms = MsSince(&t);
  result.ok = true;
  if (result.roi_w <= 0) return result;
  const MaskView mask{mask_.data(), image.width, image.height, image.width};
  std::vector<Blob> blobs = FindBlobs(mask, result.roi_x, result.roi_y, result.roi_x + result.roi_w,
                                      result.roi_y + result.roi_h, config_.min_fragment_area_px);
  BandTest band;
  if (config_.merge_band_gap_frac > 0.0)
    band = [this](const Eigen::Vector2d& a, const Eigen::Vector2d& b, double hw) { return IsBand(a, b, hw); };
  MergeAlongAxes(&blobs, config_.merge_lateral_frac, config_.merge_gap_frac, config_.max_tilt_deg * M_PI / 180.0, band,
                 config_.merge_band_gap_frac);
  result.blobs_ms = MsSince(&t);
  std::vector<ConeDetection> dets(blobs.size());
  std::vector<OutlineFit> fits(blobs.size());
  for (size_t i = 0; i < blobs.size(); ++i) dets[i] = Judge(std::move(blobs[i]), mask, camera, &fits[i]);
  SplitMergedTips(&dets, fits, mask, camera);
  result.orange_undist_px = OrangeRegions(dets, camera);
  ReadCutCones(&dets, camera);  // after the orange regions: a cone it reads is a refused blob's part
  for (ConeDetection& det : dets) {
    det.blob.runs.clear();
    det.blob.runs.shrink_to_fit();
    (det.accepted() ? result.cones : result.rejected).push_back(std::move(det));
  }
  std::sort(result.cones.begin(), result.cones.end(),
            [](const ConeDetection& a, const ConeDetection& b) { return a.peak_px.x() < b.peak_px.x(); });
  result.measure_ms = MsSince(&t);
  return result;
}

std::vector<rig_model::ImageBox> OrangeRegions(const std::vector<ConeDetection>& dets, const CameraModel& camera) {
  std::vector<rig_model::ImageBox> boxes;
  for (const ConeDetection& d : dets) {
    const std::vector<rig_model::ImageBox> slabs = RowSlabs(d.blob.runs, kOrangeSlabs);
    boxes.insert(boxes.end(), slabs.begin(), slabs.end());
  }
  // Each box's corners and edge midpoints, undistorted: the box around them holds the undistorted box's edges, which
  // the lens bends.
  std::vector<Eigen::Vector2d> pts;
  for (const rig_model::ImageBox& b : boxes) {
    const double um = 0.5 * (b.u_min + b.u_max), vm = 0.5 * (b.v_min + b.v_max);
    for (const auto& [u, v] : {std::pair{b.u_min, b.v_min},
                               {um, b.v_min},
                               {b.u_max, b.v_min},
                               {b.u_max, vm},
                               {b.u_max, b.v_max},
                               {um, b.v_max},
                               {b.u_min, b.v_max},
                               {b.u_min, vm}})
      pts.emplace_back(u, v);
  }
  // A hundredth of a pixel is plenty for boxes the association samples (and takes a few iterations, not 1e-7's).
  if (!UndistortPixels(camera, &pts, 1e-2)) return boxes;  // a lens that does not invert: the raw boxes, near enough
  for (size_t i = 0; i < boxes.size(); ++i) {
    rig_model::ImageBox& b = boxes[i];
    b = {INFINITY, INFINITY, -INFINITY, -INFINITY};
    for (size_t k = 8 * i; k < 8 * i + 8; ++k) {
      b.u_min = std::min(b.u_min, pts[k].x()), b.u_max = std::max(b.u_max, pts[k].x());
      b.v_min = std::min(b.v_min, pts[k].y()), b.v_max = std::max(b.v_max, pts[k].y());
    }
    // A barrel lens spreads the edge's pixels past the pinhole image's bounds: a box it puts wholly outside keeps its
    // last pixel row or column inside, where the orange reaches the image's edge (rig_model::UnexplainedOrange), and
    // the message's regions, clipped to the image, keep it.
    if (camera.width_px > 0 && camera.height_px > 0) {
      const double u_last = camera.width_px - 1.0, v_last = camera.height_px - 1.0;
      b.u_min = std::min(b.u_min, u_last), b.u_max = std::max(b.u_max, 0.0);
      b.v_min = std::min(b.v_min, v_last), b.v_max = std::max(b.v_max, 0.0);
    }
  }
  return boxes;
}

bool UndistortPixels(const CameraModel& camera, std::vector<Eigen::Vector2d>* points, double tolerance_px) {
  if (!camera.HasDistortion() || !(camera.fx_px > 0.0) || !(camera.fy_px > 0.0)) return true;
  const cv::Matx33d K(camera.fx_px, 0, camera.cx_px, 0, camera.fy_px, camera.cy_px, 0, 0, 1);
  std::vector<cv::Point2d> src, dst;
  for (const auto& p : *points) src.emplace_back(p.x(), p.y());
  try {
    // (3.11) iteratively: OpenCV's default of 5 iterations leaves tenths of a
    // pixel at the corners with this lens. EPS is the reprojection error in
    // pixels: the default 1e-7 px keeps the distort/undistort round trip within
    // 1e-6 px (test_refinement.cpp) for fewer iterations than the 1e-10 it had,
    // on every outline point of every frame.
    cv::undistortPoints(src, dst, K, camera.distortion, cv::noArray(), K,
                        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, tolerance_px));
  } catch (const cv::Exception&) {
    return false;
  }
  for (size_t i = 0; i < dst.size(); ++i) {
    if (!std::isfinite(dst[i].x) || !std::isfinite(dst[i].y)) return false;
    (*points)[i] = Eigen::Vector2d(dst[i].x, dst[i].y);
  }
  return true;
}

std::string PeakRefinementName(PeakRefinement r) {
  return r == PeakRefinement::kOutline ? "outline" : r == PeakRefinement::kTemplates ? "templates" : "none";
}

std::vector<std::string> SegmentationGateNames(uint32_t bits) {
  static const std::pair<uint32_t, const char*> kNames[] = {{kGateArea, "area"},
                                                            {kGateBorder, "border"},
                                                            {kGateSolidity, "solidity"},
                                                            {kGateAxisRatio, "axis_ratio"},
                                                            {kGateLineSearch, "line_search"},
                                                            {kGateUndistort, "undistort"},
                                                            {kGateTilt, "tilt"},
                                                            {kGateOutline, "outline"},
                                                            {kGateShape, "shape"}};
  std::vector<std::string> out;
  for (const auto& [bit, name] : kNames)
    if (bits & bit) out.emplace_back(name), bits &= ~bit;
  for (int i = 0; i < 32; ++i)  // a gate added to the core later still shows up
    if (bits & (1u << i)) out.push_back("bit" + std::to_string(i));
  return out;
}

}  // namespace cone_tracker
