// TrackerAdapter's cone_tracker/observations: which layout cone each detection
// is (the accepted pose's correspondence, else the association through the
// prediction, pose/associate.h) and the message with every associated cone's
// undistorted points and their 2x2 covariances.
#include <algorithm>
#include <cmath>

#include <boost/make_shared.hpp>

#include "cone_tracker/node/tracker_adapter.h"
#include "rig_model/ros/conversions.h"

namespace cone_tracker {
namespace {

void Set2(const Eigen::Vector2d& v, boost::array<double, 2>* out) { (*out)[0] = v.x(), (*out)[1] = v.y(); }

void Set4(const Eigen::Matrix2d& m, boost::array<double, 4>* out) {
  (*out)[0] = m(0, 0), (*out)[1] = m(0, 1), (*out)[2] = m(1, 0), (*out)[3] = m(1, 1);  // row-major
}

ConePoints2d PointsOf(const ConeDetection& d) { return {d.peak_undist_px, d.mid_undist_px, d.base_undist_px}; }

}  // namespace

void TrackerAdapter::FillObservations(const sensor_msgs::Image& im, const std::optional<pose_math::Pose>& pred,
                                      const std::optional<pose_math::Matrix6d>& pred_cov_ros, double since_tracked_s,
                                      FrameResult* r) {
  const std::vector<ConeDetection>& dets = r->segmentation.cones;
  if (dets.empty()) return;
  std::vector<ConePoints2d> points;
  std::vector<std::array<Eigen::Matrix2d, 3>> cov;
  for (const ConeDetection& d : dets) {
    points.push_back(PointsOf(d));
    cov.push_back(PointCovariances(points.back(), d.blob.area, config_.pose.sigma_px));
    if (d.by_collars) {  // the points read off the collars: their error along the axis (collar_ruler.h)
      const Eigen::Vector2d a = (d.base_undist_px - d.peak_undist_px).normalized();
      for (int k = 0; k < 3; ++k) cov.back()[size_t(k)] += d.axis_sigma_px(k) * d.axis_sigma_px(k) * a * a.transpose();
    }
  }
  if (pred) {
    AssociationConfig a;
    a.sigma_px = config_.pose.sigma_px;
    a.gate_probability = config_.pose.chi2_probability;
    a.ambiguity_margin = config_.association_margin;
    a.miss_cost = config_.association_miss_cost;
    a.unexplained_cost = config_.association_unexplained_cost;
    a.prediction_sigma_rad = config_.prediction_sigma_deg * M_PI / 180.0;
    if (pred_cov_ros) {
      // pose_ekf's own covariance, plus the prediction's error beyond it (prediction_sigma_*): not the tf's
      // extrapolation alone, pose_ekf's orientation can be several times its sigma off (README, "The tf
      // prediction at the image stamp").
      a.prediction_cov = AssociationPrior(pred->q, *pred_cov_ros);
      a.prediction_cov->diagonal() += Eigen::Matrix<double, 6, 1>(
          (Eigen::Matrix<double, 6, 1>() << Eigen::Vector3d::Constant(a.prediction_sigma_rad * a.prediction_sigma_rad),
           Eigen::Vector3d::Constant(config_.prediction_sigma_m * config_.prediction_sigma_m))
              .finished());
      ++counters_.association_filter_covariance;
    } else {
      // Without the filter's covariance: pose_ekf's position drifts while no cone is
      // fused; its orientation (gyros) stays near the prediction's (test/README.md).
      a.prediction_sigma_m = config_.prediction_drift_m_s > 0.0
                                 ? std::min(config_.prediction_max_sigma_m,
                                            config_.prediction_sigma_m + config_.prediction_drift_m_s * since_tracked_s)
                                 : config_.prediction_sigma_m;
    }
    CameraModel pinhole = camera_;  // the detections are undistorted (3.1.2)
    pinhole.distortion.clear();
    r->association = AssociateCones(points, cov, layout_.size(), LayoutSeenFrom(layout_), pinhole,
                                    pose_math::Invert(*pred), a, r->segmentation.orange_undist_px);
    counters_.association_ambiguous += uint64_t(r->association.ambiguous);
    counters_.association_conflicts += r->association.conflict;
  }

  std::vector<int> ids;
  const ConePoseResult& cp = r->cone_pose;
  if (cp.ok) {
    // 3.1.6 decided (and its pose passed the gates): the observations carry its ids.
    ids = cp.cone_of_detection;
    r->observation_source = "pose";
    const std::vector<int>& by_pred = r->association.cone_of_detection;
    for (size_t d = 0; d < ids.size() && d < by_pred.size(); ++d)
      if (ids[d] >= 0 && by_pred[d] >= 0 && ids[d] != by_pred[d]) ++counters_.association_disagreements;
  } else if (pred) {
    ids = r->association.cone_of_detection;
    r->observation_source = "prediction";
  } else {
    ++counters_.unobserved_no_prediction;  // start-up with fewer than 3 cones: nothing to associate with
    return;
  }

  auto msg = boost::make_shared<ConeObservations>();
  msg->header.stamp = im.header.stamp;
  msg->header.frame_id = im.header.frame_id.empty() ? config_.camera_frame : im.header.frame_id;
  msg->fx = camera_.fx_px, msg->fy = camera_.fy_px, msg->cx = camera_.cx_px, msg->cy = camera_.cy_px;
  msg->width = static_cast<uint32_t>(camera_.width_px), msg->height = static_cast<uint32_t>(camera_.height_px);
  for (const rig_model::ImageBox& b : r->segmentation.orange_undist_px) {
    const sensor_msgs::RegionOfInterest roi = rig_model::ToRoi(b, msg->width, msg->height, true);
    if (roi.width > 0) msg->orange.push_back(roi);
  }
  for (size_t d = 0; d < dets.size() && d < ids.size(); ++d) {
    if (ids[d] < 0) continue;
    ConeObservation o;
    o.cone_id = ids[d];
    Set2(points[d][0], &o.peak_px), Set2(points[d][1], &o.mid_px), Set2(points[d][2], &o.base_px);
    Set4(cov[d][0], &o.peak_cov_px2), Set4(cov[d][1], &o.mid_cov_px2), Set4(cov[d][2], &o.base_cov_px2);
    msg->cones.push_back(o);
  }
  if (r->pose || msg->cones.size() >= 2) tracked_stamp_ = im.header.stamp;
  if (msg->cones.empty()) {
    r->observation_source.clear();
    return;
  }
  ++counters_.observation_msgs;
  counters_.observed_cones_sum += msg->cones.size();
  ++counters_.observation_msgs_by_cones[int(msg->cones.size())];
  r->observations = msg;
}

}  // namespace cone_tracker
