// Standalone wrapper: loads the PoseEkfNodelet into this process. On the rig,
// prefer the nodelet in the shared manager (launch/pose_ekf.launch).
#include <nodelet/loader.h>
#include <ros/ros.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "pose_ekf");
  nodelet::Loader loader;
  nodelet::M_string remappings(ros::names::getRemappings());
  nodelet::V_string args(argv + 1, argv + argc);
  if (!loader.load(ros::this_node::getName(), "pose_ekf/PoseEkfNodelet", remappings, args)) {
    ROS_FATAL("pose_ekf: could not load pose_ekf/PoseEkfNodelet");
    return 1;
  }
  ros::spin();
  return 0;
}
