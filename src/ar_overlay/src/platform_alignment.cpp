#include "ar_overlay/platform_alignment.h"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace ar_overlay {
namespace {

constexpr double kInchM = 0.0254;

std::vector<cv::Point2d> Undistort(const std::vector<cv::Point2d>& raw, const CameraIntrinsics& k) {
  if (raw.empty() || !k.HasDistortion()) return raw;
  const cv::Matx33d K(k.fx_px, 0, k.cx_px, 0, k.fy_px, k.cy_px, 0, 0, 1);
  std::vector<cv::Point2d> out;
  cv::undistortPoints(raw, out, K, k.distortion, cv::noArray(), K);
  return out;
}

// Where segments a0-a1 and b0-b1 cross; false when they are parallel.
bool Cross(const cv::Point2d& a0, const cv::Point2d& a1, const cv::Point2d& b0, const cv::Point2d& b1, cv::Point2d* p) {
  const cv::Point2d da = a1 - a0, db = b1 - b0;
  const double den = da.x * db.y - da.y * db.x;
  if (std::abs(den) < 1e-9) return false;
  const cv::Point2d w = b0 - a0;
  *p = a0 + da * ((w.x * db.y - w.y * db.x) / den);
  return true;
}

// The four blue centres around `red`, in angular order, if they form a grid
// cell that contains it: every angular gap under 180 degrees and no side more
// than three times another (perspective stretches a cell, it does not fold it).
bool CellAround(const cv::Point2d& red, const std::vector<cv::Point2d>& blue, cv::Point2d corners[4]) {
  if (blue.size() < 4) return false;
  std::vector<std::pair<double, size_t>> by_distance;
  for (size_t i = 0; i < blue.size(); ++i) by_distance.push_back({cv::norm(blue[i] - red), i});
  std::partial_sort(by_distance.begin(), by_distance.begin() + 4, by_distance.end());
  std::vector<std::pair<double, cv::Point2d>> by_angle;
  for (int i = 0; i < 4; ++i) {
    const cv::Point2d& b = blue[by_distance[i].second];
    by_angle.push_back({std::atan2(b.y - red.y, b.x - red.x), b});
  }
  std::sort(by_angle.begin(), by_angle.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  double shortest = 1e300, longest = 0;
  for (int i = 0; i < 4; ++i) {
    double gap = (i < 3 ? by_angle[i + 1].first : by_angle[0].first + 2 * M_PI) - by_angle[i].first;
    if (gap >= M_PI) return false;
    corners[i] = by_angle[i].second;
    const double side = cv::norm(by_angle[(i + 1) % 4].second - by_angle[i].second);
    shortest = std::min(shortest, side), longest = std::max(longest, side);
  }
  return longest < 3.0 * shortest;
}

}  // namespace

cv::Mat DotMask(const cv::Mat& bgr, DotColour colour) {
  CV_Assert(bgr.type() == CV_8UC3);
  cv::Mat mask(bgr.size(), CV_8UC1);
  for (int v = 0; v < bgr.rows; ++v) {
    const cv::Vec3b* p = bgr.ptr<cv::Vec3b>(v);
    uint8_t* m = mask.ptr<uint8_t>(v);
    for (int u = 0; u < bgr.cols; ++u) {
      const int b = p[u][0], g = p[u][1], r = p[u][2];
      // Red: the overlay's lit red (the specular highlight adds grey to all three).
      // Blue: the platform's dots under daylight; the grey ground and white board fail both.
      m[u] = colour == DotColour::kRed ? (r > 80 && r > g + 50 && r > b + 50 && std::abs(g - b) < 40 ? 255 : 0)
                                       : (b > 60 && b > r + 40 && b > g + 25 ? 255 : 0);
    }
  }
  return mask;
}

std::vector<DotBlob> SegmentDots(const cv::Mat& bgr, DotColour colour, const AlignmentConfig& config) {
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(DotMask(bgr, colour), labels, stats, centroids, 8, CV_32S);
  std::vector<DotBlob> blobs;
  for (int i = 1; i < n; ++i) {
    const int x = stats.at<int>(i, cv::CC_STAT_LEFT), y = stats.at<int>(i, cv::CC_STAT_TOP);
    const int w = stats.at<int>(i, cv::CC_STAT_WIDTH), h = stats.at<int>(i, cv::CC_STAT_HEIGHT);
    const double area = stats.at<int>(i, cv::CC_STAT_AREA);
    if (area < config.min_area_px || area > config.max_area_px || area < config.min_fill * w * h) continue;
    const int b = config.border_px;
    if (x < b || y < b || x + w > bgr.cols - b || y + h > bgr.rows - b) continue;
    blobs.push_back({{centroids.at<double>(i, 0), centroids.at<double>(i, 1)}, area});
  }
  return blobs;
}

std::vector<DotError> MeasureAlignment(const cv::Mat& bgr, const CameraIntrinsics& k, const AlignmentConfig& config) {
  std::vector<cv::Point2d> red, blue;
  for (const DotBlob& d : SegmentDots(bgr, DotColour::kRed, config)) red.push_back(d.centre_px);
  for (const DotBlob& d : SegmentDots(bgr, DotColour::kBlue, config)) blue.push_back(d.centre_px);
  red = Undistort(red, k);
  blue = Undistort(blue, k);
  std::vector<DotError> errors;
  for (const cv::Point2d& r : red) {
    cv::Point2d c[4], middle;
    if (!CellAround(r, blue, c) || !Cross(c[0], c[2], c[1], c[3], &middle)) continue;
    const double side =
        0.25 * (cv::norm(c[1] - c[0]) + cv::norm(c[2] - c[1]) + cv::norm(c[3] - c[2]) + cv::norm(c[0] - c[3]));
    errors.push_back({r, middle, r - middle, config.spacing_m / side});
  }
  return errors;
}

AlignmentStats Summarize(const std::vector<DotError>& errors) {
  AlignmentStats s;
  s.dots = errors.size();
  if (errors.empty()) return s;
  cv::Point2d sum_px, sum2_px, sum_in, sum2_in;
  for (const DotError& e : errors) {
    const cv::Point2d in = e.error_px * (e.m_per_px / kInchM);
    sum_px += e.error_px, sum2_px += cv::Point2d(e.error_px.x * e.error_px.x, e.error_px.y * e.error_px.y);
    sum_in += in, sum2_in += cv::Point2d(in.x * in.x, in.y * in.y);
  }
  const double n = static_cast<double>(errors.size());
  const auto sd = [n](double sum, double sum2) {
    return n > 1 ? std::sqrt(std::max(0.0, (sum2 - sum * sum / n) / (n - 1))) : 0.0;
  };
  s.mean_px = sum_px / n;
  s.mean_inch = sum_in / n;
  s.std_px = {sd(sum_px.x, sum2_px.x), sd(sum_px.y, sum2_px.y)};
  s.std_inch = {sd(sum_in.x, sum2_in.x), sd(sum_in.y, sum2_in.y)};
  return s;
}

}  // namespace ar_overlay
