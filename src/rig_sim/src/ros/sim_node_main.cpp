// rosrun rig_sim sim_node: publishes a simulated rig live (see sim_publisher.h).
#include "rig_sim/ros/sim_publisher.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "rig_sim");
  ros::NodeHandle nh, pnh("~");
  rig_sim::SimPublisherConfig config;
  std::string err;
  if (!rig_sim::LoadSimPublisherConfig(pnh, &config, &err)) {
    ROS_FATAL("rig_sim: %s", err.c_str());
    return 1;
  }
  try {
    rig_sim::SimPublisher publisher(nh, pnh, config);
    publisher.Run();
  } catch (const std::exception& e) {
    ROS_FATAL("rig_sim: %s", e.what());
    return 1;
  }
  return 0;
}
