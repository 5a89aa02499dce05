#include "cone_tracker/node/tracker_adapter.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <cv_bridge/cv_bridge.h>
#include <boost/make_shared.hpp>
#include <boost/math/distributions/chi_squared.hpp>

#include "cone_tracker/node/layout.h"
#include "cone_tracker/vision/two_cone_pose.h"
#include "pose_math/covariance.h"
#include "pose_math/pose.h"
#include "rig_model/ros/conversions.h"

namespace cone_tracker {
namespace {

constexpr int kMinImageSidePx = 8;  // below this the two-level pyramid (3.1.5.2) has nothing to work on

int ChannelsOf(const std::string& encoding) {
  return encoding == "rgb8" || encoding == "bgr8" ? 3 : 1;  // bayer_*8: one byte per pixel
}

void Set2(const Eigen::Vector2d& v, boost::array<double, 2>* out) { (*out)[0] = v.x(), (*out)[1] = v.y(); }

DetectedCone ToMsg(const ConeDetection& d, int cone_id) {
  DetectedCone m;
  Set2(d.peak_px, &m.peak_px), Set2(d.mid_px, &m.mid_px), Set2(d.base_px, &m.base_px);
  Set2(d.peak_undist_px, &m.peak_undistorted_px), Set2(d.mid_undist_px, &m.mid_undistorted_px),
      Set2(d.base_undist_px, &m.base_undistorted_px);
  const Blob& b = d.blob;
  m.area_px = b.area, m.solidity = b.solidity;
  Set2(b.centroid, &m.centroid_px);
  m.major_axis_px = b.major_px, m.minor_axis_px = b.minor_px;
  m.orientation_rad = b.orientation_rad, m.axis_ratio = b.axis_ratio;
  m.bbox_px = {b.bbox_x, b.bbox_y, b.bbox_w, b.bbox_h};
  m.fragments = b.fragments;
  m.failed_gates = d.failed_gates;
  m.failed_gate_names = SegmentationGateNames(d.failed_gates);
  m.cone_id = cone_id;
  return m;
}

}  // namespace

const char* ToString(FrameStatus s) {
  switch (s) {
    case FrameStatus::kPose:
      return "pose";
    case FrameStatus::kNoCameraInfo:
      return "no camera_info";
    case FrameStatus::kBadCameraInfo:
      return "invalid camera_info";
    case FrameStatus::kBadImage:
      return "bad image";
    case FrameStatus::kUnsupportedEncoding:
      return "unsupported encoding";
    case FrameStatus::kSizeMismatch:
      return "image size differs from camera_info";
    case FrameStatus::kNoCones:
      return "no cones";
    case FrameStatus::kTooFewCones:
      return "too few cones";
    case FrameStatus::kSolverFailed:
      return "pose solver failed";
    case FrameStatus::kRejectedChi2:
      return "rejected by the chi-square gate";
    case FrameStatus::kRejectedMotion:
      return "rejected by the motion gate";
    case FrameStatus::kRejectedAmbiguous:
      return "rejected: another assignment of the cones fits too";
  }
  return "?";
}

std::vector<std::string> PoseGateNames(uint32_t bits) {
  static const std::pair<uint32_t, const char*> kNames[] = {{kPoseTooFewCones, "too_few_cones"},
                                                            {kPoseSolverFailed, "solver"},
                                                            {kPoseChi2, "chi2"},
                                                            {kPoseMotion, "motion"},
                                                            {kPoseAmbiguous, "ambiguous"}};
  std::vector<std::string> out;
  for (const auto& [bit, name] : kNames)
    if (bits & bit) out.emplace_back(name);
  return out;
}

namespace {

// The config with the layout's collars for reading cut cones (segmenter.h, read_collars).
NodeConfig WithCollars(NodeConfig config, const std::vector<ConeModel>& layout) {
  config.segmenter.collar.collars = CommonCollars(layout);
  return config;
}

}  // namespace

TrackerAdapter::TrackerAdapter(const NodeConfig& config, const std::vector<ConeModel>& layout)
    : config_(WithCollars(config, layout)), layout_(layout), detector_(config_.segmenter, config_.detector) {
  ValidateConfig(config_);
  if (layout_.size() < 3 || int(layout_.size()) > kMaxTrackedCones)
    throw std::invalid_argument("the layout needs 3 to " + std::to_string(kMaxTrackedCones) + " cones");
}

bool TrackerAdapter::SetCameraInfo(const sensor_msgs::CameraInfo& info, std::string* error) {
  has_camera_info_ = true;
  CameraModel camera;
  camera_error_.clear();
  camera_valid_ = rig_model::FromCameraInfo(info, &camera, &camera_error_);
  if (!camera_valid_) {
    ++counters_.bad_camera_info_msgs;
    if (error) *error = camera_error_;
    return false;
  }
  camera_ = camera;
  camera_width_ = camera.width_px, camera_height_ = camera.height_px;
  return true;
}

void TrackerAdapter::Reconfigure(const SegmenterConfig& segmenter, const ConePoseConfig& pose,
                                 const DebugImageConfig& debug) {
  NodeConfig next = config_;
  next.segmenter = segmenter, next.pose = pose, next.debug = debug;
  next.segmenter.collar.collars = config_.segmenter.collar.collars;  // the layout's, not a parameter
  ValidateConfig(next);
  detector_.SetConfig(segmenter, next.detector.dnn_score_min);  // the colour table: only if the HSI bounds changed
  config_ = next;
}

void TrackerAdapter::ClearTrack() {
  last_T_cones_camera_.reset();
  own_track_ = false;
  track_start_stamp_ = ros::Time();
  tracked_stamp_ = ros::Time();
}

FrameResult TrackerAdapter::Fail(FrameStatus status, const std::string& message) {
  FrameResult r;
  r.status = status, r.message = message;
  return r;
}

std::optional<pose_math::Pose> TrackerAdapter::Prediction(const ros::Time& stamp,
                                                          const std::optional<pose_math::Pose>& tf_T_cones_camera,
                                                          std::string* source) {
  const bool last_recent = last_T_cones_camera_ && (stamp - last_pose_stamp_).toSec() <= config_.prediction_max_age_s;
  // A track re-acquired from the cones alone predicts while tf contradicts it (6.4.2's motion gate): pose_ekf may be
  // metres off and sure of it, and frames predicted by tf would feed it its own wrong ids (README, "The re-acquired
  // track overrules a contradicting tf"). Its cones reach pose_ekf with their own ids until it re-initialises.
  if (own_track_ && last_recent && tf_T_cones_camera) {
    const pose_math::Pose& T_tf = *tf_T_cones_camera;
    if (config_.pose.WithinMotionGate(pose_math::TranslationError(T_tf, *last_T_cones_camera_),
                                      pose_math::RotationErrorRad(T_tf, *last_T_cones_camera_) * 180.0 / M_PI)) {
      own_track_ = false;
    } else {
      ++counters_.tf_overruled;
      *source = "last_pose";
      return last_T_cones_camera_;
    }
  }
  if (tf_T_cones_camera) {
    *source = "tf";
    return tf_T_cones_camera;
  }
  if (last_recent) {
    *source = "last_pose";
    return last_T_cones_camera_;
  }
  *source = "none";
  return std::nullopt;
}

FrameResult TrackerAdapter::Process(const sensor_msgs::ImageConstPtr& msg,
                                    const std::optional<pose_math::Pose>& tf_T_cones_camera,
                                    const std::optional<pose_math::Matrix6d>& tf_cov_ros,
                                    const std::optional<Eigen::Vector3d>& up_camera) {
  ++counters_.frames;
  if (!msg) return ++counters_.bad_image, Fail(FrameStatus::kBadImage, "null image message");
  const sensor_msgs::Image& im = *msg;
  if (!Segmenter::SupportedEncoding(im.encoding)) {
    ++counters_.unsupported_encoding;
    return Fail(FrameStatus::kUnsupportedEncoding,
                "image encoding '" + im.encoding + "' is not supported (rgb8, bgr8, bayer_rggb8/bggr8/gbrg8/grbg8)");
  }
  const size_t row_bytes = size_t(im.width) * ChannelsOf(im.encoding);
  std::ostringstream bad;
  if (int(im.width) < kMinImageSidePx || int(im.height) < kMinImageSidePx) {
    bad << "image is " << im.width << "x" << im.height << " px (at least " << kMinImageSidePx << "x" << kMinImageSidePx
        << " needed)";
  } else if (im.step < row_bytes) {
    bad << "image step " << im.step << " is shorter than a row (" << row_bytes << " bytes)";
  } else if (im.data.size() < size_t(im.step) * im.height) {
    bad << "image data has " << im.data.size() << " bytes, step x height is " << size_t(im.step) * im.height;
  }
  if (!bad.str().empty()) return ++counters_.bad_image, Fail(FrameStatus::kBadImage, bad.str());
  if (!has_camera_info_) {
    ++counters_.no_camera_info;
    return Fail(FrameStatus::kNoCameraInfo, "no camera_info received yet: cannot undistort or solve");
  }
  if (!camera_valid_) {
    ++counters_.bad_camera_info_frames;
    return Fail(FrameStatus::kBadCameraInfo, camera_error_ + "; no pose until a valid camera_info arrives");
  }
  if ((camera_width_ > 0 && int(im.width) != camera_width_) ||
      (camera_height_ > 0 && int(im.height) != camera_height_)) {
    ++counters_.size_mismatch;
    std::ostringstream m;
    m << "image is " << im.width << "x" << im.height << " but camera_info is " << camera_width_ << "x"
      << camera_height_;
    return Fail(FrameStatus::kSizeMismatch, m.str());
  }

  FrameResult r;
  if (!last_image_stamp_.isZero() && im.header.stamp < last_image_stamp_) {
    ++counters_.time_jumps;
    r.time_jumped_back = true;
    ClearTrack();
  }
  last_image_stamp_ = im.header.stamp;
  if (track_start_stamp_.isZero()) track_start_stamp_ = im.header.stamp;

  // The frame is shared, not copied: toCvShare without a target encoding wraps msg->data.
  cv_bridge::CvImageConstPtr cv;
  try {
    cv = cv_bridge::toCvShare(msg);
  } catch (const cv_bridge::Exception& e) {
    ++counters_.bad_image;
    return Fail(FrameStatus::kBadImage, std::string("cv_bridge cannot read the image: ") + e.what());
  }
  const ImageView view{cv->image.data, cv->image.cols, cv->image.rows, int(cv->image.step[0]), im.encoding};
  r.segmentation = detector_.Process(view, camera_).segmentation;  // colour, or the DNN's boxes (detector)
  if (!r.segmentation.ok) {
    ++counters_.bad_image;
    r.status = FrameStatus::kBadImage;
    r.message = "segmentation failed: " + r.segmentation.error;
    return r;
  }
  ++counters_.segmented_frames;
  counters_.cones_found_sum += r.segmentation.cones.size();
  for (const ConeDetection& d : r.segmentation.rejected)
    for (const std::string& g : SegmentationGateNames(d.failed_gates)) ++counters_.blobs_rejected_by_gate[g];

  const std::optional<pose_math::Pose> pred = Prediction(im.header.stamp, tf_T_cones_camera, &r.prediction_source);
  const ros::Time since = last_T_cones_camera_ ? last_pose_stamp_ : track_start_stamp_;
  const bool track_lost = (im.header.stamp - since).toSec() > config_.reacquire_after_s;
  const double since_tracked_s = tracked_stamp_.isZero() ? INFINITY : (im.header.stamp - tracked_stamp_).toSec();
  const bool from_tf = r.prediction_source == "tf";
  FillPose(im, pred, track_lost, up_camera, &r);
  FillObservations(im, pred, from_tf ? tf_cov_ros : std::nullopt, since_tracked_s, &r);
  return r;
}

void TrackerAdapter::FillPose(const sensor_msgs::Image& im, const std::optional<pose_math::Pose>& pred, bool track_lost,
                              const std::optional<Eigen::Vector3d>& up_camera, FrameResult* r) {
  const SegmentationResult& seg = r->segmentation;
  std::optional<pose_math::Pose> T_camera_cones_pred;
  if (pred) T_camera_cones_pred = pose_math::Invert(*pred);
  // Detections are undistorted already; the core solves on the pinhole K.
  r->cone_pose = EstimateConePose(seg.cones, layout_, camera_, config_.pose, T_camera_cones_pred);
  if (track_lost && pred && !r->cone_pose.ok && seg.cones.size() >= 3) {
    // The track is lost and the prediction matched nothing: re-initialise from
    // the linear algorithms (3.1.6), the prediction's bearing breaking the tie.
    ConePoseConfig reinit = config_.pose;
    reinit.initial_heading_rad = std::atan2(pred->t.y(), pred->t.x());
    r->cone_pose = EstimateConePose(seg.cones, layout_, camera_, reinit, std::nullopt);
    r->prediction_source = "reacquire";
    ++counters_.reacquisitions;
  }
  if (!pred && seg.cones.size() == 2 && layout_.size() <= kTwoConeMaxLayout &&
      config_.two_cone_gravity_sigma_deg > 0.0) {
    // No track to continue and two cones: the two-cone start (README, "Two cones and gravity").
    if (!up_camera) {
      ++counters_.two_cone_no_gravity;
    } else {
      r->cone_pose = EstimateTwoConePose(seg.cones, seg.rejected, layout_, camera_, config_.pose,
                                         GravityPrior{*up_camera, config_.two_cone_gravity_sigma_deg * M_PI / 180.0});
      r->prediction_source = "two_cones_gravity";
      ++(r->cone_pose.ok ? counters_.two_cone_poses : counters_.two_cone_refused);
    }
  }
  const ConePoseResult& cp = r->cone_pose;

  auto det = boost::make_shared<ConeDetections>();
  det->header = im.header;
  for (size_t i = 0; i < seg.cones.size(); ++i)
    det->detections.push_back(ToMsg(seg.cones[i], i < cp.cone_of_detection.size() ? cp.cone_of_detection[i] : -1));
  for (const ConeDetection& d : seg.rejected) det->detections.push_back(ToMsg(d, -1));
  det->accepted_count = int(seg.cones.size());
  det->roi_px = {seg.roi_x, seg.roi_y, seg.roi_w, seg.roi_h};
  det->prediction_source = r->prediction_source;
  det->pose_rejected_by = cp.rejected_by;
  det->pose_rejected_by_names = PoseGateNames(cp.rejected_by);
  if (cp.pnp.ok) {
    det->reprojection_rms_px = cp.pnp.reproj_rms_px;
    det->chi2 = cp.chi2;
    det->chi2_dof = cp.chi2_dof;
    det->chi2_threshold = cp.chi2_threshold;
    det->chi2_cdf = det->chi2_dof > 0 ? boost::math::cdf(boost::math::chi_squared(det->chi2_dof), cp.chi2) : 0.0;
    det->chi2_passed = !(cp.rejected_by & kPoseChi2);
    det->motion_checked = cp.motion_checked;
    det->motion_passed = cp.motion_checked && !(cp.rejected_by & kPoseMotion);
    det->translation_change_m = cp.translation_change_m;
    det->rotation_change_deg = cp.rotation_change_deg;
  }
  r->detections = det;

  std::ostringstream why;
  if (seg.cones.empty()) {
    ++counters_.no_cones;
    r->status = FrameStatus::kNoCones;
    why << "no cones found (" << seg.rejected.size() << " orange blobs rejected by the segmentation gates)";
  } else if (cp.rejected_by & kPoseTooFewCones) {
    ++counters_.too_few_cones;
    r->status = FrameStatus::kTooFewCones;
    why << seg.cones.size() << " cone(s) found: " << cp.error
        << (config_.two_cone_gravity_sigma_deg > 0.0 ? " (3 needed, or 2 with gravity and no track)" : " (3 needed)");
  } else if (cp.rejected_by & kPoseSolverFailed) {
    ++counters_.solver_failed;
    r->status = FrameStatus::kSolverFailed;
    why << cp.error;
  } else if (cp.rejected_by & kPoseChi2) {
    ++counters_.rejected_chi2;
    r->status = FrameStatus::kRejectedChi2;
    why << "chi-square gate (6.4.1): " << cp.chi2 << " > " << cp.chi2_threshold << " at probability "
        << config_.pose.chi2_probability;
    if (r->prediction_source == "two_cones_gravity") why << "; " << cp.error;
  } else if (cp.rejected_by & kPoseAmbiguous) {
    ++counters_.rejected_ambiguous;
    r->status = FrameStatus::kRejectedAmbiguous;
    why << "cold start refused: " << cp.error;
  } else if (cp.rejected_by & kPoseMotion) {
    ++counters_.rejected_motion;
    r->status = FrameStatus::kRejectedMotion;
    why << "motion gate (6.4.2): moved " << det->translation_change_m << " m, turned " << det->rotation_change_deg
        << " deg against the " << r->prediction_source << " prediction";
  } else if (!cp.ok) {
    ++counters_.solver_failed;
    r->status = FrameStatus::kSolverFailed;
    why << "no pose: " << cp.error;
  }
  if (!why.str().empty()) {
    r->message = why.str();
    det->status = r->message;
    return;
  }

  // The camera in `cones` with the covariance carried through the inversion;
  // its ROS 6x6 is the exact image of the constrained 7x7 (5.6.3-5.6.4).
  const pose_math::PoseWithCovariance T_cones_camera =
      pose_math::Invert(pose_math::PoseWithCovariance{cp.pnp.T_camera_model, cp.pnp.cov7});
  const pose_math::Matrix6d cov6 = pose_math::CovarianceRosFromThesis(T_cones_camera.pose.q, T_cones_camera.cov);
  if (!cov6.allFinite() || !T_cones_camera.pose.t.allFinite()) {
    ++counters_.solver_failed;
    r->status = FrameStatus::kSolverFailed;
    r->message = det->status = "non-finite pose or covariance";
    return;
  }
  auto pose = boost::make_shared<geometry_msgs::PoseWithCovarianceStamped>();
  pose->header.stamp = im.header.stamp;
  pose->header.frame_id = config_.fixed_frame;
  const pose_math::Pose& T = T_cones_camera.pose;
  pose->pose = rig_model::ToPoseWithCovarianceMsg(T, cov6);
  r->pose = pose;
  r->status = FrameStatus::kPose;
  det->pose_published = true;
  last_T_cones_camera_ = T;
  last_pose_stamp_ = im.header.stamp;
  own_track_ = r->prediction_source == "reacquire" || (own_track_ && r->prediction_source == "last_pose");
  ++counters_.poses;
}

}  // namespace cone_tracker
