// hope_node: the hope nodelet as a standalone node, for launch files without a manager.
#include <nodelet/loader.h>
#include <ros/ros.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "hope");
  nodelet::Loader loader;
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (!loader.load(ros::this_node::getName(), "hope/PlaneExtractorNodelet",
                   ros::names::getRemappings(), args)) {
    ROS_FATAL("hope_node: could not load hope/PlaneExtractorNodelet (is the package built?)");
    return 1;
  }
  ros::spin();
  return 0;
}
