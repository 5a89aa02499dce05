#include "cone_tracker/vision/collar_ruler.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "cone_tracker/vision/cone_outline.h"
#include "cone_tracker/vision/segmenter.h"

namespace cone_tracker {

namespace {

constexpr double kStepPx = 0.25;  // along the axis, undistorted px
constexpr int kMinRunSteps = 4;   // a collar or an orange band shorter than a pixel is noise
constexpr int kMinBodyRows = 6;   // a cut body fewer rows tall gives no edges to speak of

// The smallest channel over the largest at a raw pixel position, bilinear; NaN outside the image.
double WhiteRatio(const RgbView& im, const Eigen::Vector2d& p) {
  const double x = p.x(), y = p.y();
  if (!(x >= 0.0 && y >= 0.0 && x <= im.width - 1 && y <= im.height - 1)) return NAN;
  const int x0 = std::min(int(x), im.width - 2), y0 = std::min(int(y), im.height - 2);
  const double fx = x - x0, fy = y - y0;
  double c[3] = {0.0, 0.0, 0.0};
  for (int k = 0; k < 4; ++k) {
    const int dx = k & 1, dy = k >> 1;
    const double w = (dx ? fx : 1.0 - fx) * (dy ? fy : 1.0 - fy);
    const uint8_t* q = im.data + size_t(y0 + dy) * size_t(im.step) + 3 * size_t(x0 + dx);
    for (int ch = 0; ch < 3; ++ch) c[ch] += w * q[ch];
  }
  const double mx = std::max({c[0], c[1], c[2]}), mn = std::min({c[0], c[1], c[2]});
  return mx > 0.0 ? mn / mx : 1.0;
}

// The 1-D projective map from x = 1 - (fraction of the height) (0 at the apex, 1 at the base) to the distance along
// the axis's image from where the scan measures it: s(x) = s0 + a x / (1 + c x), s0 the apex. It is the image of the
// straight front line of the cone.
struct Map {
  double s0 = 0.0, a = 0.0, c = 0.0;
  double operator()(double x) const { return s0 + a * x / (1.0 + c * x); }
  Eigen::RowVector3d Gradient(double x) const {  // by (s0, a, c)
    const double den = 1.0 + c * x;
    return {1.0, x / den, -a * x * x / (den * den)};
  }
};

// Least squares of s_i = map(x_i), s0 = 0 held when free_apex is false: the linear form s_i (1 + c x_i) = a x_i
// from s0 = 0, then Gauss-Newton on the pixels. cov: the parameters' covariance per unit pixel variance.
bool FitMap(const std::vector<double>& x, const std::vector<double>& s, bool free_apex, Map* map,
            Eigen::Matrix3d* cov) {
  Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
  for (size_t i = 0; i < x.size(); ++i) {
    const Eigen::Vector2d row(x[i], -x[i] * s[i]);
    A += row * row.transpose(), b += row * s[i];
  }
  const Eigen::Vector2d ac = A.ldlt().solve(b);
  Eigen::Vector3d theta(0.0, ac(0), ac(1));
  const int first = free_apex ? 0 : 1;  // the parameters fitted
  Eigen::Matrix3d JtJ;
  for (int it = 0; it < 8 && theta.allFinite(); ++it) {
    const Map m{theta(0), theta(1), theta(2)};
    JtJ.setZero();
    Eigen::Vector3d Jtr = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < x.size(); ++i) {
      const Eigen::RowVector3d g = m.Gradient(x[i]);
      JtJ += g.transpose() * g, Jtr += g.transpose() * (s[i] - m(x[i]));
    }
    const int n = 3 - first;
    theta.tail(n) += JtJ.bottomRightCorner(n, n).ldlt().solve(Jtr.tail(n));
  }
  *map = Map{theta(0), theta(1), theta(2)};
  const int n = 3 - first;
  cov->setZero();
  cov->bottomRightCorner(n, n) = JtJ.bottomRightCorner(n, n).inverse();
  // Increasing over the cone, the base in front of the camera (1 + c x > 0 up to x = 1).
  return theta.allFinite() && cov->allFinite() && map->a > 0.0 && 1.0 + map->c > 0.1;
}

// The runs above row `above_y` whose two ends (the silhouette's edges half a pixel past the end pixels, undistorted)
// lie within tol_px of the fitted edge lines.
std::vector<Run> RunsOnEdges(const std::vector<Run>& runs, int above_y, const OutlineFit& fit,
                             const CameraModel& camera, double tol_px) {
  std::vector<Run> above;
  std::vector<Eigen::Vector2d> ends;
  for (const Run& r : runs)
    if (r.y < above_y) above.push_back(r), ends.emplace_back(r.x0 - 0.5, r.y), ends.emplace_back(r.x1 + 0.5, r.y);
  if (!UndistortPixels(camera, &ends, 1e-2)) return {};
  const auto distance = [](const Eigen::Vector3d& line, const Eigen::Vector2d& p) {
    return std::abs(line.head<2>().dot(p) + line.z()) / line.head<2>().norm();
  };
  std::vector<Run> on;
  for (size_t i = 0; i < above.size(); ++i)
    if (distance(fit.left_line, ends[2 * i]) < tol_px && distance(fit.right_line, ends[2 * i + 1]) < tol_px)
      on.push_back(above[i]);
  return on;
}

}  // namespace

std::string CollarRulerConfig::Validate() const {
  double below = 1.0;
  std::vector<std::pair<double, double>> sorted = collars;
  std::sort(sorted.begin(), sorted.end(), [](const auto& p, const auto& q) { return p.second > q.second; });
  for (const auto& [from, to] : sorted) {
    if (!(from > 0.0 && from < to && to < below))
      return "collar.collars must be disjoint (from, to) fractions of the height in (0, 1)";
    below = from;
  }
  if (!(white_ratio > 0.0 && white_ratio < 1.0)) return "collar.white_ratio must be in (0, 1)";
  if (!(max_residual_px > 0.0)) return "collar.max_residual_px must be > 0";
  if (!(edge_sigma_px > 0.0)) return "collar.edge_sigma_px must be > 0";
  return "";
}

CollarReading ReadCollars(const RgbView& image, const CameraModel& camera, const Eigen::Vector2d& apex_undist_px,
                          const Eigen::Vector2d& axis_dir, double start_px, bool apex_known,
                          const CollarRulerConfig& config) {
  CollarReading out;
  // The collar edges from the top down, as x = 1 - fraction of the height: orange to white at a collar's top, back
  // at its bottom.
  std::vector<std::pair<double, double>> collars = config.collars;
  std::sort(collars.begin(), collars.end(), [](const auto& p, const auto& q) { return p.second > q.second; });
  std::vector<double> edge_x;
  for (const auto& [from, to] : collars) edge_x.push_back(1.0 - to), edge_x.push_back(1.0 - from);
  const size_t min_edges = apex_known ? 3 : 4;  // one more than the map's parameters: a check
  if (edge_x.size() < min_edges) return out.why = "too few collar edges on the cone", out;
  if (!image.data) return out.why = "no image", out;

  // Samples down the axis to the image's edge: up to where the undistorted line is well outside it (the lens model
  // is not meant for points far outside).
  std::vector<Eigen::Vector2d> raw;
  const Eigen::Vector2d lo(-0.25 * image.width, -0.25 * image.height), hi(1.25 * image.width, 1.25 * image.height);
  for (double s = start_px;; s += kStepPx) {
    const Eigen::Vector2d p = apex_undist_px + s * axis_dir;
    if (!((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all())) break;
    raw.push_back(p);
  }
  if (!DistortPixels(camera, &raw)) return out.why = "distortion failed", out;
  std::vector<double> ratio;
  for (const Eigen::Vector2d& p : raw) {
    const double r = WhiteRatio(image, p);
    if (std::isnan(r)) break;
    ratio.push_back(r);
  }
  if (ratio.empty() || ratio[0] >= config.white_ratio) return out.why = "the axis does not start in orange", out;

  // Where the samples change from orange to white and back, interpolated to a fraction of a step.
  int last_k = 0;
  for (size_t k = 1; k < ratio.size(); ++k) {
    const bool was = ratio[k - 1] >= config.white_ratio, is = ratio[k] >= config.white_ratio;
    if (was == is) continue;
    if (int(k) - last_k < kMinRunSteps) return out.why = "a band under a pixel long", out;
    last_k = int(k);
    const double f = (config.white_ratio - ratio[k - 1]) / (ratio[k] - ratio[k - 1]);
    out.edges_px.push_back(start_px + (double(k) - 1.0 + f) * kStepPx);
  }
  if (out.edges_px.size() > edge_x.size()) return out.why = "more edges than collars: the base is in view", out;
  if (out.edges_px.size() < min_edges) return out.why = "too few collar edges before the image's edge", out;

  const std::vector<double> x(edge_x.begin(), edge_x.begin() + long(out.edges_px.size()));
  Map map;
  Eigen::Matrix3d unit_cov;
  if (!FitMap(x, out.edges_px, !apex_known, &map, &unit_cov)) return out.why = "the edges fit no cone", out;
  for (size_t i = 0; i < x.size(); ++i)
    out.residual_px = std::max(out.residual_px, std::abs(out.edges_px[i] - map(x[i])));
  if (!(out.residual_px <= config.max_residual_px)) return out.why = "the edges are not a cone's collars", out;
  const Eigen::Matrix3d cov = config.edge_sigma_px * config.edge_sigma_px * unit_cov;
  const double at[3] = {0.0, 0.5, 1.0};  // peak, mid, base
  for (int k = 0; k < 3; ++k) {
    const Eigen::RowVector3d g = map.Gradient(at[k]);
    out.points_undist_px[size_t(k)] = apex_undist_px + map(at[k]) * axis_dir;
    out.axis_sigma_px(k) = std::sqrt(g * cov * g.transpose());
  }
  out.ok = true;
  return out;
}

void Segmenter::ReadCutCones(std::vector<ConeDetection>* dets, const CameraModel& camera) const {
  if (config_.refinement() != PeakRefinement::kOutline || !config_.read_collars || config_.collar.collars.empty())
    return;
  std::vector<Eigen::Vector2d> accepted_peaks;
  std::vector<const std::vector<Run>*> refused;
  for (const ConeDetection& d : *dets)
    if (d.accepted())
      accepted_peaks.push_back(d.peak_px);
    else
      refused.push_back(&d.blob.runs);
  std::vector<ConeDetection> read;
  for (const ConeDetection& cut : *dets) {
    if (cut.accepted() || cut.blob.bbox_y + cut.blob.bbox_h < frame_h_ - config_.border_px) continue;
    std::vector<Run> runs;
    const OutlineFit fit = FitCutCone(cut.blob.runs, refused, camera, &runs);
    if (!(fit.left_line.head<2>().norm() > 0.0)) continue;  // the edges did not fit, or did not meet
    Eigen::Vector2d d = OutlineAxisLine(fit.left_line, fit.right_line, camera).head<2>();
    d = Eigen::Vector2d(d.y(), -d.x());
    std::vector<Eigen::Vector2d> bottom = {Eigen::Vector2d(0.5 * (runs.front().x0 + runs.front().x1), runs.front().y)};
    if (!(d.norm() > 0.0) || !UndistortPixels(camera, &bottom)) continue;
    d.normalize();
    if (d.dot(bottom[0] - fit.apex_undist_px) < 0.0) d = -d;
    // The apex is the edges' when the tip reaches it (the tip's rows joined the fit); else, extrapolated from the
    // body's edges, it is known only roughly, and the collars place it along the axis.
    const bool apex_known = fit.tip_short_px >= -1.5 && fit.tip_short_px <= fit.tip_zone_px;
    const CollarReading r = ReadCollars(RgbView{frame_rgb_, frame_w_, frame_h_, frame_step_}, camera,
                                        fit.apex_undist_px, d, fit.tip_zone_px, apex_known, config_.collar);
    if (!r.ok) continue;
    std::vector<Eigen::Vector2d> raw(r.points_undist_px.begin(), r.points_undist_px.end());
    if (!DistortPixels(camera, &raw)) continue;
    bool seen = false;
    for (const Eigen::Vector2d& p : accepted_peaks) seen |= (p - raw[0]).norm() < 2.0;
    if (seen) continue;
    ConeDetection det;
    det.blob = BlobOfRuns(std::move(runs));  // the cone's rows that the fit took
    det.by_collars = true;
    det.peak_px = raw[0], det.mid_px = raw[1], det.base_px = raw[2];
    det.peak_undist_px = r.points_undist_px[0], det.mid_undist_px = r.points_undist_px[1];
    det.base_undist_px = r.points_undist_px[2];
    det.axis_sigma_px = r.axis_sigma_px;
    accepted_peaks.push_back(raw[0]);
    read.push_back(std::move(det));
  }
  for (ConeDetection& det : read) dets->push_back(std::move(det));
}

OutlineFit Segmenter::FitCutCone(const std::vector<Run>& cut, const std::vector<const std::vector<Run>*>& refused,
                                 const CameraModel& camera, std::vector<Run>* runs) const {
  // The cone's lower body: the blob's rows from the image's bottom edge up, one run each, to the first row without
  // one (a collar) or with two (another cone beside it). Its edges are the cone's.
  std::vector<const Run*> by_row(size_t(frame_h_), nullptr);
  std::vector<int> count(size_t(frame_h_), 0);
  int y_max = -1;
  for (const Run& r : cut) by_row[size_t(r.y)] = &r, ++count[size_t(r.y)], y_max = std::max(y_max, r.y);
  std::vector<Run> body;
  for (int y = y_max; y >= 0 && count[size_t(y)] == 1; --y) body.push_back(*by_row[size_t(y)]);
  *runs = body;
  if (int(body.size()) < kMinBodyRows) return OutlineFit();
  const Eigen::Vector2d low(0.5 * (body.front().x0 + body.front().x1), body.front().y);
  OutlineFit fit = FitConeOutline(body, Eigen::Vector2d(0.5 * (body.back().x0 + body.back().x1), body.back().y), low,
                                  camera, config_.outline);
  // Extrapolated from the lower body alone the apex can be pixels off the cone's axis (a body 57 rows tall below an
  // apex 140 rows above it: look_away seed 52): the rows above the body whose run ends both lie on the edges, in the
  // cut blob or another refused one (the orange between the collars, the tip where nothing orange is beside it),
  // join the fit, within 2 px of the body's lines, then 1 px of the refitted ones.
  for (int pass = 0; pass < 2 && fit.left_line.head<2>().norm() > 0.0; ++pass) {
    std::vector<Run> cone = body;
    for (const std::vector<Run>* other : refused)
      for (const Run& r : RunsOnEdges(*other, body.back().y, fit, camera, 2.0 - pass)) cone.push_back(r);
    if (cone.size() == body.size()) break;
    const Run& top = *std::min_element(cone.begin(), cone.end(), [](const Run& a, const Run& b) { return a.y < b.y; });
    fit = FitConeOutline(cone, Eigen::Vector2d(0.5 * (top.x0 + top.x1), top.y), low, camera, config_.outline);
    *runs = std::move(cone);
  }
  return fit;
}

}  // namespace cone_tracker
