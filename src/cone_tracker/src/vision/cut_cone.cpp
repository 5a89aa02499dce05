#include "cone_tracker/vision/cut_cone.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cone_tracker {

namespace {

// Distance along the unit ray p + t d (t > 0) to where it leaves [0, w-1] x [0, h-1].
double ExitDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& d, int w, int h) {
  double t = std::numeric_limits<double>::infinity();
  if (d.x() > 1e-9) t = std::min(t, (w - 1 - p.x()) / d.x());
  if (d.x() < -1e-9) t = std::min(t, -p.x() / d.x());
  if (d.y() > 1e-9) t = std::min(t, (h - 1 - p.y()) / d.y());
  if (d.y() < -1e-9) t = std::min(t, -p.y() / d.y());
  return t;
}

// Mean colour of the pixels at p + s e for the given offsets s; false when none is in the image.
bool MeanColour(const RgbView& im, const Eigen::Vector2d& p, const Eigen::Vector2d& e, const double* s, int n,
                Eigen::Vector3d* mean) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int count = 0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d q = p + s[i] * e;
    const int x = int(std::lround(q.x())), y = int(std::lround(q.y()));
    if (x < 0 || y < 0 || x >= im.width || y >= im.height) continue;
    const uint8_t* c = im.data + size_t(y) * size_t(im.step) + 3 * size_t(x);
    sum += Eigen::Vector3d(c[0], c[1], c[2]);
    ++count;
  }
  if (count == 0) return false;
  *mean = sum / count;
  return true;
}

}  // namespace

bool SilhouetteRunsOutOfImage(const RgbView& image, const Eigen::Vector2d& peak_px, const Eigen::Vector2d& base_px,
                              double base_half_width_px, int min_contrast, double max_run_frac) {
  if (min_contrast <= 0 || !image.data) return false;
  const double height = (base_px - peak_px).norm();
  if (!(height > 2.0 && base_half_width_px > 0.5)) return false;
  const Eigen::Vector2d d = (base_px - peak_px) / height, e(d.y(), -d.x());
  const double run = ExitDistance(base_px, d, image.width, image.height);
  // A base on or next to the edge is the border gate's; a run longer than any collar would show
  // the lower part (orange: the segmenter's OrangeBelowBase), not only the collar.
  if (!(run >= 2.0 && run <= max_run_frac * height)) return false;
  int rows = 0, continued = 0;
  for (double t = 1.5; t <= run; t += 1.0) {
    // The produced edges widen as they leave the apex.
    const double hw = base_half_width_px * (height + t) / height;
    const Eigen::Vector2d p = base_px + t * d;
    const double inside[] = {-0.5 * hw, 0.0, 0.5 * hw};
    const double left[] = {-hw - 2.0, -hw - 4.0}, right[] = {hw + 2.0, hw + 4.0};
    Eigen::Vector3d in, out;
    if (!MeanColour(image, p, e, inside, 3, &in)) continue;
    ++rows;
    int sides = 0, differ = 0;
    for (const double* s : {left, right}) {
      if (!MeanColour(image, p, e, s, 2, &out)) continue;
      ++sides;
      differ += (in - out).cwiseAbs().maxCoeff() >= min_contrast;
    }
    continued += sides > 0 && differ == sides;
  }
  return rows >= 2 && continued >= 0.8 * rows;
}

}  // namespace cone_tracker
