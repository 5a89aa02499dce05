// ar_overlay_bench: render + composite at 1024x768 with the peaks surface at
// 160 x 160 (50,562 triangles) on whatever EGL gives (llvmpipe here), with the
// default level of detail (RenderConfig::lod_max_error_px) and without, against
// a software baseline on the same mesh and pose in the same process: OpenCV's
// cv::projectPoints (with the distortion) and cv::fillConvexPoly per triangle,
// painter-sorted and flat-shaded.
#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <numeric>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "ar_overlay/core/mesh_generators.h"
#include "ar_overlay/core/overlay.h"

using namespace ar_overlay;
using Clock = std::chrono::steady_clock;

namespace {

double Median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

double ProcessCpuMs() {  // every thread's CPU time: llvmpipe rasterises on its own threads
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

// Median wall-clock ms per call; *cpu_ms (if given) gets the median CPU ms of
// all the process's threads, which other jobs on a shared machine do not inflate.
template <typename F>
double MedianMs(int warmup, int runs, F&& f, double* cpu_ms = nullptr) {
  for (int i = 0; i < warmup; ++i) f();
  std::vector<double> ms, cpu;
  for (int i = 0; i < runs; ++i) {
    const double c0 = ProcessCpuMs();
    const auto t0 = Clock::now();
    f();
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    cpu.push_back(ProcessCpuMs() - c0);
  }
  if (cpu_ms) *cpu_ms = Median(cpu);
  return Median(ms);
}

// The baseline: project every vertex, sort triangles far to near, fill each.
void SoftwareRender(const Mesh& m, float scale, const Eigen::Isometry3d& T_camera_model, const CameraModel& k,
                    cv::Mat& img) {
  cv::Mat R, rvec;
  cv::eigen2cv(Eigen::Matrix3d(T_camera_model.linear()), R);
  cv::Rodrigues(R, rvec);
  const Eigen::Vector3d t = T_camera_model.translation();
  std::vector<cv::Point3f> object(m.vertices.size());
  for (size_t i = 0; i < object.size(); ++i)
    object[i] = {scale * m.vertices[i].position[0], scale * m.vertices[i].position[1],
                 scale * m.vertices[i].position[2]};
  std::vector<cv::Point2f> px;
  const cv::Matx33d K(k.fx_px, 0, k.cx_px, 0, k.fy_px, k.cy_px, 0, 0, 1);
  cv::projectPoints(object, rvec, cv::Vec3d(t.x(), t.y(), t.z()), K, k.distortion, px);
  const size_t n = m.TriangleCount();
  std::vector<std::pair<float, uint32_t>> order;
  const Eigen::Matrix3f Rf = T_camera_model.linear().cast<float>();
  const Eigen::Vector3f tf = t.cast<float>();
  // Clip as GL would: drop triangles with a corner behind the camera or well
  // outside the view (where the distortion polynomial folds back and
  // projectPoints's pixels mean nothing).
  std::vector<char> usable(m.vertices.size());
  for (size_t v = 0; v < usable.size(); ++v) {
    const Eigen::Vector3f c = Rf * Eigen::Vector3f(object[v].x, object[v].y, object[v].z) + tf;
    const float u = static_cast<float>(k.fx_px) * c.x() / c.z(), w = static_cast<float>(k.fy_px) * c.y() / c.z();
    usable[v] = c.z() > 0.05f && std::abs(u) < k.width_px && std::abs(w) < k.height_px;
  }
  order.clear();
  for (size_t i = 0; i < n; ++i) {
    const uint32_t* t3 = &m.indices[3 * i];
    if (!usable[t3[0]] || !usable[t3[1]] || !usable[t3[2]]) continue;
    const cv::Point3f& p = object[t3[0]];
    order.push_back({Rf.row(2).dot(Eigen::Vector3f(p.x, p.y, p.z)) + tf.z(), static_cast<uint32_t>(i)});
  }
  std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  const Eigen::Vector3f to_light = Eigen::Vector3f(-0.3f, -0.6f, -1.0f).normalized();
  for (const auto& [depth, i] : order) {
    const Vertex& v = m.vertices[m.indices[3 * i]];
    const float lambert = std::abs((Rf * Eigen::Vector3f(v.normal[0], v.normal[1], v.normal[2])).dot(to_light));
    const float s = 255.0f * (0.3f + 0.7f * lambert);
    const cv::Point tri[3] = {px[m.indices[3 * i]] * 16, px[m.indices[3 * i + 1]] * 16, px[m.indices[3 * i + 2]] * 16};
    cv::fillConvexPoly(img, tri, 3, cv::Scalar(v.color[2] * s, v.color[1] * s, v.color[0] * s), cv::LINE_8, 4);
  }
}

}  // namespace

int main() {
  const CameraModel k{1024, 768, 800, 800, 511.5, 383.5, {-0.2, 0.05, 0.001, -0.001, 0}};
  CameraModel pinhole = k;
  pinhole.distortion.clear();
  const Mesh peaks = PeaksSurface(160);
  ModelSpec spec;
  spec.name = "peaks";
  spec.scale = 0.05;
  spec.T_parent_origin.translation() << 0, 0, 0.4;
  // The camera about 1.4 m away, the surface filling a good part of the frame.
  const Eigen::Isometry3d T_camera_cones = CameraLookAt({0.5, -0.6, 0.8}, {0, 0, 0.35}).inverse();
  cv::Mat background(k.height_px, k.width_px, CV_8UC3);
  cv::randu(background, 0, 255);
  try {
    Overlay overlay;  // the default RenderConfig: level of detail at <= 0.5 px
    overlay.AddModel(spec, peaks);
    RenderConfig full_mesh;
    full_mesh.lod_max_error_px = 0.0;
    Overlay overlay_full(full_mesh);
    overlay_full.AddModel(spec, peaks);
    std::printf("mesh: peaks 160x160, %zu triangles; image %dx%d; GL: %s\n", peaks.TriangleCount(), k.width_px,
                k.height_px, overlay.gl_renderer().c_str());
    std::printf("levels of detail (triangles, error m):");
    for (const auto& [triangles, error] : overlay.renderer().LevelsOfDetail(0))
      std::printf(" %zu/%.2g", triangles, error * spec.scale);
    std::printf("\n");
    cv::Mat out;
    std::string enc;
    double ours_cpu = 0, opencv_cpu = 0;
    const double ours = MedianMs(
        10, 100, [&] { overlay.Process(background, "bgr8", k, T_camera_cones, out, enc); }, &ours_cpu);
    const size_t drawn = overlay.renderer().drawn_triangles();
    double full_cpu = 0;
    const double full = MedianMs(
        10, 100, [&] { overlay_full.Process(background, "bgr8", k, T_camera_cones, out, enc); }, &full_cpu);
    const double no_remap =
        MedianMs(10, 100, [&] { overlay.Process(background, "bgr8", pinhole, T_camera_cones, out, enc); });
    const Eigen::Isometry3d T_camera_model = T_camera_cones * spec.T_parent_origin;
    const auto scale = static_cast<float>(spec.scale);
    const double opencv = MedianMs(
        2, 20,
        [&] {
          background.copyTo(out);
          SoftwareRender(peaks, scale, T_camera_model, k, out);
        },
        &opencv_cpu);
    if (const char* dir = std::getenv("AR_OVERLAY_BENCH_PNG")) {  // to look at both renderings
      overlay.Process(background, "bgr8", k, T_camera_cones, out, enc);
      cv::imwrite(std::string(dir) + "/bench_gl.png", out);
      background.copyTo(out);
      SoftwareRender(peaks, scale, T_camera_model, k, out);
      cv::imwrite(std::string(dir) + "/bench_opencv.png", out);
    }
    std::printf("GL render + remap + composite: median %.2f ms per frame (%zu triangles drawn at <= %.1f px error)\n",
                ours, drawn, RenderConfig().lod_max_error_px);
    std::printf("the same, always the full mesh (lod_max_error_px 0): median %.2f ms\n", full);
    std::printf("GL render + composite, no lens distortion (no remap): median %.2f ms\n", no_remap);
    std::printf("OpenCV projectPoints + fillConvexPoly (painter, flat): median %.2f ms\n", opencv);
    std::printf("BENCH ar_overlay.render_median %.3f ms\n", ours);
    std::printf("BENCH ar_overlay.render_full_mesh_median %.3f ms\n", full);
    std::printf("BENCH ar_overlay.render_full_mesh_cpu_median %.3f ms\n", full_cpu);
    std::printf("BENCH ar_overlay.render_no_remap_median %.3f ms\n", no_remap);
    std::printf("BENCH ar_overlay.opencv_fillpoly_median %.3f ms\n", opencv);
    std::printf("BENCH ar_overlay.speedup_vs_opencv %.2f x\n", opencv / ours);
    std::printf("BENCH ar_overlay.render_cpu_median %.3f ms\n", ours_cpu);
    std::printf("BENCH ar_overlay.opencv_fillpoly_cpu_median %.3f ms\n", opencv_cpu);
    std::printf("BENCH ar_overlay.cpu_speedup_vs_opencv %.2f x\n", opencv_cpu / ours_cpu);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ar_overlay_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
