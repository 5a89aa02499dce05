#include "pose_ekf/node/pose_ekf_adapter.h"

#include <ros/time.h>

#include <cmath>
#include <sstream>

#include "pose_math/covariance.h"
#include "pose_math/rotation.h"
#include "rig_model/ros/conversions.h"

namespace pose_ekf {
namespace {

template <size_t N>
Eigen::Matrix<double, N, N> ToMatrix(const boost::array<double, N * N>& a) {
  return Eigen::Map<const Eigen::Matrix<double, N, N, Eigen::RowMajor>>(a.data());
}

template <size_t N>
void FromMatrix(const Eigen::Matrix<double, N, N>& m, boost::array<double, N * N>* a) {
  Eigen::Map<Eigen::Matrix<double, N, N, Eigen::RowMajor>>(a->data()) = m;
}

Eigen::Vector3d ToVector(const geometry_msgs::Vector3& v) { return {v.x, v.y, v.z}; }

}  // namespace

bool QuaternionFarFromUnit(const geometry_msgs::Quaternion& q) {
  const double norm2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
  return !(std::abs(norm2 - 1.0) <= kQuaternionNorm2Tolerance);
}

ConversionResult CameraFromMsg(const geometry_msgs::PoseWithCovarianceStamped& msg, const std::string& cones_frame,
                               CameraMeasurement* out, std::string* why) {
  const std::string topic = kCameraTopic;
  if (msg.header.frame_id != cones_frame) {
    *why = topic + ": header.frame_id is '" + msg.header.frame_id + "', expected '" + cones_frame + "'";
    return ConversionResult::kInvalid;
  }
  out->stamp_s = msg.header.stamp.toSec();
  pose_math::Matrix6d cov6;
  rig_model::FromPoseWithCovarianceMsg(msg.pose, &out->T_cones_camera, &cov6);
  const pose_math::Quat q = out->T_cones_camera.q;  // as received: normalised below, counted by the caller
  const char* non_finite = !q.allFinite()                       ? "pose.pose.orientation"
                           : !out->T_cones_camera.t.allFinite() ? "pose.pose.position"
                           : !cov6.allFinite()                  ? "pose.covariance"
                                                                : nullptr;
  if (non_finite) {
    *why = topic + ": " + non_finite + " is not finite";
    return ConversionResult::kNonFinite;
  }
  const double norm = q.norm();
  if (norm < 1e-6) {
    *why = topic + ": pose.pose.orientation is zero (|q| = " + std::to_string(norm) + "), no rotation";
    return ConversionResult::kInvalid;
  }
  if (cov6.diagonal().minCoeff() <= 0.0) {
    *why = topic + ": pose.covariance has a non-positive diagonal entry";
    return ConversionResult::kInvalid;
  }
  out->T_cones_camera.q = q / norm;  // any norm means a rotation; far from 1 is counted by the caller
  out->cov = pose_math::CovarianceThesisFromRos(out->T_cones_camera.q, cov6);  // the 5.6.4 form
  return ConversionResult::kOk;
}

std::string CheckLeverArm(const Eigen::Vector3d& p, const std::string& camera_frame, const std::string& imu_frame) {
  if (p.allFinite() && p.norm() <= kMaxLeverArmM) return "";
  std::ostringstream s;
  s << "the tf " << camera_frame << " -> " << imu_frame << " has a translation (lever arm, camera_imu.translation_m of "
    << "the camera-IMU calibration) of " << p.norm() << " m [" << p.transpose() << "]; more than " << kMaxLeverArmM
    << " m is not a rig: IMU samples not used";
  return s.str();
}

ConversionResult ImuFromMsg(const sensor_msgs::Imu& msg, const Eigen::Quaterniond& q_camera_imu, ImuMeasurement* out,
                            std::string* why, const Eigen::Vector3d& p_imu_in_camera_m) {
  const Eigen::Matrix3d R = q_camera_imu.toRotationMatrix();
  out->stamp_s = msg.header.stamp.toSec();
  out->has_gyro = msg.angular_velocity_covariance[0] != -1.0;
  out->has_accel = msg.linear_acceleration_covariance[0] != -1.0;
  if (!out->has_gyro && !out->has_accel) {
    *why = "IMU message has neither angular velocity nor linear acceleration (both covariances -1)";
    return ConversionResult::kInvalid;
  }
  // Into the camera frame's axes (3.26); the origins differ by the lever arm, which the accelerometer model takes.
  out->p_imu_in_camera_m = p_imu_in_camera_m;
  out->omega_camera_rad_s = R * ToVector(msg.angular_velocity);
  out->accel_camera_m_s2 = R * ToVector(msg.linear_acceleration);
  const Eigen::Matrix3d gyro_cov = ToMatrix<3>(msg.angular_velocity_covariance);
  const Eigen::Matrix3d accel_cov = ToMatrix<3>(msg.linear_acceleration_covariance);
  out->has_covariance = out->has_gyro && out->has_accel && !gyro_cov.isZero(0.0) && !accel_cov.isZero(0.0);
  if (out->has_covariance) {
    out->gyro_cov = R * gyro_cov * R.transpose();
    out->accel_cov = R * accel_cov * R.transpose();
  }
  return ConversionResult::kOk;  // non-finite values are caught and counted by the buffer
}

ConversionResult ConeFrameFromMsg(const cone_tracker::ConeObservations& msg, const std::string& camera_frame,
                                  const std::vector<ConeGeometry>& layout, ConeFrame* out, std::string* why,
                                  int* cones_nan, int* cones_invalid) {
  const std::string topic = kObservationsTopic;
  *cones_nan = *cones_invalid = 0;
  if (msg.header.frame_id != camera_frame) {
    *why = topic + ": header.frame_id is '" + msg.header.frame_id + "', expected '" + camera_frame + "'";
    return ConversionResult::kInvalid;
  }
  if (layout.empty()) {
    *why = topic + ": no cone layout (~layout_file is not set): the observations cannot be used";
    return ConversionResult::kInvalid;
  }
  out->stamp_s = msg.header.stamp.toSec();
  out->K = {msg.fx, msg.fy, msg.cx, msg.cy};
  const bool finite_k =
      std::isfinite(msg.fx) && std::isfinite(msg.fy) && std::isfinite(msg.cx) && std::isfinite(msg.cy);
  if (!finite_k || !(msg.fx > 0.0) || !(msg.fy > 0.0)) {
    std::ostringstream s;
    s << topic << ": intrinsics fx " << msg.fx << ", fy " << msg.fy << ", cx " << msg.cx << ", cy " << msg.cy
      << ": fx and fy must be positive, all finite";
    *why = s.str();
    return finite_k ? ConversionResult::kInvalid : ConversionResult::kNonFinite;
  }
  out->cones.clear();
  out->layout = layout;
  out->width_px = msg.width, out->height_px = msg.height;  // 0 (an older publisher): no negative information
  out->orange_px.clear();
  for (const sensor_msgs::RegionOfInterest& roi : msg.orange)
    if (roi.do_rectify) out->orange_px.push_back(rig_model::FromRoi(roi));  // the model's pixels are undistorted
  static const char* const kPoints[kConePoints] = {"peak", "mid", "base"};
  for (size_t i = 0; i < msg.cones.size(); ++i) {
    const cone_tracker::ConeObservation& m = msg.cones[i];
    const std::string at = topic + ": cones[" + std::to_string(i) + "] (cone_id " + std::to_string(m.cone_id) + ")";
    if (m.cone_id < 0 || m.cone_id >= static_cast<int>(layout.size())) {
      if (why->empty()) *why = at + ": cone_id is not in the layout (" + std::to_string(layout.size()) + " cones)";
      ++*cones_invalid;
      continue;
    }
    ConeObservation o;
    o.cone_id = m.cone_id;
    o.cone = layout[static_cast<size_t>(m.cone_id)];
    const boost::array<double, 2>* px[kConePoints] = {&m.peak_px, &m.mid_px, &m.base_px};
    const boost::array<double, 4>* cov[kConePoints] = {&m.peak_cov_px2, &m.mid_cov_px2, &m.base_cov_px2};
    std::string problem;
    bool non_finite = false;
    for (int k = 0; k < kConePoints && problem.empty(); ++k) {
      o.px[k] = Eigen::Vector2d((*px[k])[0], (*px[k])[1]);
      o.cov_px2[k] = ToMatrix<2>(*cov[k]);
      if (!o.px[k].allFinite() || !o.cov_px2[k].allFinite()) {
        non_finite = true;
        problem = std::string(kPoints[k]) + (o.px[k].allFinite() ? "_cov_px2" : "_px") + " is not finite";
      }
    }
    if (problem.empty()) {
      ConeFrame one;
      one.stamp_s = out->stamp_s;
      one.K = out->K;
      one.cones.push_back(o);
      const std::string err = CheckConeFrame(one);  // the covariances
      if (!err.empty()) problem = err.substr(err.find('.') + 1);
    }
    if (!problem.empty()) {
      if (why->empty()) *why = at + ": " + problem;
      ++*(non_finite ? cones_nan : cones_invalid);
      continue;
    }
    out->cones.push_back(o);
  }
  return ConversionResult::kOk;
}

PoseEkfAdapter::PoseEkfAdapter(const NodeConfig& config) : config_(config), buffer_(config.ekf) {}

void PoseEkfAdapter::Reconfigure(const EkfConfig& ekf) {
  buffer_.SetConfig(ekf);
  config_.ekf = ekf;
}

AddResult PoseEkfAdapter::Count(ConversionResult r) {
  if (r == ConversionResult::kNonFinite) {
    ++nan_rejected_;
    return AddResult::kRejectedNonFinite;
  }
  ++invalid_rejected_;
  return AddResult::kRejectedInvalid;
}

AddResult PoseEkfAdapter::HandleCamera(const geometry_msgs::PoseWithCovarianceStamped& msg, std::string* why) {
  CameraMeasurement m;
  const ConversionResult c = CameraFromMsg(msg, config_.cones_frame, &m, why);
  if (c != ConversionResult::kOk) {
    ++camera_rejected_;
    return Count(c);
  }
  if (QuaternionFarFromUnit(msg.pose.pose.orientation)) {
    ++camera_quaternions_normalized_;
    const auto& q = msg.pose.pose.orientation;
    *why = std::string(kCameraTopic) +
           ": pose.pose.orientation has |q|^2 = " + std::to_string(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z) +
           ", normalised";
  }
  const AddResult r = buffer_.AddCamera(m);
  const std::string topic = kCameraTopic;
  if (r == AddResult::kRejectedNonFinite) *why = topic + ": header.stamp not finite";
  if (r == AddResult::kDroppedLate) *why = topic + ": camera pose older than max_delay_s";
  if (r == AddResult::kGated || r == AddResult::kReinitialized) {
    const BufferCounters& n = buffer_.counters();
    std::ostringstream s;
    s << topic << ": camera pose outside the chi-square gate (" << n.camera_gate_last_rejected_chi2 << " > "
      << buffer_.filter().camera_gate_chi2() << ", " << EkfCore::kCameraGateDof << " dof)";
    if (r == AddResult::kReinitialized) {
      s << "; " << config_.ekf.reinit_after_rejections
        << " in a row (reinit_after_rejections): the filter re-initialised from this pose";
    }
    *why = s.str();
  }
  return r;
}

AddResult PoseEkfAdapter::HandleImu(const sensor_msgs::Imu& msg, const Eigen::Quaterniond& q_camera_imu,
                                    std::string* why, const Eigen::Vector3d& p_imu_in_camera_m) {
  ImuMeasurement m;
  const ConversionResult c = ImuFromMsg(msg, q_camera_imu, &m, why, p_imu_in_camera_m);
  if (c != ConversionResult::kOk) return Count(c);
  const AddResult r = buffer_.AddImu(m);
  if (r == AddResult::kRejectedNonFinite) *why = "IMU sample not finite";
  if (r == AddResult::kDroppedLate) *why = "IMU sample older than max_delay_s";
  return r;
}

AddResult PoseEkfAdapter::HandleObservations(const cone_tracker::ConeObservations& msg, std::string* why) {
  ConeFrame f;
  int nan = 0, invalid = 0;
  const ConversionResult c = ConeFrameFromMsg(msg, config_.camera_frame, config_.layout_cones, &f, why, &nan, &invalid);
  if (c != ConversionResult::kOk) {
    ++observations_rejected_;
    return Count(c);
  }
  cones_refused_nan_ += static_cast<uint64_t>(nan);
  cones_refused_invalid_ += static_cast<uint64_t>(invalid);
  nan_rejected_ += static_cast<uint64_t>(nan);
  invalid_rejected_ += static_cast<uint64_t>(invalid);
  if (f.cones.empty() && nan + invalid > 0) {
    return nan > 0 ? AddResult::kRejectedNonFinite : AddResult::kRejectedInvalid;  // *why names the first
  }
  const AddResult r = buffer_.AddCones(f);
  const std::string topic = kObservationsTopic;
  if (r == AddResult::kRejectedNonFinite) *why = topic + ": header.stamp not finite";
  if (r == AddResult::kDroppedLate) *why = topic + ": observations older than max_delay_s (or the filter's start)";
  if (r == AddResult::kGated) {
    const BufferCounters& n = buffer_.counters();
    const ConeFrameResult& last = buffer_.last_cone_frame();
    std::ostringstream s;
    if (last.ambiguous > 0) {
      s << topic << ": a lone cone that another layout cone fits within cone_ambiguity_margin: not fused";
    } else if (last.too_few > 0) {
      s << topic << ": re-acquiring, " << last.too_few << " cone(s) passed, fewer than reacquire_min_cones: not fused";
    } else {
      s << topic << ": no cone of the frame passed the chi-square gates (largest per-cone statistic "
        << n.cone_last_rejected_chi2 << ", threshold " << buffer_.filter().cone_gate_chi2() << ", " << kConeDof
        << " dof)";
    }
    if (buffer_.ReacquireDue()) s << "; the next camera pose re-initialises the filter";
    *why = s.str();
  }
  return r;
}

bool PoseEkfAdapter::MakeOutputs(AdapterOutputs* out) const { return FillOutputs(buffer_.filter(), out); }

bool PoseEkfAdapter::MakePredictedOutputs(double stamp_s, AdapterOutputs* out) const {
  EkfCore copy = buffer_.filter();
  copy.Predict(stamp_s);
  return FillOutputs(copy, out);
}

bool PoseEkfAdapter::FillOutputs(const EkfCore& filter, AdapterOutputs* out) const {
  if (!filter.initialized()) return false;
  const pose_math::PoseWithCovariance T = filter.Pose();
  const pose_math::Quat q = T.pose.q.normalized();
  ros::Time stamp;
  stamp.fromSec(filter.state().stamp_s);

  auto& pose = out->pose;
  pose.header.stamp = stamp;
  pose.header.frame_id = config_.cones_frame;
  const pose_math::Pose T_unit{q, T.pose.t};  // the published pose: unit quaternion
  pose.pose = rig_model::ToPoseWithCovarianceMsg(pose_math::PoseWithCovariance{T_unit, T.cov});

  // Odometry: twist in the child (camera) frame, as nav_msgs/Odometry specifies.
  auto& odom = out->odometry;
  odom.header = pose.header;
  odom.child_frame_id = config_.camera_frame;
  odom.pose = pose.pose;
  const Eigen::Matrix3d R_cones_camera = pose_math::RotationFromQuat(q);
  const Eigen::Vector3d v_camera = R_cones_camera.transpose() * filter.v_cones_m_s();
  const Eigen::Vector3d w_camera = filter.omega_camera_rad_s();
  odom.twist.twist.linear.x = v_camera.x();
  odom.twist.twist.linear.y = v_camera.y();
  odom.twist.twist.linear.z = v_camera.z();
  odom.twist.twist.angular.x = w_camera.x();
  odom.twist.twist.angular.y = w_camera.y();
  odom.twist.twist.angular.z = w_camera.z();
  const StateMatrix& P = filter.state().P;
  Eigen::Matrix<double, 6, 6> twist_cov;
  twist_cov.topLeftCorner<3, 3>() = R_cones_camera.transpose() * P.block<3, 3>(kV, kV) * R_cones_camera;
  twist_cov.topRightCorner<3, 3>() = R_cones_camera.transpose() * P.block<3, 3>(kV, kW);
  twist_cov.bottomLeftCorner<3, 3>() = twist_cov.topRightCorner<3, 3>().transpose();
  twist_cov.bottomRightCorner<3, 3>() = P.block<3, 3>(kW, kW);
  FromMatrix<6>(twist_cov, &odom.twist.covariance);

  auto& tf = out->tf;
  tf.header = pose.header;
  tf.child_frame_id = config_.camera_frame;
  tf.transform = rig_model::ToTransformMsg(T_unit);
  return true;
}

}  // namespace pose_ekf
