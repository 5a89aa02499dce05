#include "rig_sim/ros/bag_reader.h"

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <cstdint>
#include <fstream>
#include <utility>

namespace rig_sim {
namespace {

// A bag's index sits at its end (the file header's index_pos): a bag cut short (disk full, recorder
// killed, partial copy) has its header pointing past the end of the file. rosbag then reports only
// the failed read ("wanted 4 bytes, read 0 bytes"), so say what it means.
std::string TruncationNote(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::string magic(13, '\0');
  if (!f.read(&magic[0], 13) || magic != "#ROSBAG V2.0\n") return "";
  auto u32 = [&f](uint32_t* v) {
    unsigned char b[4];
    if (!f.read(reinterpret_cast<char*>(b), 4)) return false;
    *v = uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24;
    return true;
  };
  uint32_t header_len = 0;
  if (!u32(&header_len) || header_len > 4096) return "";
  std::string header(header_len, '\0');
  if (!f.read(&header[0], header_len)) return "";
  f.clear();
  f.seekg(0, std::ios::end);
  const uint64_t size = uint64_t(f.tellg());
  for (size_t i = 0; i + 4 <= header.size();) {
    const uint32_t len = uint32_t(uint8_t(header[i])) | uint32_t(uint8_t(header[i + 1])) << 8 |
                         uint32_t(uint8_t(header[i + 2])) << 16 | uint32_t(uint8_t(header[i + 3])) << 24;
    const std::string field = header.substr(i + 4, len);
    i += 4 + len;
    if (field.size() == 10 + 8 && field.compare(0, 10, "index_pos=") == 0) {
      uint64_t index_pos = 0;
      for (int k = 7; k >= 0; --k) index_pos = index_pos << 8 | uint8_t(field[size_t(10 + k)]);
      if (index_pos >= size)
        return "the bag is truncated (its index should start at byte " + std::to_string(index_pos) +
               " but the file has " + std::to_string(size) + " bytes); try `rosbag reindex " + path +
               "` to recover the messages before the cut";
      return "";
    }
  }
  return "";
}

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
    const std::string note = TruncationNote(path);
    if (error) *error = "reading '" + path + "': " + (note.empty() ? e.what() : note + " (rosbag: " + e.what() + ")");
    return false;
  }
}

}  // namespace rig_sim
