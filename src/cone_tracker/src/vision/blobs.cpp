#include "cone_tracker/vision/blobs.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>

#include <opencv2/imgproc.hpp>

namespace cone_tracker {

namespace {
// Sum of k^2 for k = 0..n.
double SumSq(double n) { return n * (n + 1.0) * (2.0 * n + 1.0) / 6.0; }

int Find(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// 8-connectivity: joins every run with the runs of the row above that it touches (overlapping or diagonal). runs are
// sorted by row, then by x0; parent starts as the identity.
void UnionTouchingRuns(const std::vector<Run>& runs, std::vector<int>* parent) {
  size_t above = 0, row = 0;  // the first runs of the row above and of the current row
  for (size_t i = 0; i < runs.size(); ++i) {
    if (runs[i].y != runs[row].y) {
      above = runs[i].y == runs[row].y + 1 ? row : i;
      row = i;
    }
    for (size_t j = above; j < row; ++j) {
      if (runs[j].x1 < runs[i].x0 - 1) continue;
      if (runs[j].x0 > runs[i].x1 + 1) break;
      const int a = Find(*parent, int(i)), b = Find(*parent, int(j));
      if (a != b) (*parent)[size_t(std::max(a, b))] = std::min(a, b);
    }
  }
}
}  // namespace

double WidthAcross(const std::vector<Run>& runs, const Eigen::Vector2d& origin, const Eigen::Vector2d& axis,
                   double t_lo, double t_hi) {
  double lo = INFINITY, hi = -INFINITY;
  for (const Run& r : runs)
    for (int x : {r.x0, r.x1}) {
      const Eigen::Vector2d d = Eigen::Vector2d(x, r.y) - origin;
      const double t = d.dot(axis);
      if (t < t_lo || t > t_hi) continue;
      const double s = d.x() * axis.y() - d.y() * axis.x();
      lo = std::min(lo, s), hi = std::max(hi, s);
    }
  return hi >= lo ? hi - lo + 1.0 : 0.0;
}

std::vector<rig_model::ImageBox> RowSlabs(const std::vector<Run>& runs, int slabs) {
  if (runs.empty() || slabs < 1) return {};
  int y_lo = runs[0].y, y_hi = runs[0].y;
  for (const Run& r : runs) y_lo = std::min(y_lo, r.y), y_hi = std::max(y_hi, r.y);
  const int rows = y_hi - y_lo + 1, n = std::min(slabs, rows);
  std::vector<rig_model::ImageBox> box(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {  // every row of the band, those of a white collar between fragments too
    box[size_t(i)].v_min = y_lo + (i * rows + n - 1) / n - 0.5;
    box[size_t(i)].v_max = y_lo + ((i + 1) * rows + n - 1) / n - 0.5;
    box[size_t(i)].u_min = INFINITY, box[size_t(i)].u_max = -INFINITY;
  }
  for (const Run& r : runs) {
    rig_model::ImageBox& b = box[size_t((r.y - y_lo) * n / rows)];
    b.u_min = std::min(b.u_min, r.x0 - 0.5), b.u_max = std::max(b.u_max, r.x1 + 0.5);
  }
  // A band wholly inside a collar takes the columns of the band below it (nearer the base), else above.
  const auto take_columns = [&](size_t to, size_t from) {
    if (!(box[to].u_max > box[to].u_min)) box[to].u_min = box[from].u_min, box[to].u_max = box[from].u_max;
  };
  for (size_t i = size_t(n) - 1; i-- > 0;) take_columns(i, i + 1);
  for (size_t i = 1; i < size_t(n); ++i) take_columns(i, i - 1);
  return box;
}

void Moments::Add(const Run& r) {
  const double len = r.x1 - r.x0 + 1.0, y = r.y;
  const double sx_run = 0.5 * len * (r.x0 + r.x1);
  n += len;
  sx += sx_run;
  sy += len * y;
  sxx += SumSq(r.x1) - SumSq(r.x0 - 1.0);  // valid for x0 >= 0
  syy += len * y * y;
  sxy += y * sx_run;
}

void Moments::Add(const Moments& o) {
  n += o.n;
  sx += o.sx;
  sy += o.sy;
  sxx += o.sxx;
  syy += o.syy;
  sxy += o.sxy;
}

double HullArea(const std::vector<Run>& runs) {
  std::vector<cv::Point2f> pts;
  pts.reserve(runs.size() * 4);
  for (const Run& r : runs) {
    pts.emplace_back(r.x0 - 0.5f, r.y - 0.5f);
    pts.emplace_back(r.x0 - 0.5f, r.y + 0.5f);
    pts.emplace_back(r.x1 + 0.5f, r.y - 0.5f);
    pts.emplace_back(r.x1 + 0.5f, r.y + 0.5f);
  }
  std::vector<cv::Point2f> hull;
  cv::convexHull(pts, hull);
  return cv::contourArea(hull);
}

void ComputeProperties(Blob* b) {
  const Moments& m = b->m;
  b->area = m.n;
  b->centroid = Eigen::Vector2d(m.sx / m.n, m.sy / m.n);
  // Second central moments of the pixel squares (+1/12), as regionprops.
  const double mu20 = m.sxx / m.n - b->centroid.x() * b->centroid.x() + 1.0 / 12.0;
  const double mu02 = m.syy / m.n - b->centroid.y() * b->centroid.y() + 1.0 / 12.0;
  const double mu11 = m.sxy / m.n - b->centroid.x() * b->centroid.y();
  const double common = std::sqrt((mu20 - mu02) * (mu20 - mu02) + 4.0 * mu11 * mu11);
  b->major_px = 2.0 * std::sqrt(2.0) * std::sqrt(std::max(0.0, mu20 + mu02 + common));
  b->minor_px = 2.0 * std::sqrt(2.0) * std::sqrt(std::max(0.0, mu20 + mu02 - common));
  b->orientation_rad = 0.5 * std::atan2(2.0 * mu11, mu20 - mu02);
  b->axis_ratio = b->minor_px > 0.0 ? b->major_px / b->minor_px : INFINITY;
  b->solidity = b->hull_area > 0.0 ? std::min(1.0, b->area / b->hull_area) : 0.0;
  int x0 = INT32_MAX, y0 = INT32_MAX, x1 = INT32_MIN, y1 = INT32_MIN;
  for (const Run& r : b->runs) {
    x0 = std::min(x0, r.x0), x1 = std::max(x1, r.x1), y0 = std::min(y0, r.y), y1 = std::max(y1, r.y);
  }
  b->bbox_x = x0, b->bbox_y = y0, b->bbox_w = x1 - x0 + 1, b->bbox_h = y1 - y0 + 1;
}

bool MaskHitAlong(const MaskView& mask, const Eigen::Vector2d& from, const Eigen::Vector2d& dir, double t_lo,
                  double t_hi, double t_step, double side_px) {
  const Eigen::Vector2d across(dir.y(), -dir.x());
  for (double t = t_lo; t <= t_hi; t += t_step)
    for (double s : {-side_px, 0.0, side_px}) {
      const Eigen::Vector2d p = from + t * dir + s * across;
      if (mask.At(int(std::lround(p.x())), int(std::lround(p.y())))) return true;
    }
  return false;
}

Blob BlobOfRuns(std::vector<Run> runs) {
  Blob b;
  std::sort(runs.begin(), runs.end(), [](const Run& a, const Run& c) { return a.y != c.y ? a.y < c.y : a.x0 < c.x0; });
  std::vector<int> parent(runs.size());
  std::iota(parent.begin(), parent.end(), 0);
  UnionTouchingRuns(runs, &parent);
  std::vector<std::vector<Run>> pieces(runs.size());
  for (size_t i = 0; i < runs.size(); ++i) pieces[size_t(Find(parent, int(i)))].push_back(runs[i]);
  b.fragments = 0;
  for (const std::vector<Run>& piece : pieces)
    if (!piece.empty()) b.hull_area += HullArea(piece), ++b.fragments;
  for (const Run& r : runs) b.m.Add(r);
  b.runs = std::move(runs);
  if (b.m.n > 0) ComputeProperties(&b);
  return b;
}

std::vector<Blob> FindBlobs(const MaskView& mask, int x0, int y0, int x1, int y1, int min_area_px) {
  x0 = std::max(0, x0), y0 = std::max(0, y0);
  x1 = std::min(mask.width, x1), y1 = std::min(mask.height, y1);
  std::vector<Run> runs;
  for (int y = y0; y < y1; ++y) {
    const uint8_t* row = mask.data + size_t(y) * mask.step;
    for (int x = x0; x < x1;) {
      if (!row[x]) {  // background: skip it eight pixels at a time
        uint64_t word = 0;
        while (x + 8 <= x1 && (std::memcpy(&word, row + x, 8), word == 0)) x += 8;
        if (x < x1 && !row[x]) ++x;
        continue;
      }
      const int start = x;
      while (x < x1 && row[x]) ++x;
      runs.push_back({y, start, x - 1});
    }
  }
  std::vector<int> parent(runs.size());
  std::iota(parent.begin(), parent.end(), 0);
  UnionTouchingRuns(runs, &parent);
  std::vector<int> blob_of(runs.size(), -1);
  std::vector<Blob> blobs;
  for (size_t i = 0; i < runs.size(); ++i) {
    const int root = Find(parent, int(i));
    if (blob_of[root] < 0) {
      blob_of[root] = int(blobs.size());
      blobs.emplace_back();
    }
    Blob& b = blobs[blob_of[root]];
    b.runs.push_back(runs[i]);
    b.m.Add(runs[i]);
  }
  std::vector<Blob> kept;
  for (Blob& b : blobs) {
    if (b.m.n < min_area_px) continue;
    b.hull_area = HullArea(b.runs);
    ComputeProperties(&b);
    kept.push_back(std::move(b));
  }
  return kept;
}

namespace {

// The cone axis one blob shows, pointing down the image (peak to base), or
// zero when its shape does not say: an elongated blob (a whole cone, a tip)
// lies along its major axis; one clearly wider than tall (the body below a
// collar, a band between two) lies across it; a near-round one says nothing.
// An axis further than max_tilt_rad from the image vertical is no cone's.
Eigen::Vector2d ConeAxisOf(const Blob& b, double max_tilt_rad) {
  const Eigen::Vector2d major(std::cos(b.orientation_rad), std::sin(b.orientation_rad));
  Eigen::Vector2d axis = Eigen::Vector2d::Zero();
  if (b.axis_ratio >= 2.0)
    axis = major;
  else if (b.axis_ratio >= 1.3)
    axis = Eigen::Vector2d(-major.y(), major.x());
  if (std::abs(axis.y()) < std::cos(max_tilt_rad)) return Eigen::Vector2d::Zero();
  return axis.y() > 0.0 ? axis : Eigen::Vector2d(-axis);
}

// Largest coordinate along `axis` (from origin) of the blob's run ends.
double ExtentAlong(const std::vector<Run>& runs, const Eigen::Vector2d& origin, const Eigen::Vector2d& axis) {
  double hi = -INFINITY;
  for (const Run& r : runs)
    for (int x : {r.x0, r.x1}) hi = std::max(hi, (Eigen::Vector2d(x, r.y) - origin).dot(axis));
  return hi;
}

// Gap between `big`'s end and `small` along their common cone axis if `small`
// can be the next fragment of the cone `big` belongs to; NaN otherwise.
double FragmentGap(const Blob& big, const Blob& small, double lateral_frac, double gap_frac, double max_tilt_rad,
                   const BandTest& band, double band_gap_frac) {
  const Eigen::Vector2d d = small.centroid - big.centroid;
  const double max_gap_frac = band ? std::max(gap_frac, band_gap_frac) : gap_frac;
  // Quick reject: each end lies within its blob's major axis of its centroid.
  if (d.norm() > (1.0 + lateral_frac + max_gap_frac) * big.major_px + small.major_px) return NAN;
  Eigen::Vector2d axis = ConeAxisOf(big, max_tilt_rad);
  if (axis.isZero()) {  // a near-round body: the line to the fragment is the axis, if upright
    if (d.norm() < 1e-9) return NAN;
    axis = d.normalized() * (d.y() >= 0.0 ? 1.0 : -1.0);
    if (axis.y() < std::cos(max_tilt_rad)) return NAN;
  }
  const Eigen::Vector2d small_axis = ConeAxisOf(small, max_tilt_rad);
  if (!small_axis.isZero() && small_axis.dot(axis) < std::cos(20.0 * M_PI / 180.0)) return NAN;
  const Eigen::Vector2d toward = d.dot(axis) > 0.0 ? axis : Eigen::Vector2d(-axis);
  const double along = d.dot(toward), lateral = std::abs(d.x() * axis.y() - d.y() * axis.x());
  const double big_end = ExtentAlong(big.runs, big.centroid, toward);
  const double small_back = ExtentAlong(small.runs, small.centroid, -toward);
  const double gap = along - big_end - small_back;
  if (lateral > lateral_frac * big.major_px || gap > max_gap_frac * big.major_px || along < big_end) return NAN;
  // A cone narrows toward its peak. A fragment above the big blob's end is no
  // wider than that end: a second cone standing behind the first, seen above
  // it, shows its wide base there. A fragment below it starts at least about
  // as wide: the next cone's peak, seen below a far cone's base, does not.
  const double end_window = std::max(3.0, 0.15 * big.major_px);
  const double big_end_width = WidthAcross(big.runs, big.centroid, toward, big_end - end_window, INFINITY);
  if (toward.y() < 0.0) {
    if (WidthAcross(small.runs, small.centroid, toward, -INFINITY, INFINITY) > 1.2 * big_end_width + 2.0) return NAN;
  } else {
    const double small_near = -ExtentAlong(small.runs, small.centroid, -toward);
    const double small_end_width = WidthAcross(small.runs, small.centroid, toward, -INFINITY, small_near + end_window);
    if (small_end_width < 0.6 * big_end_width - 2.0) return NAN;
  }
  if (gap > gap_frac * big.major_px) {  // only across a band, and on the cone's two straight edges:
    // the widths either side of the band are in the ratio of their distances from the apex (the
    // upper fragment's far end). A far cone's base seen above a near cone's end is too narrow.
    const double small_near_width =
        WidthAcross(small.runs, small.centroid, toward, -INFINITY, -small_back + end_window);
    const double small_len = small_back + ExtentAlong(small.runs, small.centroid, toward);
    const double big_len = big_end + ExtentAlong(big.runs, big.centroid, -toward);
    const double expected = toward.y() < 0.0 ? small_len / (small_len + gap) : (big_len + gap) / big_len;
    const double ratio = small_near_width / std::max(1.0, big_end_width);
    if (!(ratio > 0.6 * expected && ratio < 1.6 * expected + 0.1)) return NAN;
    const Eigen::Vector2d side = d - along * toward;  // the small fragment's lateral offset
    const Eigen::Vector2d from = big.centroid + big_end * toward + (big_end / along) * side;
    const Eigen::Vector2d to = big.centroid + (along - small_back) * toward + ((along - small_back) / along) * side;
    const double narrow = std::min(WidthAcross(small.runs, small.centroid, toward, -INFINITY, INFINITY), big_end_width);
    if (!band(from, to, 0.3 * narrow)) return NAN;
  }
  return gap;
}

}  // namespace

void MergeAlongAxes(std::vector<Blob>* blobs, double lateral_frac, double gap_frac, double max_tilt_rad,
                    const BandTest& band, double band_gap_frac) {
  // Greedy, nearest pair first: a cone's own fragments, a collar apart, join
  // before a neighbour's. A far cone's tip seen above this cone's peak then
  // finds its own band and body first, and a far cone's base seen above this
  // cone's tip meets the tip's narrow end, not the wide body below it.
  for (;;) {
    size_t host = 0, fragment = 0;
    double best_gap = INFINITY;
    for (size_t i = 0; i < blobs->size(); ++i)
      for (size_t j = 0; j < blobs->size(); ++j) {
        const Blob &a = (*blobs)[i], &b = (*blobs)[j];
        if (i == j || a.area < b.area || (a.area == b.area && i > j)) continue;  // the larger one hosts
        const double gap = FragmentGap(a, b, lateral_frac, gap_frac, max_tilt_rad, band, band_gap_frac);
        if (gap < best_gap) host = i, fragment = j, best_gap = gap;
      }
    if (!std::isfinite(best_gap)) return;
    Blob& big = (*blobs)[host];
    const Blob& small = (*blobs)[fragment];
    big.runs.insert(big.runs.end(), small.runs.begin(), small.runs.end());
    big.m.Add(small.m);
    big.hull_area += small.hull_area;
    big.fragments += small.fragments;
    ComputeProperties(&big);
    blobs->erase(blobs->begin() + long(fragment));
  }
}

}  // namespace cone_tracker
