#include "rig_sim/ros/bag_reader.h"

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <utility>

namespace rig_sim {
namespace {

std::string Strip(const std::string& t) { return !t.empty() && t[0] == '/' ? t.substr(1) : t; }

template <typename R, typename M>
void FillStamps(const M& msg, const rosbag::MessageInstance& m, R* r) {
  r->stamp_s = msg.header.stamp.toSec();
  r->receive_s = m.getTime().toSec();
}

}  // namespace

bool ReadBagContents(const std::string& path, const TopicNames& topics, BagContents* out, std::string* error) {
  try {
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    rosbag::View view(bag);
    BagContents c;
    c.imu_topic = topics.imu;
    c.image_topic = topics.image;
    c.info_topic = topics.camera_info;
    c.truth_topic = topics.truth;
    const std::string imu = Strip(topics.imu), image = Strip(topics.image), info = Strip(topics.camera_info),
                      truth = Strip(topics.truth);
    for (const rosbag::MessageInstance& m : view) {
      const std::string topic = Strip(m.getTopic());
      if (topic == imu) {
        const auto msg = m.instantiate<sensor_msgs::Imu>();
        if (!msg) continue;
        ImuRecord r;
        FillStamps(*msg, m, &r);
        r.gyro_rad_s = Eigen::Vector3d(msg->angular_velocity.x, msg->angular_velocity.y, msg->angular_velocity.z);
        r.accel_m_s2 =
            Eigen::Vector3d(msg->linear_acceleration.x, msg->linear_acceleration.y, msg->linear_acceleration.z);
        r.orientation_covariance0 = msg->orientation_covariance[0];
        r.frame = msg->header.frame_id;
        c.imu.push_back(r);
      } else if (topic == image) {
        const auto msg = m.instantiate<sensor_msgs::Image>();
        if (!msg) continue;
        ImageRecord r;
        FillStamps(*msg, m, &r);
        r.width = msg->width;
        r.height = msg->height;
        r.step = msg->step;
        r.encoding = msg->encoding;
        r.frame = msg->header.frame_id;
        r.data_size = msg->data.size();
        c.images.push_back(r);
      } else if (topic == info) {
        const auto msg = m.instantiate<sensor_msgs::CameraInfo>();
        if (!msg) continue;
        InfoRecord r;
        FillStamps(*msg, m, &r);
        r.width = msg->width;
        r.height = msg->height;
        r.frame = msg->header.frame_id;
        r.distortion_model = msg->distortion_model;
        r.d_size = msg->D.size();
        r.fx = msg->K[0];
        r.fy = msg->K[4];
        c.infos.push_back(r);
      } else if (topic == truth) {
        const auto msg = m.instantiate<geometry_msgs::PoseStamped>();
        if (!msg) continue;
        TruthRecord r;
        FillStamps(*msg, m, &r);
        r.p = Eigen::Vector3d(msg->pose.position.x, msg->pose.position.y, msg->pose.position.z);
        r.q = Eigen::Quaterniond(msg->pose.orientation.w, msg->pose.orientation.x, msg->pose.orientation.y,
                                 msg->pose.orientation.z);
        c.truth.push_back(r);
      }
    }
    *out = std::move(c);
    return true;
  } catch (const std::exception& e) {
    if (error) *error = "reading '" + path + "': " + e.what();
    return false;
  }
}

}  // namespace rig_sim
