#include "cone_tracker/node/node_config.h"

#include <ros/node_handle.h>

#include <cmath>
#include <stdexcept>

#include "cone_tracker/node/params.h"
#include "rig_model/ros/param_table_ros.h"

namespace cone_tracker {
namespace {

void Check(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("parameter ~" + what);
}

}  // namespace

void ValidateConfig(const NodeConfig& c) {
  Check(!c.fixed_frame.empty(), "fixed_frame must not be empty");
  Check(!c.camera_frame.empty(), "camera_frame must not be empty");
  Check(c.prediction_max_age_s >= 0.0, "prediction_max_age_s must be >= 0");
  Check(c.reacquire_after_s > 0.0, "reacquire_after_s must be > 0");
  Check(std::isnan(c.heading_prior_deg) || std::isfinite(c.heading_prior_deg),
        "heading_prior_deg must be finite or nan");
  Check(c.two_cone_gravity_sigma_deg >= 0.0 && c.two_cone_gravity_sigma_deg <= 45.0,
        "two_cone_gravity_sigma_deg must be in [0, 45] (0: no two-cone start)");
  Check(c.gravity_window_s > 0.0 && c.gravity_window_s <= 1.0, "gravity_window_s must be in (0, 1]");
  Check(c.prediction_sigma_m > 0.0, "prediction_sigma_m must be > 0");
  Check(c.prediction_sigma_deg > 0.0, "prediction_sigma_deg must be > 0");
  Check(c.prediction_drift_m_s >= 0.0, "prediction_drift_m_s must be >= 0");
  Check(c.prediction_max_sigma_m >= c.prediction_sigma_m, "prediction_max_sigma_m must be >= prediction_sigma_m");
  Check(c.association_margin >= 0.0, "association_margin must be >= 0");
  Check(c.association_miss_cost >= 0.0, "association_miss_cost must be >= 0");
  Check(c.association_unexplained_cost >= 0.0, "association_unexplained_cost must be >= 0");
  Check(c.expected_rate_hz > 0.0, "expected_rate_hz must be > 0");
  Check(c.rate_tolerance >= 0.0 && c.rate_tolerance < 1.0, "rate_tolerance must be in [0, 1)");
  const std::string seg = c.segmenter.Validate();
  Check(seg.empty(), seg);
  const std::string detector = c.detector.Validate();
  Check(detector.empty(), detector);
  const std::string pose = c.pose.Validate();
  Check(pose.empty(), pose);
}

NodeConfig LoadConfig(const ros::NodeHandle& private_nh) {
  NodeConfig c;
  // Also known: the debug image's image_transport plugin settings (compressed_image_transport keeps
  // ~debug_image/compressed/* on the server across restarts).
  rig_model::LoadParams(private_nh, NodeParams(), &c, {"debug_image"});
  Check(!c.layout_file.empty(),
        "layout_file is required (a layout YAML in rig_model's schema, e.g. "
        "$(find rig_model)/config/layouts/default.yaml)");
  c.pose.initial_heading_rad = c.heading_prior_deg * (M_PI / 180.0);  // the core works in radians
  ValidateConfig(c);
  return c;
}

}  // namespace cone_tracker
