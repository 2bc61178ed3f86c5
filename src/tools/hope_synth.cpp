// hope_synth: renders a synthetic scene with an exact answer, as a TUM-style depth/colour pair
// plus the camera pose, so that hope_extract can be tried without any dataset.
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>

#include <opencv2/imgcodecs.hpp>

#include "hope/synthetic/scene.h"

int main(int argc, char** argv) {
  std::string out_dir;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--out" && i + 1 < argc) {
      out_dir = argv[++i];
    } else if (arg == "--help" || arg == "-h") {
      std::cout << "usage: hope_synth --out DIR\n"
                   "Renders the demo room (floor, table, book, cabinet, two stair treads, a ramp,\n"
                   "a ball, a cone, a tube) seen by a 640x480 depth camera with structured-light\n"
                   "noise. Writes DIR/depth.png (16-bit, 5000 per metre), DIR/rgb.png,\n"
                   "DIR/pose.txt (tx ty tz qx qy qz qw) and DIR/truth.txt (the planes to find).\n";
      return 0;
    } else {
      std::cerr << "hope_synth: error: unknown argument '" << arg << "' (see --help)\n";
      return 2;
    }
  }
  if (out_dir.empty()) {
    std::cerr << "hope_synth: error: --out DIR is required\n";
    return 2;
  }
  try {
    using namespace hope::synthetic;
    const Scene scene = demoRoom();
    const Camera camera = demoCamera();
    const RenderedFrame frame = scene.render(camera);
    cv::Mat depth16(frame.depth.size(), CV_16UC1);
    frame.depth.convertTo(depth16, CV_16UC1, 5000.0);  // TUM scale; saturates beyond 13 m
    if (!cv::imwrite(out_dir + "/depth.png", depth16) ||
        !cv::imwrite(out_dir + "/rgb.png", frame.bgr)) {
      throw std::runtime_error("cannot write images into '" + out_dir + "' (does it exist?)");
    }
    const Eigen::Quaterniond q(camera.pose.linear());
    const Eigen::Vector3d t = camera.pose.translation();
    std::ofstream pose(out_dir + "/pose.txt");
    pose.precision(9);
    pose << t.x() << " " << t.y() << " " << t.z() << " " << q.x() << " " << q.y() << " " << q.z()
         << " " << q.w() << "\n";
    std::ofstream truth(out_dir + "/truth.txt");
    truth << "# label height_m surface\n0 0.00 floor\n1 0.75 table top\n2 0.45 cabinet top\n"
             "3 0.17 first stair tread\n4 0.34 second stair tread\n5 0.80 book on the table\n"
             "# not planes: a ramp sloped 0.5 rad, a ball, a cone, a lying tube\n";
    if (!pose || !truth) throw std::runtime_error("cannot write text files into '" + out_dir + "'");
    std::cout << "hope_synth: wrote " << out_dir << "/{depth.png,rgb.png,pose.txt,truth.txt}\n";
  } catch (const std::exception& e) {
    std::cerr << "hope_synth: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
