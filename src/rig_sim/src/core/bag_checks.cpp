#include "rig_sim/bag_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace rig_sim {
namespace {

std::string Fmt(const char* format, double a, double b = 0, double c = 0, double d = 0, double e = 0) {
  char buf[256];
  std::snprintf(buf, sizeof(buf), format, a, b, c, d, e);
  return buf;
}

template <typename R>
double Start(const std::vector<R>& v) {
  return v.empty() ? 0.0 : v.front().stamp_s;
}

// Monotonic stamps, rate from the median period, largest gap, latency.
template <typename R>
void CheckSeries(const std::string& topic, const std::vector<R>& v, double t0, double expected_hz, double min_hz,
                 const ValidateConfig& cfg, ValidationReport* report) {
  if (v.size() < 2) {
    report->checks.push_back({topic + " present", false, Fmt("only %.0f message(s)", v.size())});
    return;
  }
  std::vector<double> periods;
  Check mono{topic + " monotonic stamps", true, "strictly increasing"};
  Check gap{topic + " gaps", true, ""};
  Check latency{topic + " latency", true, ""};
  double worst_gap = 0.0, worst_at = 0.0, worst_latency = 0.0;
  for (size_t i = 1; i < v.size(); ++i) {
    const double dt = v[i].stamp_s - v[i - 1].stamp_s;
    if (dt <= 0.0 && mono.ok) {
      mono.ok = false;
      mono.message =
          Fmt("stamp at t=%.6f s is not after the previous one (t=%.6f s)", v[i].stamp_s - t0, v[i - 1].stamp_s - t0);
    }
    periods.push_back(dt);
    if (dt > worst_gap) worst_gap = dt, worst_at = v[i - 1].stamp_s - t0;
  }
  for (const R& r : v) {
    const double lat = r.receive_s - r.stamp_s;
    if (lat < -1e-6 || lat > cfg.max_latency_s) {
      latency.ok = false;
      latency.message = Fmt("bag time minus stamp is %.3f s at t=%.3f s (allowed 0 to %.3f s)", lat, r.stamp_s - t0,
                            cfg.max_latency_s);
      break;
    }
    worst_latency = std::max(worst_latency, lat);
  }
  if (latency.ok) latency.message = Fmt("largest %.4f s", worst_latency);
  std::nth_element(periods.begin(), periods.begin() + periods.size() / 2, periods.end());
  const double median = periods[periods.size() / 2];
  const double limit = cfg.max_gap_factor * median;
  gap.ok = worst_gap <= limit;
  gap.message = Fmt(gap.ok ? "largest gap %.4f s at t=%.3f s (median period %.4f s; limit %.4f s)"
                           : "gap of %.3f s after t=%.3f s (median period %.4f s; limit %.4f s)",
                    worst_gap, worst_at, median, limit);
  const double rate = median > 0.0 ? 1.0 / median : 0.0;
  Check rate_check{topic + " rate", true, ""};
  if (expected_hz > 0.0) {
    rate_check.ok = std::fabs(rate - expected_hz) <= cfg.rate_tolerance * expected_hz;
    rate_check.message = Fmt("%.2f Hz (expected %.2f Hz +- %.0f%%)", rate, expected_hz, 100.0 * cfg.rate_tolerance);
  } else if (min_hz > 0.0) {
    rate_check.ok = rate >= min_hz * (1.0 - cfg.rate_tolerance);
    rate_check.message = Fmt("%.2f Hz (at least %.2f Hz required)", rate, min_hz);
  } else {
    rate_check.message = Fmt("%.2f Hz", rate);
  }
  report->checks.push_back(mono);
  report->checks.push_back(rate_check);
  report->checks.push_back(gap);
  report->checks.push_back(latency);
}

void CheckCameraInfo(const BagContents& bag, double t0, ValidationReport* report) {
  Check c{"camera_info matches images", true, ""};
  size_t j = 0, matched = 0;
  for (const ImageRecord& img : bag.images) {
    const double bpp = img.encoding == "rgb8" || img.encoding == "bgr8" ? 3 : img.encoding == "mono8" ? 1 : 0;
    if (bpp == 0 || img.step < img.width * bpp || img.data_size != static_cast<size_t>(img.step) * img.height) {
      c.ok = false;
      c.message = Fmt("image at t=%.3f s: bad encoding/step/size (", img.stamp_s - t0) + img.encoding + ", step " +
                  std::to_string(img.step) + ", " + std::to_string(img.data_size) + " bytes for " +
                  std::to_string(img.width) + "x" + std::to_string(img.height) + ")";
      break;
    }
    while (j < bag.infos.size() && bag.infos[j].stamp_s < img.stamp_s - 1e-9) ++j;
    if (j == bag.infos.size() || std::fabs(bag.infos[j].stamp_s - img.stamp_s) > 1e-9) {
      c.ok = false;
      c.message = Fmt("no camera_info with the stamp of the image at t=%.3f s", img.stamp_s - t0);
      break;
    }
    const InfoRecord& info = bag.infos[j];
    if (info.width != img.width || info.height != img.height || info.frame != img.frame) {
      c.ok = false;
      c.message = Fmt("at t=%.3f s camera_info says %.0fx%.0f", img.stamp_s - t0, info.width, info.height) + " in '" +
                  info.frame + "' but the image is " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                  " in '" + img.frame + "'";
      break;
    }
    if (!(info.fx > 0.0 && info.fy > 0.0) || (info.distortion_model == "plumb_bob" && info.d_size != 5)) {
      c.ok = false;
      c.message =
          Fmt("camera_info at t=%.3f s has a bad K or D (fx %.1f, fy %.1f, ", info.stamp_s - t0, info.fx, info.fy) +
          info.distortion_model + " with " + std::to_string(info.d_size) + " coefficients)";
      break;
    }
    ++matched;
  }
  if (c.ok) c.message = std::to_string(matched) + " images, each with a matching camera_info";
  report->checks.push_back(c);
}

// Rest stretches from the ground truth (pose unchanged), else from the IMU
// (gyro and accel nearly constant over 0.5 s).
std::vector<bool> RestMask(const BagContents& bag) {
  std::vector<bool> rest(bag.imu.size(), false);
  if (!bag.truth.empty()) {
    size_t j = 0;
    for (size_t i = 0; i < bag.imu.size(); ++i) {
      const double t = bag.imu[i].stamp_s;
      while (j < bag.truth.size() && bag.truth[j].stamp_s < t - 0.25) ++j;
      size_t k = j;
      bool still = j < bag.truth.size() && bag.truth[j].stamp_s <= t - 0.24;
      for (; still && k < bag.truth.size() && bag.truth[k].stamp_s <= t + 0.25; ++k)
        still =
            (bag.truth[k].p - bag.truth[j].p).norm() < 1e-7 && bag.truth[k].q.angularDistance(bag.truth[j].q) < 1e-7;
      rest[i] = still && k < bag.truth.size();
    }
    return rest;
  }
  const size_t w = 50;
  for (size_t i = 0; i + w <= bag.imu.size(); ++i) {
    Eigen::Vector3d mg = Eigen::Vector3d::Zero(), ma = mg;
    for (size_t k = i; k < i + w; ++k) mg += bag.imu[k].gyro_rad_s, ma += bag.imu[k].accel_m_s2;
    mg /= w, ma /= w;
    double sg = 0, sa = 0;
    for (size_t k = i; k < i + w; ++k)
      sg += (bag.imu[k].gyro_rad_s - mg).squaredNorm(), sa += (bag.imu[k].accel_m_s2 - ma).squaredNorm();
    if (std::sqrt(sg / w) < 0.01 && std::sqrt(sa / w) < 0.1) rest[i + w / 2] = true;
  }
  return rest;
}

void CheckImu(const BagContents& bag, double t0, const ValidateConfig& cfg, ValidationReport* report) {
  Check fmt{"imu REP-145 fields", true, "no orientation (covariance[0] = -1), finite values, frame set"};
  for (const ImuRecord& r : bag.imu) {
    if (r.orientation_covariance0 != -1.0 || !r.gyro_rad_s.allFinite() || !r.accel_m_s2.allFinite() ||
        r.frame.empty()) {
      fmt.ok = false;
      fmt.message = Fmt("sample at t=%.3f s: orientation_covariance[0] = %g (want -1), non-finite values or no frame",
                        r.stamp_s - t0, r.orientation_covariance0);
      break;
    }
  }
  report->checks.push_back(fmt);
  const std::vector<bool> rest = RestMask(bag);
  Check norms{"imu norms at rest", true, ""};
  // Mean over each contiguous rest stretch, so white noise does not fail it.
  size_t stretches = 0, samples = 0;
  for (size_t i = 0; i < rest.size();) {
    if (!rest[i]) {
      ++i;
      continue;
    }
    size_t k = i;
    Eigen::Vector3d g = Eigen::Vector3d::Zero(), a = g;
    for (; k < rest.size() && rest[k]; ++k) g += bag.imu[k].gyro_rad_s, a += bag.imu[k].accel_m_s2;
    const double n = static_cast<double>(k - i);
    const double an = (a / n).norm(), gn = (g / n).norm();
    ++stretches;
    samples += k - i;
    if (std::fabs(an - cfg.gravity_m_s2) > cfg.rest_accel_tolerance_m_s2 || gn > cfg.rest_gyro_max_rad_s) {
      norms.ok = false;
      norms.message = Fmt("at rest from t=%.3f s to %.3f s: |accel| %.3f m/s^2 (want %.2f +- %.2f), |gyro| %.4f rad/s",
                          bag.imu[i].stamp_s - t0, bag.imu[k - 1].stamp_s - t0, an, cfg.gravity_m_s2,
                          cfg.rest_accel_tolerance_m_s2) +
                      Fmt(" (max %.3f)", gn, cfg.rest_gyro_max_rad_s);
      break;
    }
    i = k;
  }
  if (norms.ok)
    norms.message = stretches == 0 ? "no rest stretch found (nothing to check)"
                                   : Fmt("%.0f rest stretch(es), %.0f samples, |accel| within %.2f m/s^2 of g",
                                         stretches, samples, cfg.rest_accel_tolerance_m_s2);
  report->checks.push_back(norms);
}

}  // namespace

bool ValidationReport::ok() const {
  return std::all_of(checks.begin(), checks.end(), [](const Check& c) { return c.ok; });
}

std::string ValidationReport::Text() const {
  std::ostringstream out;
  for (const Check& c : checks) out << (c.ok ? "PASS " : "FAIL ") << c.name << ": " << c.message << "\n";
  return out.str();
}

ValidationReport ValidateContents(const BagContents& bag, const ValidateConfig& cfg) {
  ValidationReport report;
  double t0 = 1e300;
  if (!bag.imu.empty()) t0 = std::min(t0, Start(bag.imu));
  if (!bag.images.empty()) t0 = std::min(t0, Start(bag.images));
  if (!bag.truth.empty()) t0 = std::min(t0, Start(bag.truth));
  if (t0 == 1e300) t0 = 0.0;
  CheckSeries(bag.imu_topic, bag.imu, t0, cfg.imu_rate_hz, 0.0, cfg, &report);
  CheckSeries(bag.image_topic, bag.images, t0, cfg.camera_rate_hz, 0.0, cfg, &report);
  CheckSeries(bag.info_topic, bag.infos, t0, cfg.camera_rate_hz, 0.0, cfg, &report);
  if (bag.truth.empty())
    report.checks.push_back({"ground truth", true, "none in this bag (a real-rig bag?)"});
  else
    CheckSeries(bag.truth_topic, bag.truth, t0, 0.0, cfg.min_truth_rate_hz, cfg, &report);
  CheckCameraInfo(bag, t0, &report);
  if (!bag.imu.empty()) CheckImu(bag, t0, cfg, &report);
  return report;
}

}  // namespace rig_sim
