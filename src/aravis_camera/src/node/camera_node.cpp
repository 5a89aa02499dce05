// `rosrun aravis_camera camera_node`: the CameraNodelet in a process of its own
// (for use without a manager; the rig's launch files load the nodelet instead).
#include <nodelet/loader.h>
#include <ros/ros.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "camera");
  nodelet::Loader loader(false);
  const nodelet::M_string remappings(ros::names::getRemappings());
  const nodelet::V_string args(argv + 1, argv + argc);
  if (!loader.load(ros::this_node::getName(), "aravis_camera/CameraNodelet", remappings, args)) {
    ROS_FATAL("could not load aravis_camera/CameraNodelet");
    return 1;
  }
  ros::spin();
  return 0;
}
