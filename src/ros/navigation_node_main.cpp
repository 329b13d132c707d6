#include <ros/ros.h>

#include "endovascular_sim/ros/navigation_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "navigation_node");
  try {
    evsim::NavigationNode node(ros::NodeHandle(), ros::NodeHandle("~"));
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL_STREAM(e.what());
    return 1;
  }
  return 0;
}
