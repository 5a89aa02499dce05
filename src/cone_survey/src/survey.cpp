#include "cone_survey/survey.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "bundle.h"
#include "imu_track.h"
#include "initialise.h"

namespace cone_survey {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The arc of directions (degrees) the cone was seen from: 360 minus the largest gap between the
// bearings of the cameras around it.
double ViewSpreadDeg(std::vector<double> azimuths_rad) {
  if (azimuths_rad.size() < 2) return 0.0;
  std::sort(azimuths_rad.begin(), azimuths_rad.end());
  double gap = azimuths_rad.front() + 2.0 * kPi - azimuths_rad.back();
  for (size_t i = 1; i < azimuths_rad.size(); ++i) gap = std::max(gap, azimuths_rad[i] - azimuths_rad[i - 1]);
  return (2.0 * kPi - gap) * 180.0 / kPi;
}

std::string Fixed(double v, int digits) {
  std::ostringstream s;
  s.precision(digits);
  s << std::fixed << v;
  return s.str();
}

}  // namespace

std::string SurveyConfig::Validate() const {
  std::ostringstream e;
  if (!(track_gate_frac > 0.0 && track_gate_frac < 1.0))
    e << "track_gate_frac must be in (0, 1)";
  else if (track_max_gap_frames < 0 || min_track_frames < 2)
    e << "need track_max_gap_frames >= 0, min_track_frames >= 2";
  else if (!(adjust_rate_hz > 0.0))
    e << "adjust_rate_hz must be > 0";
  else if (!(sigma_px > 0.0 && robust_px > 0.0))
    e << "sigma_px and robust_px must be > 0";
  else if (!(gyro_noise_rad_s > 0.0 && gravity_sigma_deg > 0.0 && accel_noise_m_s2 > 0.0))
    e << "gyro_noise_rad_s, gravity_sigma_deg, accel_noise_m_s2 must be > 0";
  else if (!(height_tolerance > 0.0 && height_tolerance < 0.5))
    e << "height_tolerance must be in (0, 0.5)";
  else if (min_frames < 2 || !(min_view_spread_deg >= 0.0))
    e << "need min_frames >= 2, min_view_spread_deg >= 0";
  else if (!(outlier_px > 0.0 && moved_fraction > 0.0 && moved_fraction <= 1.0))
    e << "need outlier_px > 0 and moved_fraction in (0, 1]";
  return e.str();
}

SurveyResult SurveyLayout(const SurveyInput& in, const Inventory& inv, const SurveyConfig& config) {
  SurveyResult res;
  res.error = config.Validate();
  if (!res.error.empty()) return res;
  if (in.frames.empty() || in.imu.empty()) {
    res.error = in.frames.empty() ? "no camera frames" : "no IMU samples";
    return res;
  }
  const GyroIntegrator gyro(in.imu, in.R_camera_imu);
  Eigen::Vector3d bias = Eigen::Vector3d::Zero();
  if (!gyro.StillStartBias(config.still_start_s, &bias))
    res.notes.push_back("the walk does not start still: the gyro bias starts at zero (hold the rig still for " +
                        Fixed(config.still_start_s, 1) + " s at the start)");
  const std::vector<Track> tracks = TrackCones(in, gyro, bias, config);
  res.tracks = static_cast<int>(tracks.size());
  InitialSurvey survey;
  if (!InitialiseSurvey(in, inv, config, gyro, bias, tracks, &survey, &res.error)) return res;
  BundleResult bundle;
  if (!AdjustSurvey(in, inv, config, gyro, bias, &survey, &bundle, &res.error)) return res;
  res.frames_adjusted = static_cast<int>(survey.frames.size());
  res.observations = static_cast<int>(survey.observations.size());
  res.reprojection_rms_px = bundle.rms_px;
  res.gyro_bias_rad_s = bundle.bias_imu;
  res.base_offset_px = bundle.base_offset_px;
  res.scale_sigma = bundle.scale_sigma;

  // Per cone: frames, directions, residuals.
  const double t0 = in.frames.front().stamp_s;
  const int n = static_cast<int>(inv.cones.size());
  std::vector<std::vector<double>> azimuths(n);
  std::vector<double> sum_sq(n, 0.0), first(n, 1e300), last(n, -1e300), outlier_first(n, 1e300),
      outlier_last(n, -1e300);
  std::vector<int> count(n, 0), outliers(n, 0);
  for (size_t i = 0; i < survey.observations.size(); ++i) {
    const Observation& o = survey.observations[i];
    const Eigen::Vector3d d = survey.p_camera_m[o.frame] - survey.base_m[o.cone];
    azimuths[o.cone].push_back(std::atan2(d.y(), d.x()));
    const double e = bundle.error_px[i], t = in.frames[survey.frames[o.frame]].stamp_s - t0;
    sum_sq[o.cone] += e * e;
    ++count[o.cone];
    first[o.cone] = std::min(first[o.cone], t);
    last[o.cone] = std::max(last[o.cone], t);
    if (e > config.outlier_px) {
      ++outliers[o.cone];
      outlier_first[o.cone] = std::min(outlier_first[o.cone], t);
      outlier_last[o.cone] = std::max(outlier_last[o.cone], t);
    }
  }
  std::ostringstream moved, weak;
  for (int i = 0; i < n; ++i) {
    SurveyedCone c;
    c.spec = inv.cones[i];
    c.spec.base_m = survey.base_m[i];
    c.sigma_m = bundle.sigma_m[i];
    c.correlation_factor = bundle.correlation_factor[i];
    c.frames = count[i];
    c.view_spread_deg = ViewSpreadDeg(azimuths[i]);
    c.rms_px = count[i] ? std::sqrt(sum_sq[i] / count[i]) : 0.0;
    c.outlier_fraction = count[i] ? static_cast<double>(outliers[i]) / count[i] : 0.0;
    c.first_seen_s = first[i];
    c.last_seen_s = last[i];
    res.cones.push_back(c);
    const std::string at = " at (" + Fixed(c.spec.base_m.x(), 2) + ", " + Fixed(c.spec.base_m.y(), 2) + ") m";
    if (c.outlier_fraction > config.moved_fraction)
      moved << "\n  " << inv.Name(i) << at << ": " << outliers[i] << " of its " << count[i]
            << " sightings are off by more than " << config.outlier_px << " px (between " << Fixed(outlier_first[i], 1)
            << " and " << Fixed(outlier_last[i], 1) << " s): it moved during the walk";
    else if (c.frames < config.min_frames || c.view_spread_deg < config.min_view_spread_deg)
      weak << "\n  " << inv.Name(i) << at << ": seen in " << c.frames << " frames from directions spanning "
           << Fixed(c.view_spread_deg, 0) << " deg (need " << config.min_frames << " frames over "
           << config.min_view_spread_deg << " deg): walk around it";
  }
  if (!moved.str().empty()) {
    res.error = "cones moved during the walk (survey again with every cone in place):" + moved.str();
    return res;
  }
  if (!weak.str().empty()) {
    res.error = "the walk does not constrain every cone:" + weak.str();
    return res;
  }
  res.ok = true;
  return res;
}

}  // namespace cone_survey
