// Tracker time per 1024x768 frame (segmentation + correspondence + pose, no
// prediction: the cold start, the worst case; and tracked: segmentation, the
// pose from the prediction and the per-cone association) with a 30-cone layout and 3-5
// cones in view, against the baseline of the 3-cone layout's frames in the same
// process; also the pose step alone, cold and with a prediction. Single-threaded.
// Prints BENCH lines (DESIGN.md).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "cone_tracker/pose/algorithms.h"
#include "cone_tracker/pose/associate.h"
#include "cone_tracker/testing/large_layout.h"
#include "cone_tracker/testing/vision_frames.h"
#include "cone_tracker/vision/cone_pose.h"
#include "cone_tracker/vision/cone_pose_search.h"
#include "cone_tracker/vision/segmenter.h"
#include "pose_math/rotation.h"
#include "rig_sim/scene.h"

namespace {

using namespace cone_tracker;
using Clock = std::chrono::steady_clock;
double Ms(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double, std::milli>(b - a).count(); }
double Median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
  return v[v.size() / 2];
}

struct Set {
  std::vector<SimFrame> frames;
  std::vector<ConeModel> models;
  std::vector<double> frame_ms, pose_cold_ms, search_ms, pose_pred_ms, assoc_tight_ms, assoc_loose_ms;
  std::vector<double> tracked_frame_ms;  // segmentation + predicted pose + per-cone association (tracked)
  std::vector<double> classify_ms, blobs_ms, measure_ms;  // segmentation's three steps (segmenter.h)
  int solved = 0, runs = 0;
};

double TimeAssociation(const std::vector<ConeDetection>& dets, const std::vector<ConeModel>& models,
                       const CameraModel& cam, const pose_math::Pose& T_camera_cones, double sigma_m,
                       const Eigen::Vector3d& eye_offset_m) {
  const auto t0 = Clock::now();
  std::vector<ConePoints2d> points;
  std::vector<std::array<Eigen::Matrix2d, 3>> cov;
  for (const ConeDetection& d : dets) {
    points.push_back({d.peak_undist_px, d.mid_undist_px, d.base_undist_px});
    cov.push_back(PointCovariances(points.back(), d.blob.area, 1.0));
  }
  pose_math::Pose pred = T_camera_cones;
  pred.t -= pose_math::RotationFromQuat(pred.q) * eye_offset_m;  // the camera moved by eye_offset_m
  AssociationConfig a;
  Eigen::Matrix<double, 6, 6> P = Eigen::Matrix<double, 6, 6>::Zero();
  P.diagonal() << Eigen::Vector3d::Constant(std::pow(2.0 * M_PI / 180.0, 2)),
      Eigen::Vector3d::Constant(sigma_m * sigma_m);
  a.prediction_cov = P;
  CameraModel pinhole = cam;
  pinhole.distortion.clear();
  AssociateCones(points, cov, models.size(), LayoutSeenFrom(models), pinhole, pred, a);
  return Ms(t0, Clock::now());
}

void RunSet(Set* s, int iterations) {
  Segmenter seg{SegmenterConfig()};
  for (int i = 0; i < iterations; ++i) {
    const SimFrame& f = s->frames[size_t(i) % s->frames.size()];
    const Eigen::Matrix3d R = f.pose.R_cones_camera.transpose();
    const pose_math::Pose truth = PoseFromRt(R, -R * f.pose.p_camera_in_cones_m);
    const auto t0 = Clock::now();
    const SegmentationResult r =
        seg.Process({f.rgb.data(), f.camera.width_px, f.camera.height_px, f.camera.width_px * 3, "rgb8"}, f.camera);
    const auto t1 = Clock::now();
    s->classify_ms.push_back(r.classify_ms), s->blobs_ms.push_back(r.blobs_ms), s->measure_ms.push_back(r.measure_ms);
    const ConePoseResult cold = EstimateConePose(r.cones, s->models, f.camera, ConePoseConfig(), std::nullopt);
    const auto t2 = Clock::now();
    EstimateConePose(r.cones, s->models, f.camera, ConePoseConfig(), truth);
    const auto t3 = Clock::now();
    s->frame_ms.push_back(Ms(t0, t2)), s->pose_cold_ms.push_back(Ms(t1, t2)), s->pose_pred_ms.push_back(Ms(t2, t3));
    if (s->models.size() > 8) {  // the cold pose's share that is the pair-hypothesis search (cone_pose_search.h)
      const auto t4 = Clock::now();
      SearchAssignments(r.cones, s->models, f.camera, ConeSearchConfig());
      s->search_ms.push_back(Ms(t4, Clock::now()));
    }
    // The per-cone association (cone_tracker/observations): tracked (the prediction 5 cm, 2 degrees
    // off), and re-acquiring (2 m off, the filter's sigma 2.5 m after an outage).
    s->assoc_tight_ms.push_back(
        TimeAssociation(r.cones, s->models, f.camera, truth, 0.05, Eigen::Vector3d(0.03, 0.04, 0)));
    s->tracked_frame_ms.push_back(Ms(t0, t1) + s->pose_pred_ms.back() + s->assoc_tight_ms.back());
    s->assoc_loose_ms.push_back(
        TimeAssociation(r.cones, s->models, f.camera, truth, 2.5, Eigen::Vector3d(1.6, -1.2, 0.3)));
    s->solved += cold.ok, ++s->runs;
  }
}

}  // namespace

int main() {
  cv::setNumThreads(1);
  const CameraModel cam = testing::LargeLayoutCamera();
  // 30 cones: the scene of the large-layout test, 8 views with 3-5 cones in view.
  const std::vector<ConeModel> layout = testing::LargeLayout(30, 7);
  const rig_sim::Scene large = testing::LargeLayoutScene(layout);
  Set big, small;
  big.models = ConeModels(large);
  std::mt19937 rng(21);
  for (int i = 0; i < 8; ++i) {
    const testing::SyntheticView v = testing::RandomView(big.models, cam, 3, 5, 0.0, &rng);
    big.frames.push_back(RenderSim(large, LookAt(v.eye_m, v.target_m), cam));
  }
  // Baseline: the 3-cone default layout, 8 views round it.
  const rig_sim::Scene three = rig_sim::DefaultScene();
  small.models = ConeModels(three);
  for (int i = 0; i < 8; ++i) {
    const double az = 0.2 + 0.25 * i;
    small.frames.push_back(RenderSim(
        three, LookAt(Eigen::Vector3d(3.3 * std::cos(az), 3.3 * std::sin(az), 1.5), Eigen::Vector3d(0, 0, 0.3)), cam));
  }
  for (size_t i = 0; i < big.frames.size(); ++i) {  // what each frame gives, for the record
    const SimFrame& f = big.frames[i];
    Segmenter seg{SegmenterConfig()};
    const SegmentationResult r =
        seg.Process({f.rgb.data(), f.camera.width_px, f.camera.height_px, f.camera.width_px * 3, "rgb8"}, f.camera);
    const ConePoseResult p = EstimateConePose(r.cones, big.models, f.camera, ConePoseConfig(), std::nullopt);
    std::string ids;
    for (int c : p.cone_of_detection) ids += " " + std::to_string(c);
    std::printf("30-cone frame %zu: %zu detections, ids%s, %s, chi2 %.1f (gate %.1f), rms %.2f px\n", i, r.cones.size(),
                ids.c_str(), p.ok ? "ok" : p.error.c_str(), p.chi2, p.chi2_threshold, p.pnp.reproj_rms_px);
  }
  const int kIterations = 400;
  RunSet(&big, kIterations);
  RunSet(&small, kIterations);
  const double big_ms = Median(big.frame_ms), small_ms = Median(small.frame_ms);
  std::printf("frames at %dx%d, %d per layout, no prediction (cold start)\n", cam.width_px, cam.height_px, kIterations);
  std::printf(
      "30-cone layout: frame median %.3f ms (pose %.3f ms cold, %.3f ms predicted), %d/%d frames pass the gates\n",
      big_ms, Median(big.pose_cold_ms), Median(big.pose_pred_ms), big.solved, big.runs);
  std::printf("30-cone layout: of the cold pose, the assignment search %.3f ms (median)\n", Median(big.search_ms));
  std::printf("30-cone layout: tracked frame median %.3f ms (segmentation, predicted pose, per-cone association)\n",
              Median(big.tracked_frame_ms));
  std::printf("30-cone layout: segmentation median: classify %.3f ms, blobs %.3f ms, gates and measures %.3f ms\n",
              Median(big.classify_ms), Median(big.blobs_ms), Median(big.measure_ms));
  std::printf(
      "30-cone layout: per-cone association median %.3f ms tracked (5 cm off, sigma 5 cm), %.3f ms "
      "re-acquiring (2 m off, sigma 2.5 m); max %.3f, %.3f ms\n",
      Median(big.assoc_tight_ms), Median(big.assoc_loose_ms),
      *std::max_element(big.assoc_tight_ms.begin(), big.assoc_tight_ms.end()),
      *std::max_element(big.assoc_loose_ms.begin(), big.assoc_loose_ms.end()));
  std::printf("3-cone layout (baseline): frame median %.3f ms (pose %.3f ms cold, %.3f ms predicted), %d/%d pass\n",
              small_ms, Median(small.pose_cold_ms), Median(small.pose_pred_ms), small.solved, small.runs);
  std::printf("ratio 30 / 3 cones: frame %.2f, cold pose %.2f\n", big_ms / small_ms,
              Median(big.pose_cold_ms) / Median(small.pose_cold_ms));
  std::printf("BENCH cone_tracker.large_layout_frame_median %.3f ms\n", big_ms);
  std::printf("BENCH cone_tracker.three_cone_frame_median %.3f ms\n", small_ms);
  std::printf("BENCH cone_tracker.large_layout_tracked_frame_median %.3f ms\n", Median(big.tracked_frame_ms));
  std::printf("BENCH cone_tracker.large_layout_frame_ratio %.3f ratio\n", big_ms / small_ms);
  std::printf("BENCH cone_tracker.large_layout_pose_cold_median %.3f ms\n", Median(big.pose_cold_ms));
  std::printf("BENCH cone_tracker.three_cone_pose_cold_median %.3f ms\n", Median(small.pose_cold_ms));
  std::printf("BENCH cone_tracker.large_layout_pose_predicted_median %.3f ms\n", Median(big.pose_pred_ms));
  std::printf("BENCH cone_tracker.large_layout_association_tracked_median %.3f ms\n", Median(big.assoc_tight_ms));
  std::printf("BENCH cone_tracker.large_layout_association_reacquiring_median %.3f ms\n", Median(big.assoc_loose_ms));
  return 0;
}
