// Repeated views (EkfConfig::cone_repeat_px): a frame that shows the cones of the last fused frame where that
// frame had them. A still camera's segmentation returns the same pixels frame after frame (rig_sim's static
// start: identical to 1e-4 px over 1.5 s), so their errors are one error seen again, not new independent ones.
#include <algorithm>
#include <cmath>

#include "pose_ekf/core/cone_measurement.h"

namespace pose_ekf {

bool RepeatsView(const FusedConeView& view, const ConeFrame& f, double max_px, double max_s) {
  if (view.count == 0 || !(f.stamp_s - view.stamp_s < max_s) || f.cones.empty()) return false;
  for (const ConeObservation& o : f.cones) {
    const int* end = view.cone_id.begin() + view.count;
    const int* found = std::find(view.cone_id.begin(), end, o.cone_id);
    if (found == end) return false;  // a cone the view did not have: new information
    const Eigen::Map<const ConeVector> before(view.z[static_cast<size_t>(found - view.cone_id.begin())].data());
    if (!((ConePixels(o) - before).cwiseAbs().maxCoeff() < max_px)) return false;
  }
  return true;
}

void NoteFusedView(const ConeFrame& f, const std::vector<int>& fused, FusedConeView* view) {
  view->stamp_s = f.stamp_s;
  view->count = 0;
  for (int i : fused) {
    if (view->count == kMaxViewCones) break;
    const ConeObservation& o = f.cones[static_cast<size_t>(i)];
    view->cone_id[static_cast<size_t>(view->count)] = o.cone_id;
    Eigen::Map<ConeVector>(view->z[static_cast<size_t>(view->count)].data()) = ConePixels(o);
    ++view->count;
  }
}

}  // namespace pose_ekf
