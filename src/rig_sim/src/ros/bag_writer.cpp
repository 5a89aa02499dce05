#include "rig_sim/ros/bag_writer.h"

#include <rosbag/bag.h>

#include "rig_sim/ros/frame_pipeline.h"

namespace rig_sim {
namespace {

// A latched connection's header. rosbag stores the given header as is, so it
// must carry the type, md5sum and definition too, or `rosbag play` refuses it.
template <typename M>
boost::shared_ptr<ros::M_string> LatchedHeader() {
  auto h = boost::make_shared<ros::M_string>();
  (*h)["type"] = ros::message_traits::datatype<M>();
  (*h)["md5sum"] = ros::message_traits::md5sum<M>();
  (*h)["message_definition"] = ros::message_traits::definition<M>();
  (*h)["callerid"] = "/rig_sim";
  (*h)["latching"] = "1";
  return h;
}

}  // namespace
bool WriteScenarioBag(const Scenario& scenario, const BagOptions& opt, const std::string& path, BagStats* stats,
                      std::string* error) {
  try {
    rosbag::Bag bag;
    bag.open(path, rosbag::bagmode::Write);
    if (opt.compression == "lz4")
      bag.setCompression(rosbag::compression::LZ4);
    else if (opt.compression == "bz2")
      bag.setCompression(rosbag::compression::BZ2);
    else if (opt.compression != "none")
      throw std::invalid_argument("compression must be none, lz4 or bz2");
    SimStream stream(scenario, opt.stream);
    const ros::Time t0 = StampAt(opt.start_time_s, 0.0);
    bag.write("/tf_static", t0, MakeStaticTruth(scenario.imu, t0, opt.frames), LatchedHeader<tf2_msgs::TFMessage>());
    bag.write(opt.topics.markers, t0, MakeConeMarkers(scenario.scene, t0, opt.frames.cones),
              LatchedHeader<visualization_msgs::MarkerArray>());
    BagStats local;
    FramePipeline frames(stream, opt.start_time_s, opt.frames.camera, FrameCount(scenario));
    const uint64_t truth_per_imu =
        std::max<uint64_t>(1, static_cast<uint64_t>(std::llround(opt.stream.truth_rate_hz / scenario.imu.rate_hz)));
    SimEvent ev;
    while (stream.Next(&ev)) {
      const ros::Time stamp = StampAt(opt.start_time_s, ev.stamp_s);
      const ros::Time deliver = StampAt(opt.start_time_s, ev.deliver_s);
      switch (ev.kind) {
        case EventKind::kImu: {
          const ros::Time imu_stamp = ImuMessageStamp(stamp, scenario.imu);
          bag.write(opt.topics.imu, deliver, MakeImu(ev.imu, scenario.imu, imu_stamp, opt.frames.imu));
          bag.write(opt.topics.imu_bias, deliver, MakeImuBias(ev.imu, imu_stamp, opt.frames.imu));
          ++local.imu;
          break;
        }
        case EventKind::kTruth:
          bag.write(opt.topics.truth, deliver, MakeTruthPose(ev.pose, stamp, opt.frames.cones));
          if (opt.truth_tf && ev.index % truth_per_imu == 0) {
            tf2_msgs::TFMessage tf;
            tf.transforms.push_back(MakeTruthTransform(ev.pose, stamp, opt.frames));
            bag.write("/tf", deliver, tf);
          }
          ++local.truth;
          break;
        case EventKind::kImage: {
          const sensor_msgs::ImagePtr img = frames.Pop();
          if (img->header.stamp != stamp) throw std::logic_error("frame pipeline out of order");
          bag.write(opt.topics.image, deliver, img);
          bag.write(opt.topics.camera_info, deliver, MakeCameraInfo(scenario.camera, stamp, opt.frames.camera));
          ++local.images;
          break;
        }
      }
    }
    local.render_s = frames.render_s();
    bag.close();
    if (stats) *stats = local;
    return true;
  } catch (const std::exception& e) {
    if (error) *error = std::string("writing '") + path + "': " + e.what();
    return false;
  }
}

}  // namespace rig_sim
