// The overlay test platform's measurement (thesis 7.2): in a composited frame,
// segment the real blue dots and the virtual red dots; each red dot should lie
// in the middle of the four blue dots around it. The middle comes from the
// homography of the blue grid (undistorted centres, every dot): the image of
// the cell's centre under any perspective view, so no pose or model is needed.
// The pixel error becomes a distance on the platform through the cell's own size.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "ar_overlay/core/camera_projection.h"

namespace ar_overlay {

struct AlignmentConfig {
  double spacing_m = 0.1;        // between neighbouring blue dots on the platform
  int grid_size = 5;             // blue dots per row and per column (a square grid)
  double min_area_px = 6.0;      // blobs smaller are noise
  double max_area_px = 20000.0;  // blobs larger are not dots (sky, the platform's sides)
  double min_fill = 0.5;         // blob area / bounding box area: dots are round, sky is not
  int border_px = 2;             // blobs touching the border are cut: their centres are biased
};

struct DotBlob {
  cv::Point2d centre_px;  // raw image
  double area_px = 0;
};

struct DotError {
  cv::Point2d red_px;       // undistorted pixel coordinates (the camera's K)
  cv::Point2d expected_px;  // where the four blue dots' diagonals cross
  cv::Point2d error_px;     // red - expected
  double m_per_px = 0;      // spacing_m over the cell's mean side in pixels
};

enum class DotColour { kRed, kBlue };

// Pixel classes of a bgr8 image (CV_8UC3): red is the overlay's lit red,
// blue the platform's dots. Returns a CV_8UC1 mask, 255 where the colour is.
cv::Mat DotMask(const cv::Mat& bgr, DotColour colour);
std::vector<DotBlob> SegmentDots(const cv::Mat& bgr, DotColour colour, const AlignmentConfig& config);

// Red dots of one frame with their errors; none unless the whole blue grid is
// seen (a cone in front of it, or the platform cut by the image border).
// k: the frame's camera (its distortion is undone before the geometry).
std::vector<DotError> MeasureAlignment(const cv::Mat& bgr, const CameraModel& k, const AlignmentConfig& config);

struct AlignmentStats {
  size_t dots = 0;
  cv::Point2d mean_px, std_px;      // image x (right) and y (down)
  cv::Point2d mean_inch, std_inch;  // the same on the platform, through each cell's scale
};
AlignmentStats Summarize(const std::vector<DotError>& errors);

}  // namespace ar_overlay
