// Segmentation time per 1024x768 frame (3 road cones and orange distractors),
// single-threaded, against an OpenCV baseline of the colour + connected
// components stage (cvtColor to HSV, inRange, connectedComponentsWithStats)
// on the same frames. Prints BENCH lines (DESIGN.md).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "cone_tracker/testing/vision_frames.h"
#include "cone_tracker/vision/segmenter.h"

namespace {

using Clock = std::chrono::steady_clock;
double Ms(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double, std::milli>(b - a).count(); }
// This thread's CPU time: on a shared machine, wall time includes the time
// other jobs held the core; CPU time does not.
double CpuMs() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}
double Median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// Wall, CPU and measure-stage times of 400 frames (the frames in turn) through `seg`.
struct Timings {
  std::vector<double> total_ms, cpu_ms, measure_ms;
};
Timings TimeFrames(cone_tracker::Segmenter* seg, const std::vector<cone_tracker::SimFrame>& frames,
                   const cone_tracker::CameraModel& cam) {
  Timings t;
  for (int i = 0; i < 400; ++i) {
    const cone_tracker::SimFrame& f = frames[size_t(i) % frames.size()];
    const double c0 = CpuMs();
    const auto t0 = Clock::now();
    const cone_tracker::SegmentationResult r =
        seg->Process({f.rgb.data(), f.camera.width_px, f.camera.height_px, f.camera.width_px * 3, "rgb8"}, cam);
    t.total_ms.push_back(Ms(t0, Clock::now()));
    t.cpu_ms.push_back(CpuMs() - c0);
    t.measure_ms.push_back(r.measure_ms);
  }
  return t;
}

// The frames segmented with `config` in TimeFrames' loop (the main loop interleaves OpenCV, so its figure is not
// comparable): the frame's median wall and CPU time, printed as `what`.
void PrintTimed(const char* what, const char* key, const cone_tracker::SegmenterConfig& config,
                const std::vector<cone_tracker::SimFrame>& frames, const cone_tracker::CameraModel& cam) {
  cone_tracker::Segmenter seg{config};
  const Timings t = TimeFrames(&seg, frames, cam);
  std::printf("%s: frame median %.3f ms, CPU %.3f ms\n", what, Median(t.total_ms), Median(t.cpu_ms));
  std::printf("BENCH cone_tracker.frame_median_%s %.3f ms\n", key, Median(t.total_ms));
  std::printf("BENCH cone_tracker.frame_cpu_median_%s %.3f ms\n", key, Median(t.cpu_ms));
}

// Peak and base RMS against the truth over the frames' cones (each truth cone
// to the detection whose peak is nearest, within 15 px).
void PrintAccuracy(const char* name, cone_tracker::Segmenter* seg, const std::vector<cone_tracker::SimFrame>& frames,
                   const cone_tracker::CameraModel& cam) {
  double sp = 0, sb = 0;
  int n = 0;
  for (const auto& f : frames) {
    const auto r =
        seg->Process({f.rgb.data(), f.camera.width_px, f.camera.height_px, f.camera.width_px * 3, "rgb8"}, cam);
    for (const auto& t : f.truth) {
      const cone_tracker::ConeDetection* m = nullptr;
      for (const auto& d : r.cones)
        if ((d.peak_px - t.peak_px).norm() < 15.0 &&
            (!m || (d.peak_px - t.peak_px).norm() < (m->peak_px - t.peak_px).norm()))
          m = &d;
      if (m) sp += (m->peak_px - t.peak_px).squaredNorm(), sb += (m->base_px - t.base_px).squaredNorm(), ++n;
    }
  }
  std::printf("%s: %d cones, peak RMS %.2f px, base RMS %.2f px\n", name, n, std::sqrt(sp / n), std::sqrt(sb / n));
  std::printf("BENCH cone_tracker.peak_rms_%s %.3f px\n", name, std::sqrt(sp / n));
  std::printf("BENCH cone_tracker.base_rms_%s %.3f px\n", name, std::sqrt(sb / n));
}

}  // namespace

int main() {
  using namespace cone_tracker;
  cv::setNumThreads(1);
  rig_sim::Scene scene = rig_sim::DefaultScene();
  rig_sim::BoxSpec box;
  box.center_m =
      Eigen::Vector3d(1.5, -1.3, 0.15);  // in view, clear of the cones (an orange blob touching a cone is gated out)
  scene.boxes.push_back(box);
  rig_sim::PatchSpec patch;
  patch.center_m = Eigen::Vector2d(-1.3, 1.6);
  scene.patches.push_back(patch);
  std::vector<SimFrame> frames;
  for (int i = 0; i < 8; ++i) {
    const double az = 0.2 + 0.25 * i;
    frames.push_back(RenderSim(
        scene, LookAt(Eigen::Vector3d(3.3 * std::cos(az), 3.3 * std::sin(az), 1.5), Eigen::Vector3d(0, 0, 0.3))));
  }
  const CameraModel cam = frames[0].camera;
  const int w = frames[0].camera.width_px, h = frames[0].camera.height_px;
  Segmenter seg{SegmenterConfig()};
  const HsiBounds& k = seg.config().hsi;
  // OpenCV's 8-bit HSV: H in [0, 180) for [0, 360) deg, S and V in [0, 255].
  const cv::Scalar lo(k.hue_min_deg / 2.0, k.sat_min * 255.0, k.val_min * 255.0);
  const cv::Scalar hi(k.hue_max_deg / 2.0, k.sat_max * 255.0, k.val_max * 255.0);
  const int kFrames = 1500;
  std::vector<double> ours, baseline, classify, blobs, measure, ours_cpu, baseline_cpu;
  size_t cones = 0, cv_blobs = 0;
  cv::Mat hsv, mask, labels, stats, centroids;
  for (int i = 0; i < kFrames; ++i) {
    const SimFrame& f = frames[size_t(i) % frames.size()];
    const ImageView view{f.rgb.data(), w, h, w * 3, "rgb8"};
    const double c0 = CpuMs();
    const auto t0 = Clock::now();
    const SegmentationResult r = seg.Process(view, cam);
    const auto t1 = Clock::now();
    const double c1 = CpuMs();
    const cv::Mat rgb(h, w, CV_8UC3, const_cast<uint8_t*>(f.rgb.data()));
    cv::cvtColor(rgb, hsv, cv::COLOR_RGB2HSV);
    cv::inRange(hsv, lo, hi, mask);
    const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8);
    const auto t2 = Clock::now();
    ours_cpu.push_back(c1 - c0), baseline_cpu.push_back(CpuMs() - c1);
    ours.push_back(Ms(t0, t1));
    classify.push_back(r.classify_ms), blobs.push_back(r.blobs_ms), measure.push_back(r.measure_ms);
    baseline.push_back(Ms(t1, t2));
    cones += r.cones.size();
    cv_blobs += size_t(n - 1);
  }
  const double ours_ms = Median(ours), base_ms = Median(baseline);
  std::printf("frames %d at %dx%d, cones found per frame %.2f, OpenCV blobs per frame %.1f\n", kFrames, w, h,
              double(cones) / kFrames, double(cv_blobs) / kFrames);
  std::printf("segmentation (colour, ROI, blobs, gates, peak/base, undistort) median %.3f ms\n", ours_ms);
  std::printf(
      "  stages (medians): colour + ROI %.3f ms, blobs + merge %.3f ms, gates + peak/base (outline) + undistort %.3f "
      "ms\n",
      Median(classify), Median(blobs), Median(measure));
  std::printf("OpenCV baseline (cvtColor HSV + inRange + connectedComponentsWithStats) median %.3f ms\n", base_ms);
  std::printf("BENCH cone_tracker.frame_median %.3f ms\n", ours_ms);
  std::printf("BENCH cone_tracker.opencv_color_cc_median %.3f ms\n", base_ms);
  std::printf("BENCH cone_tracker.color_cc_ratio %.3f ratio\n", ours_ms / base_ms);
  std::printf("thread CPU time medians: ours %.3f ms, OpenCV %.3f ms\n", Median(ours_cpu), Median(baseline_cpu));
  std::printf("BENCH cone_tracker.frame_cpu_median %.3f ms\n", Median(ours_cpu));
  std::printf("BENCH cone_tracker.color_cc_cpu_ratio %.3f ratio\n", Median(ours_cpu) / Median(baseline_cpu));
  std::printf("BENCH cone_tracker.stage_color_roi_median %.3f ms\n", Median(classify));
  std::printf("BENCH cone_tracker.stage_blobs_median %.3f ms\n", Median(blobs));
  std::printf("BENCH cone_tracker.stage_measure_median %.3f ms\n", Median(measure));
  // What band merging and the merged-tip split (both on by default) cost: the same frames without each.
  SegmenterConfig no_band, no_split;
  no_band.merge_band_gap_frac = 0.0;
  no_split.split_merged_tips = false;
  PrintTimed("the same loop, defaults", "defaults", SegmenterConfig(), frames, cam);
  PrintTimed("without band merging", "no_band_merge", no_band, frames, cam);
  PrintTimed("without the merged-tip split", "no_tip_split", no_split, frames, cam);
  // The thesis's template refinement (3.1.5.4) on the same frames, for comparison.
  SegmenterConfig tc;
  tc.peak_refinement = int(PeakRefinement::kTemplates);
  const auto tb0 = Clock::now();
  Segmenter tseg{tc};
  std::printf("template set built at start-up in %.1f ms\n", Ms(tb0, Clock::now()));
  const Timings templates = TimeFrames(&tseg, frames, cam);
  std::printf("with template refinement: frame median %.3f ms, gates + peak/base (templates) + undistort %.3f ms\n",
              Median(templates.total_ms), Median(templates.measure_ms));
  std::printf("BENCH cone_tracker.frame_median_templates %.3f ms\n", Median(templates.total_ms));
  PrintAccuracy("outline", &seg, frames, cam);
  PrintAccuracy("templates", &tseg, frames, cam);
  return 0;
}
