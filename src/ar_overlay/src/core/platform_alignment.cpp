#include "ar_overlay/core/platform_alignment.h"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace ar_overlay {
namespace {

constexpr double kInchM = 0.0254;

std::vector<cv::Point2d> Undistort(const std::vector<cv::Point2d>& raw, const CameraModel& k) {
  if (raw.empty() || !k.HasDistortion()) return raw;
  const cv::Matx33d K(k.fx_px, 0, k.cx_px, 0, k.fy_px, k.cy_px, 0, 0, 1);
  std::vector<cv::Point2d> out;
  cv::undistortPoints(raw, out, K, k.distortion, cv::noArray(), K);
  return out;
}

cv::Point2d Apply(const cv::Matx33d& H, const cv::Point2d& p) {
  const cv::Vec3d q = H * cv::Vec3d(p.x, p.y, 1.0);
  return {q[0] / q[2], q[1] / q[2]};
}

// The homography from grid indices (column, row) to undistorted pixels, from
// every blue dot: the outline's four corners give a first guess, which names
// each dot's indices, and all dots then fit the final one. A local choice of
// four dots is not enough: seen obliquely, skewed quadrilaterals of dots from
// three rows are as small as the true cell. The grid is square, so which
// corner is (0, 0) does not matter. False unless every dot is seen once.
bool GridHomography(const std::vector<cv::Point2d>& blue, int n, cv::Matx33d* H_image_grid) {
  if (n < 2 || static_cast<int>(blue.size()) != n * n) return false;
  std::vector<cv::Point2f> points(blue.begin(), blue.end()), hull, corners;
  cv::convexHull(points, hull);
  if (hull.size() < 4) return false;
  // The grid's corners are the outline's four sharpest turns; dots along its
  // sides turn by almost nothing.
  std::vector<std::pair<double, size_t>> turn;
  for (size_t i = 0; i < hull.size(); ++i) {
    const cv::Point2f a = hull[(i + hull.size() - 1) % hull.size()] - hull[i],
                      b = hull[(i + 1) % hull.size()] - hull[i];
    turn.push_back({a.dot(b) / (cv::norm(a) * cv::norm(b) + 1e-12), i});  // cos of the inner angle: larger is sharper
  }
  std::partial_sort(turn.begin(), turn.begin() + 4, turn.end(),
                    [](const auto& x, const auto& y) { return x.first > y.first; });
  std::vector<size_t> keep = {turn[0].second, turn[1].second, turn[2].second, turn[3].second};
  std::sort(keep.begin(), keep.end());  // back in the outline's order
  for (size_t i : keep) corners.push_back(hull[i]);
  const float last = static_cast<float>(n - 1);
  const std::vector<cv::Point2f> grid_corners = {{0, 0}, {last, 0}, {last, last}, {0, last}};
  const cv::Matx33d guess_grid_image = cv::Matx33d(cv::getPerspectiveTransform(grid_corners, corners)).inv();
  std::vector<cv::Point2d> grid, image;
  std::vector<char> taken(static_cast<size_t>(n * n), 0);
  for (const cv::Point2d& p : blue) {
    const cv::Point2d g = Apply(guess_grid_image, p);
    const int c = static_cast<int>(std::lround(g.x)), r = static_cast<int>(std::lround(g.y));
    if (c < 0 || r < 0 || c >= n || r >= n || taken[static_cast<size_t>(r * n + c)]++) return false;
    grid.emplace_back(c, r);
    image.push_back(p);
  }
  const cv::Mat H = cv::findHomography(grid, image, 0);
  if (H.empty()) return false;
  *H_image_grid = cv::Matx33d(H);
  return true;
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

std::vector<DotError> MeasureAlignment(const cv::Mat& bgr, const CameraModel& k, const AlignmentConfig& config) {
  std::vector<cv::Point2d> red, blue;
  for (const DotBlob& d : SegmentDots(bgr, DotColour::kRed, config)) red.push_back(d.centre_px);
  for (const DotBlob& d : SegmentDots(bgr, DotColour::kBlue, config)) blue.push_back(d.centre_px);
  red = Undistort(red, k);
  blue = Undistort(blue, k);
  std::vector<DotError> errors;
  cv::Matx33d H;
  if (!GridHomography(blue, config.grid_size, &H)) return errors;
  const cv::Matx33d H_grid_image = H.inv();
  const double last_cell = config.grid_size - 2;
  for (const cv::Point2d& r : red) {
    const cv::Point2d g = Apply(H_grid_image, r);
    // The red dot's cell; one beyond the grid is an error of a whole cell, not a cell of its own.
    const double c = std::clamp(std::floor(g.x), 0.0, last_cell), w = std::clamp(std::floor(g.y), 0.0, last_cell);
    const cv::Point2d k00 = Apply(H, {c, w}), k10 = Apply(H, {c + 1, w}), k11 = Apply(H, {c + 1, w + 1}),
                      k01 = Apply(H, {c, w + 1});
    const cv::Point2d middle = Apply(H, {c + 0.5, w + 0.5});
    const double side = 0.25 * (cv::norm(k10 - k00) + cv::norm(k11 - k10) + cv::norm(k01 - k11) + cv::norm(k00 - k01));
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
