// Synthetic cone observations (cone_tracker/observations as the core sees them) on the synthetic
// rig of synthetic_rig.h: each camera event's truth projected through the pinhole model with pixel
// noise, and filter runs that feed them, the IMU and (some of) the camera poses.
#pragma once

#include <functional>
#include <random>
#include <vector>

#include "pose_ekf/core/cone_measurement.h"
#include "pose_ekf/core/ekf_core.h"
#include "pose_ekf/core/measurement_buffer.h"
#include "pose_ekf/testing/synthetic_rig.h"

namespace pose_ekf_test {

// The default layout's cones (rig_model::DefaultLayout: three 0.71 m cones, 1.5 m apart).
std::vector<pose_ekf::ConeGeometry> DefaultCones();
// A 1920x1440 pinhole camera with fx = fy = 800 px (100 by 84 degrees: the rig's cones stay in view).
pose_ekf::PinholeIntrinsics DefaultIntrinsics();

// The projection of `cones` (indices into layout) seen from T_cones_camera, with independent pixel
// noise sigma_px per coordinate (and that covariance). Cones not at least 0.3 m in front, or with a
// point outside the 2 cx by 2 cy image, are left out.
pose_ekf::ConeFrame ObserveCones(double stamp_s, const pose_math::Pose& T_cones_camera,
                                 const std::vector<pose_ekf::ConeGeometry>& layout, const std::vector<int>& cones,
                                 const pose_ekf::PinholeIntrinsics& K, double sigma_px, std::mt19937* rng);

// The filter configuration of the per-cone tests: camera_update cones (opt-in in the core), the
// synthetic rig's gyro and accelerometer noise.
pose_ekf::EkfConfig ConeSimConfig();
// The synthetic rig's first true pose: 2.6 m from the cones, looking at them.
pose_math::Pose ConeRigStart();
// An IMU sample of a rig held still at pose T: no rotation, the specific force of gravity alone.
pose_ekf::ImuMeasurement StillImu(const pose_math::Pose& T, const pose_ekf::EkfConfig& c);
// A filter initialised at ConeRigStart with a tight prior (1 mm, 1 mrad): S is then about R per cone. With
// sigma_p_m > 0 its position sigma is that on every axis instead (a filter after an outage).
pose_ekf::EkfCore Tight(const pose_ekf::EkfConfig& c, double sigma_p_m = 0.0);

struct ConeRunOptions {
  std::vector<pose_ekf::ConeGeometry> layout = DefaultCones();
  pose_ekf::PinholeIntrinsics K = DefaultIntrinsics();
  double sigma_px = 1.0;
  uint32_t seed = 7;
  // The layout cones visible in camera frame k (at stamp t); empty: none.
  std::function<std::vector<int>(int k, double t)> visible = [](int, double) { return std::vector<int>{0, 1, 2}; };
  // Which camera poses reach the filter: the first only (it initialises), those of frames with
  // three or more visible cones (what the tracker publishes), or every one.
  enum class Poses { kFirstOnly, kWhenThreeCones, kAll } poses = Poses::kWhenThreeCones;
  bool feed_cones = true;
  double delay_s = 0.0;  // camera poses and cone frames reach the buffer this long after their stamp
};

// Runs a MeasurementBuffer over the rig's events with cone frames; statistics as RunFilter's
// (RunStats), evaluated after each IMU sample from warmup_s on. The buffer's counters and the final
// state (after the messages still delayed at the end have arrived) go to the optional outputs.
RunStats RunFilterWithCones(const pose_ekf::EkfConfig& config, const std::vector<Event>& events,
                            const ConeRunOptions& options, double warmup_s,
                            pose_ekf::BufferCounters* counters_out = nullptr,
                            pose_ekf::FilterState* final_out = nullptr);

}  // namespace pose_ekf_test
