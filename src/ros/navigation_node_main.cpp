#include <ros/ros.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "navigation_node");
  ros::NodeHandle nh;
  return 0;
}
