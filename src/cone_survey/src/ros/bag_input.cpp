#include "cone_survey/ros/bag_input.h"

#include <algorithm>
#include <exception>
#include <set>

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <tf2_msgs/TFMessage.h>

#include "rig_model/camera_imu.h"
#include "rig_model/ros/conversions.h"
#include "rig_model/strict_yaml.h"

namespace cone_survey {
namespace {

std::string Trim(const std::string& topic) { return !topic.empty() && topic[0] == '/' ? topic.substr(1) : topic; }

// camera -> imu in /tf_static, exactly between the camera_info's frame and the IMU messages' frame (as
// pose_ekf's replay looks it up): a simulator's truth edge (camera_optical_truth -> imu_truth) is never
// taken for the rig's calibration.
bool FindCameraImu(const rosbag::Bag& bag, const std::string& camera_frame, const std::string& imu_frame,
                   Eigen::Matrix3d* R, std::string* used) {
  rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{"/tf_static", "tf_static"}));
  for (const rosbag::MessageInstance& m : view) {
    const tf2_msgs::TFMessage::ConstPtr tf = m.instantiate<tf2_msgs::TFMessage>();
    if (!tf) continue;
    for (const geometry_msgs::TransformStamped& t : tf->transforms) {
      if (t.header.frame_id != camera_frame || t.child_frame_id != imu_frame) continue;
      rig_model::CameraImuExtrinsics e;
      std::string why;
      if (!rig_model::FromTransformStamped(t, &e, &why)) continue;
      *R = e.R_camera_imu();
      *used = "/tf_static " + t.header.frame_id + " -> " + t.child_frame_id;
      return true;
    }
  }
  return false;
}

}  // namespace

bool ReadSurveyBag(const std::string& path, const BagInputOptions& o, SurveyInput* out, std::string* camera_imu_source,
                   std::string* error) {
  try {
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    const std::string image = Trim(o.image_topic), info = Trim(o.info_topic), imu = Trim(o.imu_topic);
    bool have_info = false;
    std::string camera_frame;
    std::set<std::string> topics;
    rosbag::View all(bag);
    for (const rosbag::ConnectionInfo* c : all.getConnections()) topics.insert(Trim(c->topic));
    auto listing = [&]() {
      std::string s;
      for (const std::string& t : topics) s += (s.empty() ? "" : ", ") + t;
      return " (the bag has: " + (s.empty() ? std::string("nothing") : s) + ")";
    };
    for (const auto& [topic, what] :
         std::vector<std::pair<std::string, std::string>>{{info, "camera_info: the survey needs the calibrated camera"},
                                                          {imu, "IMU: the survey needs the gyro and the accelerometer"},
                                                          {image, "images"}}) {
      if (!topics.count(topic)) {
        *error = path + ": no " + topic + " " + what + listing();
        return false;
      }
    }
    rosbag::View info_view(bag, rosbag::TopicQuery(std::vector<std::string>{info, "/" + info}));
    for (const rosbag::MessageInstance& m : info_view) {
      const sensor_msgs::CameraInfo::ConstPtr msg = m.instantiate<sensor_msgs::CameraInfo>();
      std::string why;
      if (msg && rig_model::FromCameraInfo(*msg, &out->camera, &why)) {
        have_info = true;
        camera_frame = msg->header.frame_id;
        break;
      }
      if (msg) {
        *error = path + ": " + info + ": " + why;
        return false;
      }
    }
    if (!have_info) {
      *error = path + ": no readable camera_info on " + info;
      return false;
    }
    std::string imu_frame;
    rosbag::View imu_view(bag, rosbag::TopicQuery(std::vector<std::string>{imu, "/" + imu}));
    for (const rosbag::MessageInstance& m : imu_view) {
      const sensor_msgs::Imu::ConstPtr msg = m.instantiate<sensor_msgs::Imu>();
      if (!msg) continue;
      if (imu_frame.empty()) imu_frame = msg->header.frame_id;
      ImuReading r;
      r.stamp_s = msg->header.stamp.toSec();
      r.gyro_rad_s = Eigen::Vector3d(msg->angular_velocity.x, msg->angular_velocity.y, msg->angular_velocity.z);
      r.accel_m_s2 =
          Eigen::Vector3d(msg->linear_acceleration.x, msg->linear_acceleration.y, msg->linear_acceleration.z);
      if (r.gyro_rad_s.allFinite() && r.accel_m_s2.allFinite()) out->imu.push_back(r);
    }
    std::sort(out->imu.begin(), out->imu.end(),
              [](const ImuReading& a, const ImuReading& b) { return a.stamp_s < b.stamp_s; });
    std::string used;
    if (!o.camera_imu_file.empty()) {
      out->R_camera_imu = rig_model::LoadCameraImuFile(o.camera_imu_file).R_camera_imu();
      used = o.camera_imu_file;
    } else if (!FindCameraImu(bag, camera_frame, imu_frame, &out->R_camera_imu, &used)) {
      *error = path + ": no camera-IMU rotation: the bag has no /tf_static " + camera_frame + " -> " +
               (imu_frame.empty() ? std::string("imu") : imu_frame) +
               "; give --camera-imu FILE (calibrate_camera_imu's YAML)";
      return false;
    }
    *camera_imu_source = used;
    cone_tracker::Segmenter segmenter(o.segmenter);
    rosbag::View image_view(bag, rosbag::TopicQuery(std::vector<std::string>{image, "/" + image}));
    for (const rosbag::MessageInstance& m : image_view) {
      const sensor_msgs::Image::ConstPtr msg = m.instantiate<sensor_msgs::Image>();
      if (!msg) continue;
      if (static_cast<int>(msg->width) != out->camera.width_px ||
          static_cast<int>(msg->height) != out->camera.height_px) {
        *error = path + ": " + image + " is " + std::to_string(msg->width) + "x" + std::to_string(msg->height) +
                 ", camera_info says " + std::to_string(out->camera.width_px) + "x" +
                 std::to_string(out->camera.height_px);
        return false;
      }
      cone_tracker::ImageView view{msg->data.data(), static_cast<int>(msg->width), static_cast<int>(msg->height),
                                   static_cast<int>(msg->step), msg->encoding};
      const cone_tracker::SegmentationResult seg = segmenter.Process(view, out->camera);
      if (!seg.ok) {
        *error = path + ": " + image + ": " + seg.error;
        return false;
      }
      SurveyFrame f;
      f.stamp_s = msg->header.stamp.toSec();
      for (const cone_tracker::ConeDetection& d : seg.cones) f.cones.push_back({d.peak_undist_px, d.base_undist_px});
      out->frames.push_back(f);
    }
    std::sort(out->frames.begin(), out->frames.end(),
              [](const SurveyFrame& a, const SurveyFrame& b) { return a.stamp_s < b.stamp_s; });
    if (out->imu.empty() || out->frames.empty()) {
      *error =
          path + ": " + (out->imu.empty() ? "no readable IMU messages on " + imu : "no readable images on " + image);
      return false;
    }
    return true;
  } catch (const rosbag::BagException& e) {
    *error = path + ": cannot read the bag: " + e.what();
  } catch (const std::exception& e) {
    *error = e.what();
  }
  return false;
}

}  // namespace cone_survey
