// rig_sim_bench: frame rendering and scenario generation times, against
// baselines on the same poses: a naive ray caster (no tile culling) and
// OpenCV-drawn flat frames (cone triangles filled on a plain background plus
// cv::randn noise, no distortion, no shading: what a cheap simulator would do).
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "rig_sim/ros/bag_writer.h"

namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

void Bench(const std::string& name, double value, const char* unit) {
  std::printf("BENCH rig_sim.%s %.3f %s\n", name.c_str(), value, unit);
}

double RenderMs(const rig_sim::Scenario& s, const rig_sim::RenderConfig& rc, int frames) {
  const rig_sim::Trajectory traj(s.trajectory);
  const rig_sim::Renderer r(s.camera.model, s.scene, rc);
  std::vector<uint8_t> rgb(static_cast<size_t>(r.width()) * r.height() * 3);
  const auto t0 = Clock::now();
  for (int n = 0; n < frames; ++n) r.Render(traj.At(5.0 + n / 30.0), 5.0 + n / 30.0, n, rgb.data());
  return 1000.0 * Since(t0) / frames;
}

double OpenCvFlatMs(const rig_sim::Scenario& s, int frames) {
  const rig_sim::Trajectory traj(s.trajectory);
  const rig_model::CameraModel& c = s.camera.model;
  cv::Mat img(c.height_px, c.width_px, CV_8UC3), noise(c.height_px, c.width_px, CV_8UC3);
  const auto t0 = Clock::now();
  for (int n = 0; n < frames; ++n) {
    const rig_sim::TruePose pose = traj.At(5.0 + n / 30.0);
    img.setTo(cv::Scalar(90, 90, 95));
    for (const rig_sim::ConeSpec& cone : s.scene.cones) {
      const Eigen::Vector3d side = pose.R_cones_camera.col(0) * cone.radius_m();
      std::vector<cv::Point> tri;
      for (const Eigen::Vector3d& p :
           {cone.peak_m(), Eigen::Vector3d(cone.base_m + side), Eigen::Vector3d(cone.base_m - side)}) {
        const Eigen::Vector3d q = pose.R_cones_camera.transpose() * (p - pose.p_camera_in_cones_m);
        if (q.z() <= 0.1) break;
        tri.emplace_back(static_cast<int>(c.fx_px * q.x() / q.z() + c.cx_px),
                         static_cast<int>(c.fy_px * q.y() / q.z() + c.cy_px));
      }
      if (tri.size() == 3) cv::fillConvexPoly(img, tri, cv::Scalar(255, 100, 20), cv::LINE_AA);
    }
    cv::randn(noise, 0, 2);
    img += noise;
  }
  return 1000.0 * Since(t0) / frames;
}

}  // namespace

int main() {
  rig_sim::Scenario s;
  std::string err;
  if (!rig_sim::MakeScenario("handheld", 1, RIG_SIM_LAYOUTS_DIR, &s, &err)) {
    std::fprintf(stderr, "rig_sim_bench: %s\n", err.c_str());
    return 1;
  }
  const int frames = 60;
  std::printf("rig_sim_bench: handheld scenario, %dx%d, %d frames from t = 5 s\n", s.camera.model.width_px,
              s.camera.model.height_px, frames);
  rig_sim::RenderConfig two = s.render, one = s.render, naive = s.render;
  one.threads = 1;
  naive.threads = 1;
  naive.tile_culling = false;
  const double ours2 = RenderMs(s, two, frames), ours1 = RenderMs(s, one, frames);
  const double naive1 = RenderMs(s, naive, frames), flat = OpenCvFlatMs(s, frames);
  Bench("render_frame_2threads", ours2, "ms");
  Bench("render_frame_1thread", ours1, "ms");
  Bench("naive_raycast_frame_1thread", naive1, "ms");
  Bench("opencv_flat_frame_1thread", flat, "ms");
  Bench("ratio_naive_vs_ours_1thread", naive1 / ours1, "x");
  Bench("ratio_ours_vs_opencv_flat_1thread", ours1 / flat, "x");
  // Scenario generation, end to end: a 10 s full-size bag, scaled to 60 s.
  rig_sim::ShortenScenario(10.0, 1.0, &s);
  const std::string path = "/tmp/rig_sim_bench.bag";
  const auto t0 = Clock::now();
  if (!rig_sim::WriteScenarioBag(s, rig_sim::BagOptions(), path, nullptr, &err)) {
    std::fprintf(stderr, "rig_sim_bench: %s\n", err.c_str());
    return 1;
  }
  const double gen_s = Since(t0);
  std::remove(path.c_str());
  Bench("generate_10s_bag_1024x768", gen_s, "s");
  Bench("generate_60s_bag_1024x768_projected", 6.0 * gen_s, "s");
  Bench("generation_realtime_factor", 10.0 / gen_s, "x");
  return 0;
}
