#include "cone_tracker/vision/blobs.h"

#include <algorithm>
#include <cmath>
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
// Extent across the axis (max - min of the perpendicular coordinate) of the
// run ends whose along-axis coordinate t (from origin) lies in [t_lo, t_hi].
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

}  // namespace

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

std::vector<Blob> FindBlobs(const MaskView& mask, int x0, int y0, int x1, int y1, int min_area_px) {
  x0 = std::max(0, x0), y0 = std::max(0, y0);
  x1 = std::min(mask.width, x1), y1 = std::min(mask.height, y1);
  std::vector<Run> runs;
  std::vector<int> parent;
  size_t prev_begin = 0, prev_end = 0;
  for (int y = y0; y < y1; ++y) {
    const uint8_t* row = mask.data + size_t(y) * mask.step;
    const size_t cur_begin = runs.size();
    for (int x = x0; x < x1;) {
      if (!row[x]) {
        ++x;
        continue;
      }
      const int start = x;
      while (x < x1 && row[x]) ++x;
      const int id = int(runs.size());
      runs.push_back({y, start, x - 1});
      parent.push_back(id);
      // 8-connectivity: previous-row runs overlapping [start-1, x].
      for (size_t j = prev_begin; j < prev_end; ++j) {
        if (runs[j].x1 < start - 1) continue;
        if (runs[j].x0 > x) break;
        const int a = Find(parent, id), b = Find(parent, int(j));
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
      }
    }
    prev_begin = cur_begin, prev_end = runs.size();
    if (y + 1 < y1 && prev_begin == prev_end) prev_begin = prev_end = runs.size();
  }
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

void MergeAlongAxes(std::vector<Blob>* blobs, double lateral_frac, double gap_frac) {
  bool merged = true;
  while (merged) {
    merged = false;
    std::sort(blobs->begin(), blobs->end(), [](const Blob& a, const Blob& b) { return a.area > b.area; });
    for (size_t i = 0; i < blobs->size() && !merged; ++i) {
      Blob& big = (*blobs)[i];
      // A cone's body below its collars is squat (its base arc makes it
      // nearly as wide as tall), so its major axis says little; cones stand
      // upright (the segmenter's tilt gate), so the image vertical is used.
      const Eigen::Vector2d axis = big.axis_ratio < 2.0 ? Eigen::Vector2d(0.0, 1.0)
                                                        : Eigen::Vector2d(std::cos(big.orientation_rad), std::sin(big.orientation_rad));
      const double half = big.axis_ratio < 2.0 ? 0.5 * big.bbox_h : 0.5 * big.major_px;
      for (size_t j = i + 1; j < blobs->size(); ++j) {
        const Blob& small = (*blobs)[j];
        const Eigen::Vector2d d = small.centroid - big.centroid;
        const double along = std::abs(d.dot(axis)), lateral = std::abs(d.x() * axis.y() - d.y() * axis.x());
        const double gap = along - half - 0.5 * small.major_px;
        if (lateral > lateral_frac * big.major_px || gap > gap_frac * big.major_px || along < half) continue;
        // A cone narrows toward its peak: a fragment beyond the collar is no
        // wider than the big blob's near end. A second cone standing behind
        // the first, seen above it, shows its wide base there and stays apart.
        const Eigen::Vector2d toward = d.dot(axis) > 0 ? axis : Eigen::Vector2d(-axis);
        const double end_window = std::max(3.0, 0.15 * big.major_px);
        const double big_end_width = WidthAcross(big.runs, big.centroid, toward, half - end_window, INFINITY);
        const double small_width = WidthAcross(small.runs, small.centroid, toward, -INFINITY, INFINITY);
        if (small_width > 1.2 * big_end_width + 2.0) continue;
        big.runs.insert(big.runs.end(), small.runs.begin(), small.runs.end());
        big.m.Add(small.m);
        big.hull_area += small.hull_area;
        big.fragments += small.fragments;
        ComputeProperties(&big);
        blobs->erase(blobs->begin() + long(j));
        merged = true;
        break;
      }
    }
  }
}

}  // namespace cone_tracker
