// pose_ekf_cone_bench: the cost of the tightly coupled per-cone camera update (cone_update.cpp) on
// the synthetic rig: the median UpdateCones time per cone for frames of one and of three cones
// (both gates included), and a frame through the buffer. Baselines in the same process on the same
// frames: the loosely coupled pose update (UpdateCamera) and the same per-cone update written
// densely (Eigen::MatrixXd, explicit S⁻¹). Target (issue 16): <= 10 us per cone.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <vector>

#include "bench_util.h"
#include "pose_ekf/core/measurement_buffer.h"
#include "pose_ekf/testing/synthetic_cones.h"

namespace {

using pose_ekf_bench::Median;
using pose_ekf_bench::Print;
using pose_ekf_bench::TimeUs;
using pose_ekf_test::Event;

// One cone's update with heap-allocated dense matrices (no gate): the textbook form.
void DenseConeUpdate(pose_ekf::FilterState* s, const pose_ekf::ConeFrame& f, const pose_ekf::ConeObservation& o) {
  pose_ekf::ConeVector h;
  pose_ekf::ConeJacobian Hs;
  if (!pose_ekf::ProjectCone(s->x, o.cone, f.K, &h, &Hs)) return;
  const Eigen::MatrixXd H = Hs, P = s->P;
  const Eigen::MatrixXd S = H * P * H.transpose() + Eigen::MatrixXd(pose_ekf::ConeCovariance(o));
  const Eigen::MatrixXd K = P * H.transpose() * S.inverse();
  const Eigen::VectorXd x = Eigen::VectorXd(s->x) + K * Eigen::VectorXd(pose_ekf::ConePixels(o) - h);
  const Eigen::MatrixXd Pn = (Eigen::MatrixXd::Identity(P.rows(), P.cols()) - K * H) * P;
  s->x = x;
  s->x.segment<4>(pose_ekf::kQ).normalize();
  s->P = 0.5 * (Pn + Pn.transpose());
}

}  // namespace

int main() {
  pose_ekf_test::RigSimConfig sim;
  sim.duration_s = 60.0;
  const std::vector<Event> events = pose_ekf_test::GenerateRig(sim);
  pose_ekf::EkfConfig config;
  const auto layout = pose_ekf_test::DefaultCones();
  const pose_ekf::PinholeIntrinsics K = pose_ekf_test::DefaultIntrinsics();
  std::printf("pose_ekf_cone_bench: %zu events (60 s: camera 30 Hz, IMU 100 Hz), 16 states, 3 cones\n", events.size());

  std::vector<double> one_us, three_us, dense_us, pose_us, buffer_us;
  for (int repeat = 0; repeat < 3; ++repeat) {
    std::mt19937 rng(1 + repeat);
    pose_ekf::EkfCore ekf(config);
    pose_ekf::MeasurementBuffer buffer(config);
    for (const Event& e : events) {
      if (!e.is_camera) {
        buffer.AddImu(e.imu);
        if (!ekf.initialized()) continue;
        ekf.Predict(e.stamp_s);
        ekf.UpdateGyro(e.imu);
        ekf.UpdateAccel(e.imu);
        continue;
      }
      if (!ekf.initialized()) {
        ekf.Initialize(e.camera);
        buffer.AddCamera(e.camera);
        continue;
      }
      const pose_ekf::ConeFrame three =
          pose_ekf_test::ObserveCones(e.stamp_s, e.truth.T_cones_camera, layout, {0, 1, 2}, K, 1.0, &rng);
      pose_ekf::ConeFrame one = three;
      one.cones.resize(std::min<size_t>(1, three.cones.size()));
      if (three.cones.size() != 3) continue;
      ekf.Predict(e.stamp_s);
      const pose_ekf::FilterState prior = ekf.state();
      pose_ekf::FilterState dense = prior;
      one_us.push_back(TimeUs([&] { ekf.UpdateCones(one); }));
      ekf.Restore(prior);
      pose_us.push_back(TimeUs([&] { ekf.UpdateCamera(e.camera); }));
      ekf.Restore(prior);
      dense_us.push_back(TimeUs([&] {
                           for (const auto& o : three.cones) DenseConeUpdate(&dense, three, o);
                         }) /
                         3.0);
      three_us.push_back(TimeUs([&] { ekf.UpdateCones(three); }) / 3.0);
      buffer_us.push_back(TimeUs([&] { buffer.AddCones(three); }));
    }
  }
  const double per_cone_one = Median(one_us), per_cone_three = Median(three_us);
  Print("cone_update_1_cone_median", per_cone_one, "us");
  Print("cone_update_per_cone_3_cones_median", per_cone_three, "us");
  Print("cone_frame_3_cones_buffered_median", Median(buffer_us), "us");
  Print("pose_update_median", Median(pose_us), "us");
  Print("dense_reference_cone_update_per_cone_median", Median(dense_us), "us");
  Print("cone_update_ratio_vs_dense", per_cone_three / Median(dense_us), "x");
  Print("cone_update_3_cones_ratio_vs_pose_update", 3.0 * per_cone_three / Median(pose_us), "x");
  const double worst = std::max(per_cone_one, per_cone_three);
  std::printf("target (issue 16): per cone <= 10 us %s (%.2f us)\n", worst <= 10.0 ? "met" : "MISSED", worst);
  return 0;
}
