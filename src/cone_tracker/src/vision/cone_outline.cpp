#include "cone_tracker/vision/cone_outline.h"

#include <algorithm>
#include <climits>
#include <cmath>

#include <opencv2/calib3d.hpp>

#include "cone_tracker/vision/segmenter.h"

namespace cone_tracker {

namespace {

// x = a + b y through points weighted 0/1; returns false when degenerate.
bool FitLine(const std::vector<Eigen::Vector2d>& p, const std::vector<char>& use, double* a, double* b) {
  double n = 0, sy = 0, syy = 0, sx = 0, sxy = 0;
  for (size_t i = 0; i < p.size(); ++i)
    if (use[i]) n += 1, sy += p[i].y(), syy += p[i].y() * p[i].y(), sx += p[i].x(), sxy += p[i].x() * p[i].y();
  const double det = n * syy - sy * sy;
  if (n < 4 || !(det > 1e-9 * n * n)) return false;
  *b = (n * sxy - sy * sx) / det;
  *a = (sx - *b * sy) / n;
  return true;
}

struct EdgeFit {
  double a = 0, b = 0, rms = INFINITY, inlier_frac = 0, outward_frac = 0;
};

// Robust line through one edge's points: the line through two of the points
// away from the base arc that most points lie near (a deterministic RANSAC:
// collar rims and where a tilted collar crosses a row put many points off the
// edge, all on one side), then least squares over the points within
// outlier_px of it.
// outward: +1 when the outside of the silhouette is toward +x (the right edge).
bool FitEdge(const std::vector<Eigen::Vector2d>& p, const std::vector<char>& initial, const std::vector<char>& counted,
             double outlier_px, double outward, EdgeFit* fit) {
  std::vector<size_t> cand;
  for (size_t i = 0; i < p.size(); ++i)
    if (initial[i]) cand.push_back(i);
  if (cand.size() < 4) return false;
  const size_t half = cand.size() / 2;
  int best_count = -1;
  for (size_t k = 0; k < 48; ++k) {
    const Eigen::Vector2d& q1 = p[cand[(k * 7919) % half]];
    const Eigen::Vector2d& q2 = p[cand[half + (k * 104729 + k / 3) % (cand.size() - half)]];
    if (std::abs(q2.y() - q1.y()) < 2.0) continue;
    const double b = (q2.x() - q1.x()) / (q2.y() - q1.y()), a = q1.x() - b * q1.y();
    const double tol = outlier_px * std::sqrt(1.0 + b * b);
    int count = 0;
    for (size_t i : cand) count += std::abs(p[i].x() - a - b * p[i].y()) < tol;
    if (count > best_count) best_count = count, fit->a = a, fit->b = b;
  }
  if (best_count < 4) return false;
  std::vector<char> use(p.size());
  for (int iter = 0; iter < 3; ++iter) {
    const double scale = 1.0 / std::sqrt(1.0 + fit->b * fit->b);  // x residual -> distance
    for (size_t i = 0; i < p.size(); ++i) use[i] = std::abs(p[i].x() - fit->a - fit->b * p[i].y()) * scale < outlier_px;
    if (!FitLine(p, use, &fit->a, &fit->b)) return false;
  }
  const double scale = 1.0 / std::sqrt(1.0 + fit->b * fit->b);
  double ss = 0, n = 0, in_counted = 0, counted_n = 0, out_n = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    const double r = (p[i].x() - fit->a - fit->b * p[i].y()) * scale;
    const bool in = std::abs(r) < outlier_px;
    if (in) ss += r * r, n += 1;
    if (counted[i]) counted_n += 1, in_counted += in;
    out_n += r * outward > outlier_px;
  }
  fit->rms = n > 0 ? std::sqrt(ss / n) : INFINITY;
  fit->inlier_frac = counted_n > 0 ? in_counted / counted_n : 0.0;
  fit->outward_frac = p.empty() ? 0.0 : out_n / double(p.size());
  return true;
}

}  // namespace

bool DistortPixels(const CameraModel& camera, std::vector<Eigen::Vector2d>* points) {
  if (!camera.HasDistortion() || !(camera.fx_px > 0.0) || !(camera.fy_px > 0.0)) return true;
  std::vector<cv::Point3d> rays;
  for (const auto& p : *points)
    rays.emplace_back((p.x() - camera.cx_px) / camera.fx_px, (p.y() - camera.cy_px) / camera.fy_px, 1.0);
  const cv::Matx33d K(camera.fx_px, 0, camera.cx_px, 0, camera.fy_px, camera.cy_px, 0, 0, 1);
  std::vector<cv::Point2d> out;
  try {
    cv::projectPoints(rays, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, camera.distortion, out);  // (3.10)
  } catch (const cv::Exception&) {
    return false;
  }
  for (size_t i = 0; i < out.size(); ++i) {
    if (!std::isfinite(out[i].x) || !std::isfinite(out[i].y)) return false;
    (*points)[i] = Eigen::Vector2d(out[i].x, out[i].y);
  }
  return true;
}

Eigen::Vector3d OutlineAxisLine(const Eigen::Vector3d& left_line, const Eigen::Vector3d& right_line,
                                const CameraModel& camera) {
  // The mirror plane's image is the bisector of the edges as unit 3-vectors in normalised coordinates
  // (l_n = K^T l), mapped back (K^-T).
  if (!(camera.fx_px > 0.0 && camera.fy_px > 0.0))
    return left_line / left_line.head<2>().norm() - right_line / right_line.head<2>().norm();
  Eigen::Matrix3d K;
  K << camera.fx_px, 0, camera.cx_px, 0, camera.fy_px, camera.cy_px, 0, 0, 1;
  const Eigen::Vector3d n = (K.transpose() * left_line).normalized() - (K.transpose() * right_line).normalized();
  return K.transpose().inverse() * n;
}

OutlineFit FitConeOutline(const std::vector<Run>& runs, const Eigen::Vector2d& peak_guess,
                          const Eigen::Vector2d& base_guess, const CameraModel& camera, const OutlineConfig& config) {
  OutlineFit out;
  const Eigen::Vector2d axis_guess = base_guess - peak_guess;
  const double height = axis_guess.norm();
  if (!(height >= 6.0)) return out.why = "too small", out;
  const Eigen::Vector2d dir_guess = axis_guess / height;
  if (std::abs(dir_guess.y()) < std::cos(config.max_tilt_deg * M_PI / 180.0)) return out.why = "tilted", out;
  // Per row the outermost pixels; the edge lies half a pixel beyond their
  // centres. Dense over the blob's rows and columns (ascending, as the fits
  // expect), not maps: this runs per blob per frame.
  int y_lo = INT_MAX, y_hi = INT_MIN;
  for (const Run& r : runs) y_lo = std::min(y_lo, r.y), y_hi = std::max(y_hi, r.y);
  std::vector<std::pair<int, int>> row_ext(runs.empty() ? 0 : size_t(y_hi - y_lo + 1), {INT_MAX, INT_MIN});
  for (const Run& r : runs) {
    auto& e = row_ext[size_t(r.y - y_lo)];
    e.first = std::min(e.first, r.x0), e.second = std::max(e.second, r.x1);
  }
  // Per column the last pixel toward the base, in the base end of the blob.
  const bool base_down = dir_guess.y() > 0.0;
  auto in_base_end = [&](const Run& r) {
    return !((Eigen::Vector2d(0.5 * (r.x0 + r.x1), r.y) - peak_guess).dot(dir_guess) < 0.6 * height);
  };
  int x_lo = INT_MAX, x_hi = INT_MIN;
  for (const Run& r : runs)
    if (in_base_end(r)) x_lo = std::min(x_lo, r.x0), x_hi = std::max(x_hi, r.x1);
  const int no_row = base_down ? INT_MIN : INT_MAX;
  std::vector<int> bottom(x_hi >= x_lo ? size_t(x_hi - x_lo + 1) : 0, no_row);
  for (const Run& r : runs) {
    if (!in_base_end(r)) continue;
    for (int x = r.x0; x <= r.x1; ++x) {
      int& b = bottom[size_t(x - x_lo)];
      b = base_down ? std::max(b, r.y) : std::min(b, r.y);
    }
  }
  std::vector<Eigen::Vector2d> pts;
  pts.reserve(2 * row_ext.size() + bottom.size() + 2);
  size_t nr = 0;
  for (size_t i = 0; i < row_ext.size(); ++i)
    if (row_ext[i].first != INT_MAX) pts.emplace_back(row_ext[i].first - 0.5, y_lo + int(i)), ++nr;
  for (size_t i = 0; i < row_ext.size(); ++i)
    if (row_ext[i].first != INT_MAX) pts.emplace_back(row_ext[i].second + 0.5, y_lo + int(i));
  for (size_t i = 0; i < bottom.size(); ++i)
    if (bottom[i] != no_row) pts.emplace_back(x_lo + int(i), bottom[i] + (base_down ? 0.5 : -0.5));
  // Undistorted with the outline, in one call: the line search's ends, and one raw pixel along the axis from the
  // peak, which gives the lens's local scale there (undistorted px per raw px).
  pts.push_back(peak_guess), pts.push_back(base_guess), pts.push_back(peak_guess + dir_guess);
  if (!UndistortPixels(camera, &pts)) return out.why = "undistortion failed", out;
  const std::vector<Eigen::Vector2d> guesses(pts.end() - 3, pts.end());
  pts.resize(pts.size() - 3);
  const double raw_px = (guesses[2] - guesses[0]).norm();
  if (!(raw_px > 0.0)) return out.why = "undistortion failed", out;
  const std::vector<Eigen::Vector2d> left(pts.begin(), pts.begin() + long(nr)),
      right(pts.begin() + long(nr), pts.begin() + long(2 * nr)), arc(pts.begin() + long(2 * nr), pts.end());
  const Eigen::Vector2d peak0 = guesses[0], dir0 = (guesses[1] - guesses[0]).normalized();
  const double h0 = (guesses[1] - guesses[0]).norm();
  // Rows clear of the base arc start the fit and count toward the inlier fraction.
  std::vector<char> initial(nr), counted(nr);
  for (size_t i = 0; i < nr; ++i) {
    const double t = (0.5 * (left[i] + right[i]) - peak0).dot(dir0) / h0;
    initial[i] = t > 0.02 && t < 0.75;
    counted[i] = t < 0.75;
  }
  EdgeFit fl, fr;
  if (!FitEdge(left, initial, counted, config.outlier_px, -1.0, &fl) ||
      !FitEdge(right, initial, counted, config.outlier_px, +1.0, &fr))
    return out.why = "edge fit failed", out;
  out.edge_rms_px = std::max(fl.rms, fr.rms);
  out.inlier_frac = std::min(fl.inlier_frac, fr.inlier_frac);
  if (!(out.edge_rms_px <= config.max_edge_rms_px)) return out.why = "edges not straight", out;
  // Inward outliers are normal (collar rims, where a tilted collar crosses a
  // row, the base arc, an occluder in front); outward ones are not: pixels
  // beyond a cone's edge belong to something else merged into the blob.
  out.outward_frac = std::max(fl.outward_frac, fr.outward_frac);
  if (!(out.inlier_frac >= config.min_inlier_frac)) return out.why = "too little of an edge is straight", out;
  if (!(out.outward_frac <= config.max_outward_frac)) return out.why = "outline is not one cone", out;
  // Lines x - b y - a = 0, oriented positive inside the silhouette.
  const Eigen::Vector3d inside(0.5 * (guesses[0] + guesses[1]).x(), 0.5 * (guesses[0] + guesses[1]).y(), 1.0);
  Eigen::Vector3d l1(1.0, -fl.b, -fl.a), l2(1.0, -fr.b, -fr.a);
  if (l1.dot(inside) < 0) l1 = -l1;
  if (l2.dot(inside) < 0) l2 = -l2;
  if (!(l1.dot(inside) > 0 && l2.dot(inside) > 0)) return out.why = "edges cross inside", out;
  const Eigen::Vector3d apex_h = l1.cross(l2);
  if (!(std::abs(apex_h.z()) > 1e-12)) return out.why = "parallel edges", out;
  const Eigen::Vector2d apex = apex_h.head<2>() / apex_h.z();
  if (!apex.allFinite()) return out.why = "no apex", out;
  // The binary tip ends where the silhouette gets narrower than about a
  // pixel, short of the apex; no cone pixel lies beyond the apex. The tip is
  // the blob's farthest pixel toward the peak, not the line search's end: a
  // cone seen obliquely from above leans in the image (more so toward its
  // side edges), its one-pixel-wide tip leaves the blob's principal axis, and
  // the line search stops up to ~12 px short of it. "A pixel" is the sensor's: the gaps are measured in raw
  // pixels (raw_px undistorted px each), or a small cone's tip where the lens shrinks the image (its corners)
  // would look cut off.
  double tip = 0.0;
  for (const auto* side : {&left, &right})
    for (const Eigen::Vector2d& p : *side) tip = std::min(tip, (p - peak0).dot(dir0));
  const double tan_half = std::tan(0.5 * std::abs(std::atan(fl.b) - std::atan(fr.b)));
  out.tip_zone_px = 3.0 + 1.0 / std::max(tan_half, 0.02);
  const double along = ((apex - peak0).dot(dir0) - tip) / raw_px,
               lateral = std::abs((apex - peak0).dot(Eigen::Vector2d(dir0.y(), -dir0.x()))) / raw_px;
  out.left_line = l1, out.right_line = l2, out.apex_undist_px = apex, out.tip_short_px = -along;
  if (along > 1.5 || along < -out.tip_zone_px || lateral > 3.0 + config.max_apex_gap_frac * h0 / raw_px)
    return out.why = "apex does not fit the tip", out;
  const Eigen::Vector3d axis = OutlineAxisLine(l1, l2, camera);
  Eigen::Vector2d d(axis.y(), -axis.x());
  if (!(d.norm() > 0)) return out.why = "no axis", out;
  d.normalize();
  if (d.dot(dir0) < 0) d = -d;
  const Eigen::Vector2d e(d.y(), -d.x());
  // The front arc near the axis: t(s) = c0 + c1 s + c2 s^2 over the points
  // within 60% of the base half-width of the axis; the base is at s = 0.
  double s_lo = 0, s_hi = 0;
  for (const auto& q : arc) s_lo = std::min(s_lo, (q - apex).dot(e)), s_hi = std::max(s_hi, (q - apex).dot(e));
  const double half = 0.6 * std::min(-s_lo, s_hi);
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  int n_arc = 0;
  double t_near = -INFINITY;
  for (const auto& q : arc) {
    const double s = (q - apex).dot(e), t = (q - apex).dot(d);
    if (std::abs(s) > half) continue;
    const Eigen::Vector3d phi(1.0, s, s * s);
    A += phi * phi.transpose(), rhs += phi * t, ++n_arc;
    if (std::abs(s) < 1.0) t_near = std::max(t_near, t);
  }
  double t_base = t_near;
  if (n_arc >= 5 && half >= 2.0) {
    const Eigen::Vector3d c = A.ldlt().solve(rhs);
    t_base = c(0);
    // Something in front of the base (another cone's collar, say) leaves a
    // notch in the arc: its points fall off the parabola.
    double ss = 0.0;
    for (const auto& q : arc) {
      const double s = (q - apex).dot(e), t = (q - apex).dot(d);
      if (std::abs(s) <= half) ss += std::pow(t - c(0) - c(1) * s - c(2) * s * s, 2);
    }
    out.arc_rms_px = std::sqrt(ss / n_arc);
    if (!(out.arc_rms_px <= config.max_edge_rms_px)) return out.why = "base arc not an ellipse", out;
  }
  const Eigen::Vector2d base = apex + t_base * d;
  if (!base.allFinite()) return out.why = "no base", out;
  std::vector<Eigen::Vector2d> raw = {apex, base};
  if (!DistortPixels(camera, &raw)) return out.why = "distortion failed", out;
  out.peak_undist_px = apex, out.base_undist_px = base;
  out.peak_px = raw[0], out.base_px = raw[1];
  out.axis_line = axis;
  out.ok = true;
  return out;
}

}  // namespace cone_tracker
