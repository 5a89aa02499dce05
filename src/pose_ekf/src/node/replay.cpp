#include "pose_ekf/node/replay.h"

#include <geometry_msgs/PoseStamped.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>
#include <tf2_msgs/TFMessage.h>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <ostream>
#include <set>
#include <stdexcept>

#include "pose_ekf/node/pose_ekf_adapter.h"
#include "pose_ekf/node/truth_residuals.h"

namespace pose_ekf {
namespace {

// Topic names in bags may or may not carry the leading slash.
bool SameTopic(const std::string& a, const std::string& b) {
  auto strip = [](const std::string& s) { return !s.empty() && s[0] == '/' ? s.substr(1) : s; };
  return strip(a) == strip(b);
}

// One line of ReplayOptions::covariance_path.
void WriteCovarianceLine(double stamp_s, const boost::array<double, 36>& cov, const EkfCore& filter,
                         std::ostream& out) {
  out << std::fixed << std::setprecision(9) << stamp_s << std::scientific << std::setprecision(6);
  for (int k = 0; k < 6; ++k) out << ' ' << cov[k * 7];
  const StateMatrix& P = filter.state().P;
  auto write = [&](const Eigen::Vector3d& bias, int i) {
    out << ' ' << bias.x() << ' ' << bias.y() << ' ' << bias.z();
    for (int k = 0; k < 3; ++k) out << ' ' << std::sqrt(P(i + k, i + k));
  };
  if (filter.config().estimate_gyro_bias) write(filter.gyro_bias_rad_s(), kB);
  if (filter.config().estimate_accel_bias) write(filter.accel_bias_m_s2(), AccelBiasIndex(filter.config()));
  out << '\n';
}

// Why a bag with neither camera poses nor IMU samples on the given topics gives no trajectory, and which of its
// topics carry them (another robot's bag names its IMU topic its own way).
std::string NothingToReplay(const rosbag::Bag& bag, const ReplayOptions& options) {
  std::set<std::string> imu, camera;
  for (const rosbag::ConnectionInfo* c : rosbag::View(bag).getConnections()) {
    if (c->datatype == "sensor_msgs/Imu") imu.insert(c->topic);
    if (c->datatype == "geometry_msgs/PoseWithCovarianceStamped") camera.insert(c->topic);
  }
  auto list = [](const std::set<std::string>& topics) {
    std::string s;
    for (const std::string& t : topics) s += (s.empty() ? "" : ", ") + t;
    return s.empty() ? std::string("none") : s;
  };
  return options.bag_path + ": no sensor_msgs/Imu on '" + options.imu_topic + "' and no camera poses on '" +
         options.camera_topic + "'; the bag's sensor_msgs/Imu topics: " + list(imu) +
         " (--imu-topic), its geometry_msgs/PoseWithCovarianceStamped topics: " + list(camera) + " (--camera-topic)";
}

}  // namespace

ReplaySummary RunReplay(const ReplayOptions& options, std::ostream& log) {
  rosbag::Bag bag;
  try {
    bag.open(options.bag_path, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    throw std::runtime_error("cannot open bag " + options.bag_path + ": " + e.what());
  }
  std::ofstream out(options.output_path);
  if (!out) throw std::runtime_error("cannot write " + options.output_path);
  out << std::fixed << std::setprecision(9);

  ReplaySummary summary;
  NodeConfig config = options.config;
  tf2::BufferCore tf(ros::Duration(1e6));
  const bool residuals = !options.truth_residuals_path.empty();
  const bool exact_peak = options.truth_points == "peak" || options.truth_points == "both";
  const bool exact_base = options.truth_points == "base" || options.truth_points == "both";
  if (!options.truth_points.empty() && !exact_peak && !exact_base)
    throw std::runtime_error("truth_points is '" + options.truth_points + "': must be peak, base or both");
  TruthResiduals truth;
  size_t imu_on_topic = 0;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    if (SameTopic(m.getTopic(), options.camera_topic)) ++summary.camera_messages;
    if (SameTopic(m.getTopic(), options.imu_topic)) ++imu_on_topic;
    if ((residuals || exact_peak || exact_base) && SameTopic(m.getTopic(), options.truth_topic)) {
      if (auto msg = m.instantiate<geometry_msgs::PoseStamped>()) {
        const auto& p = msg->pose.position;
        const auto& q = msg->pose.orientation;
        truth.AddTruth(msg->header.stamp.toSec(), {p.x, p.y, p.z}, Eigen::Quaterniond(q.w, q.x, q.y, q.z));
      }
    }
    if (m.getTopic() == "/tf_static" || m.getTopic() == "tf_static") {
      if (auto msg = m.instantiate<tf2_msgs::TFMessage>()) {
        for (const auto& t : msg->transforms) tf.setTransform(t, "bag", true);
      }
    }
  }
  if (summary.camera_messages == 0 && imu_on_topic == 0) throw std::runtime_error(NothingToReplay(bag, options));
  if (summary.camera_messages == 0) {
    // IMU only: orientation-only mode (gyro + gravity), the IMU frame is the body frame.
    summary.orientation_only = true;
    config.ekf.use_camera = false;
    config.ekf.init_from_gravity = true;
    config.ekf.accel_mode = AccelMode::kOrientation;
  }
  PoseEkfAdapter adapter(config);
  std::map<std::string, Eigen::Quaterniond> rotations;
  std::map<std::string, Eigen::Vector3d> lever_arms;  // the same tf's translation
  auto imu_rotation = [&](const std::string& frame) {
    auto it = rotations.find(frame);
    if (it != rotations.end()) return it->second;
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    lever_arms[frame] = Eigen::Vector3d::Zero();
    summary.imu_rotation_source = "identity";
    if (!summary.orientation_only && frame != config.camera_frame) {
      try {
        const auto tr = tf.lookupTransform(config.camera_frame, frame, ros::Time(0)).transform;
        const auto& r = tr.rotation;
        q = Eigen::Quaterniond(r.w, r.x, r.y, r.z).normalized();
        const Eigen::Vector3d p(tr.translation.x, tr.translation.y, tr.translation.z);
        const std::string refused = CheckLeverArm(p, config.camera_frame, frame);
        if (!refused.empty()) throw std::runtime_error(options.bag_path + ": " + refused);
        lever_arms[frame] = p;
        summary.imu_rotation_source = "/tf_static " + config.camera_frame + " <- " + frame;
      } catch (const tf2::TransformException& e) {
        log << "ekf_replay: no /tf_static " << config.camera_frame << " <- " << frame
            << " in the bag; using identity: " << e.what() << "\n";
      }
    }
    return rotations[frame] = q;
  };

  std::ofstream cone_log;
  if (!options.cone_log_path.empty()) {
    cone_log.open(options.cone_log_path);
    if (!cone_log) throw std::runtime_error("cannot write " + options.cone_log_path);
    cone_log << std::fixed << std::setprecision(6)
             << "# stamp_s cones ids result fused gated joint_dropped ambiguous too_few own_chi2 rival_chi2 rival_id "
                "sigma_p_m nis own_missed rival_missed own_unexplained rival_unexplained\n";
  }
  std::ofstream covariance;
  if (!options.covariance_path.empty()) {
    covariance.open(options.covariance_path);
    if (!covariance) throw std::runtime_error("cannot write " + options.covariance_path);
    const EkfConfig& ekf = adapter.buffer().filter().config();  // the columns WriteCovarianceLine writes
    covariance << "# stamp_s var_x var_y var_z var_rx var_ry var_rz"
               << (ekf.estimate_gyro_bias ? " gyro_bias_xyz_rad_s gyro_bias_sigma_xyz_rad_s" : "")
               << (ekf.estimate_accel_bias ? " accel_bias_xyz_m_s2 accel_bias_sigma_xyz_m_s2" : "") << "\n";
  }
  std::ofstream residual_lines;
  if (residuals) {
    residual_lines.open(options.truth_residuals_path);
    if (!residual_lines) throw std::runtime_error("cannot write " + options.truth_residuals_path);
    residual_lines << TruthResiduals::Header() << "\n";
  }
  double last_written = -1.0;
  auto write = [&] {
    AdapterOutputs o;
    if (!adapter.MakeOutputs(&o)) return;
    const double t = o.pose.header.stamp.toSec();
    if (t <= last_written) return;
    last_written = t;
    const auto& p = o.pose.pose.pose;
    out << t << ' ' << p.position.x << ' ' << p.position.y << ' ' << p.position.z << ' ' << p.orientation.x << ' '
        << p.orientation.y << ' ' << p.orientation.z << ' ' << p.orientation.w << '\n';
    ++summary.poses_written;
    if (covariance.is_open())
      WriteCovarianceLine(o.pose.header.stamp.toSec(), o.pose.pose.covariance, adapter.buffer().filter(), covariance);
  };
  std::string why;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    if (SameTopic(m.getTopic(), options.camera_topic)) {
      if (auto msg = m.instantiate<geometry_msgs::PoseWithCovarianceStamped>()) {
        adapter.HandleCamera(*msg, &why);
        if (summary.imu_messages == 0) write();  // camera-only bag: one pose per frame
      }
    } else if (SameTopic(m.getTopic(), options.imu_topic)) {
      if (auto msg = m.instantiate<sensor_msgs::Imu>()) {
        ++summary.imu_messages;
        const Eigen::Quaterniond q = imu_rotation(msg->header.frame_id);
        adapter.HandleImu(*msg, q, &why, lever_arms[msg->header.frame_id]);
        write();
      }
    } else if (SameTopic(m.getTopic(), options.observations_topic)) {
      if (auto msg = m.instantiate<cone_tracker::ConeObservations>()) {
        ++summary.observation_messages;
        ConeFrame frame;
        int nan = 0, invalid = 0;
        std::string ignored;
        const bool converted = (residuals || exact_peak || exact_base) &&
                               ConeFrameFromMsg(*msg, config.camera_frame, config.layout_cones, &frame, &ignored, &nan,
                                                &invalid) == ConversionResult::kOk;
        std::vector<ConeVector> exact;  // the frame's truth pixels, projected once for both options
        const bool have_truth = converted && (residuals ? truth.AddFrame(frame, &residual_lines, &exact)
                                                        : truth.TruthPixels(frame, &exact));
        if (have_truth && (exact_peak || exact_base)) {
          for (size_t i = 0; i < frame.cones.size(); ++i) {
            if (!exact[i].allFinite()) continue;
            for (cone_tracker::ConeObservation& c : msg->cones) {
              if (c.cone_id != frame.cones[i].cone_id) continue;
              if (exact_peak) c.peak_px = {exact[i][0], exact[i][1]};
              if (exact_base) c.base_px = {exact[i][2], exact[i][3]};
              c.mid_px = {0.5 * (c.peak_px[0] + c.base_px[0]), 0.5 * (c.peak_px[1] + c.base_px[1])};
            }
          }
        }
        const AddResult r = adapter.HandleObservations(*msg, &why);  // with camera_update: cones and a layout_file
        if (cone_log.is_open()) {
          const bool ran = r == AddResult::kApplied || r == AddResult::kReplayed || r == AddResult::kGated;
          const ConeFrameResult none, &f = ran ? adapter.buffer().last_cone_frame() : none;
          cone_log << msg->header.stamp.toSec() << ' ' << msg->cones.size() << ' ';
          for (size_t i = 0; i < msg->cones.size(); ++i) cone_log << (i ? "," : "") << msg->cones[i].cone_id;
          if (msg->cones.empty()) cone_log << '-';
          cone_log << ' ' << static_cast<int>(r) << ' ' << f.fused << ' ' << f.gated << ' ' << f.joint_dropped << ' '
                   << f.ambiguous << ' ' << f.too_few << ' ' << f.ambiguity_own_chi2 << ' ' << f.ambiguity_rival_chi2
                   << ' ' << f.ambiguity_rival_id << ' ' << adapter.buffer().PositionSigmaM() << ' ' << f.nis << ' '
                   << f.ambiguity_own_missed << ' ' << f.ambiguity_rival_missed << ' ' << f.ambiguity_own_unexplained
                   << ' ' << f.ambiguity_rival_unexplained << '\n';
        }
      }
    }
  }
  const BufferCounters& c = adapter.buffer().counters();
  log << "ekf_replay: " << summary.camera_messages << " camera poses, " << summary.imu_messages << " IMU samples, "
      << summary.poses_written << " poses written" << (summary.orientation_only ? " (orientation-only)" : "")
      << "; dropped late " << c.dropped_late << " (cone frames " << c.cone_frames_dropped_late << ")"
      << ", NaN rejected " << c.nan_rejected + adapter.nan_rejected() << ", invalid " << adapter.invalid_rejected()
      << ", resets " << c.resets << "; camera poses rejected (chi2 gate) " << c.camera_gated << " (threshold "
      << adapter.buffer().filter().camera_gate_chi2() << ", last rejected " << c.camera_gate_last_rejected_chi2
      << "), re-initialisations " << c.reinits << ", camera NIS mean "
      << (c.camera_nis_count ? c.camera_nis_sum / c.camera_nis_count : 0.0) << "; " << summary.observation_messages
      << " cone observation messages: cones fused " << c.cones_applied << ", gated " << c.cones_gated
      << ", joint-dropped " << c.cones_joint_dropped << ", refused " << adapter.observations_rejected() << " + "
      << adapter.cones_refused_nan() + adapter.cones_refused_invalid() << ", poses not fused (their cones were) "
      << c.poses_superseded << ", frames repeating the last fused view " << c.cone_frames_repeated << "\n";
  if (residuals) log << "ekf_replay: " << truth.Summary() << "\n";
  summary.camera_gated = c.camera_gated;
  summary.reinits = c.reinits;
  return summary;
}

}  // namespace pose_ekf
