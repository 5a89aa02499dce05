// Synthetic large layouts (up to 30 cones of mixed heights on a jittered grid)
// and views of them with 3 to 5 cones in view, as exact detections with the
// cone ids: for the large-layout tests and benchmark. Test code only.
#pragma once

#include <random>
#include <vector>

#include <Eigen/Core>

#include "cone_tracker/vision/cone_pose.h"
#include "rig_sim/scene.h"

namespace cone_tracker {
namespace testing {

// n cones, 3.5 m grid jittered by up to 1 m, heights 0.30/0.46/0.71/0.91 m, base centroid at the origin.
std::vector<ConeModel> LargeLayout(int n, unsigned seed);
// The scene of those cones for rig_sim's renderer: road cones and plain ones in turn (the style sets
// the collars; ConeModels(scene) gives the models the renderer draws).
rig_sim::Scene LargeLayoutScene(const std::vector<ConeModel>& cones);
// 1024x768 pinhole, 60 degrees across, no distortion.
CameraModel LargeLayoutCamera();

struct SyntheticView {
  Eigen::Vector3d eye_m, target_m;        // camera_optical at eye_m looking at target_m (LookAt)
  std::vector<ConeDetection> detections;  // sorted by the peak's u, like the segmenter's
  std::vector<int> cone_of_detection;     // the true layout index of each
};

// A hand-held view (eye 1.3-1.8 m high, 2.5-7 m from a random cone, looking near it) with
// min_in_view..max_in_view cones fully in the image and at least 20 px tall; their corrected
// model points (3.1.4) projected, plus Gaussian noise of noise_px per coordinate.
SyntheticView RandomView(const std::vector<ConeModel>& cones, const CameraModel& cam, int min_in_view, int max_in_view,
                         double noise_px, std::mt19937* rng);

}  // namespace testing
}  // namespace cone_tracker
