// Standalone node: `rosrun imu_driver imu_driver_node` loads the nodelet into
// its own process with the node's name, so ~port etc. are the node's private params.
#include <nodelet/loader.h>
#include <ros/ros.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "imu_driver");
  nodelet::Loader loader;
  const nodelet::M_string remappings(ros::names::getRemappings());
  const nodelet::V_string nodelet_argv;
  if (!loader.load(ros::this_node::getName(), "imu_driver/ImuDriverNodelet", remappings, nodelet_argv)) {
    ROS_FATAL("could not load imu_driver/ImuDriverNodelet");
    return 1;
  }
  ros::spin();
  return 0;
}
