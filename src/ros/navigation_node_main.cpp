// The navigation node's main(): builds NavigationNode (ros/navigation_node.h)
// from the node's parameters and spins; a failed start says why and exits 1.
#include <ros/ros.h>

#include <iostream>

#include "endovascular_sim/ros/navigation_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "navigation_node");
  try {
    evsim::NavigationNode node(ros::NodeHandle(), ros::NodeHandle("~"));
    ros::spin();
  } catch (const std::exception& e) {
    // Straight to stderr as well: rosconsole may not be up when the
    // parameters are read, and a failed start must always say why.
    std::cerr << ros::this_node::getName() << ": " << e.what() << std::endl;
    ROS_FATAL_STREAM(e.what());
    return 1;
  }
  return 0;
}
