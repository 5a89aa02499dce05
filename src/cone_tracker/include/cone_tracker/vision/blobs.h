// 8-connected components of a binary image and their region properties
// (3.1.5.2), labelled on horizontal runs so the cost scales with the blob
// outlines rather than the pixel count. ROS-free.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "rig_model/cone_view.h"

namespace cone_tracker {

struct Run {
  int y, x0, x1;  // inclusive
};

// Raw sums over a blob's pixels (pixel centres at integer coordinates).
struct Moments {
  double n = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  void Add(const Run& r);
  void Add(const Moments& m);
};

struct Blob {
  std::vector<Run> runs;
  Moments m;
  int fragments = 1;     // > 1 after merging pieces split by white collars
  double hull_area = 0;  // sum over fragments of their convex hull area (pixel corners)
  // Region properties (regionprops semantics).
  double area = 0, solidity = 0;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  double major_px = 0, minor_px = 0;
  double orientation_rad = 0;  // of the major axis against +u, image axes (v down), in (-pi/2, pi/2]
  double axis_ratio = 0;
  int bbox_x = 0, bbox_y = 0, bbox_w = 0, bbox_h = 0;
};

// Binary image view: nonzero = cone pixel.
struct MaskView {
  const uint8_t* data = nullptr;
  int width = 0, height = 0, step = 0;
  bool At(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height && data[size_t(y) * step + x] != 0; }
};

// Connected components of the mask restricted to [x0, x1) x [y0, y1); blobs
// smaller than min_area_px are dropped (artifacts). Properties are filled.
std::vector<Blob> FindBlobs(const MaskView& mask, int x0, int y0, int x1, int y1, int min_area_px);

// Fills area, centroid, axes, orientation, ratio, bbox from runs/moments/hull_area.
void ComputeProperties(Blob* blob);
// Convex hull area of a set of runs, using pixel corners.
double HullArea(const std::vector<Run>& runs);
// Whether the mask has a cone pixel at from + t dir + s across, t from t_lo to t_hi in steps of t_step and s in
// {-side_px, 0, side_px} (across: dir turned 90 degrees): orange on a line beyond a point.
bool MaskHitAlong(const MaskView& mask, const Eigen::Vector2d& from, const Eigen::Vector2d& dir, double t_lo,
                  double t_hi, double t_step, double side_px);
// A blob of these runs with its properties: hull_area and fragments from its 8-connected pieces, as if they had
// been merged (MergeAlongAxes). For blobs whose pixels change hands after merging (merged_tip.h).
Blob BlobOfRuns(std::vector<Run> runs);
// Extent across the axis (unit; max - min of the perpendicular coordinate, + 1 px) of the run ends whose
// along-axis coordinate from origin lies in [t_lo, t_hi]; 0 when none does.
double WidthAcross(const std::vector<Run>& runs, const Eigen::Vector2d& origin, const Eigen::Vector2d& axis,
                   double t_lo = -INFINITY, double t_hi = INFINITY);

// Where a blob's pixels lie, tighter than its bounding box: its rows cut into `slabs` bands of equal height (fewer
// for a blob fewer rows tall), each band's box in pixel edges (pixel x spans x - 0.5 .. x + 0.5), the band's rows
// by the columns of its runs. A cone's triangle leaves half its bounding box empty; its slabs follow its widening.
// The bands tile the blob's rows, a white collar's between two merged fragments included.
std::vector<rig_model::ImageBox> RowSlabs(const std::vector<Run>& runs, int slabs);

// Merges blobs that lie along one cone's axis (fragments separated by white
// collars): a smaller blob joins a larger one when its centroid is within
// lateral_frac * major of the larger's cone axis, the gap along that axis is
// below gap_frac * major, their widths fit one cone narrowing upward, and the
// axis is within max_tilt_rad of the image vertical (cones stand upright; lens
// distortion and the rig's roll tilt them in the image). The cone axis of a
// squat fragment is across its major axis, or the line to the other fragment
// when it is near round. Nearest fragments join first.
// A striped cone's white or silver band (a reflective sleeve) can be as tall as the fragment above
// it: with `band`, a gap up to band_gap_frac * major joins too when band(from, to, half_width_px)
// says that the pixels between the fragments (along the axis from `from` to `to`, that far either
// side) are a band's (bright, unsaturated).
using BandTest = std::function<bool(const Eigen::Vector2d& from, const Eigen::Vector2d& to, double half_width_px)>;
void MergeAlongAxes(std::vector<Blob>* blobs, double lateral_frac, double gap_frac, double max_tilt_rad,
                    const BandTest& band = nullptr, double band_gap_frac = 0.0);

}  // namespace cone_tracker
