#include "hope/synthetic/paper_scenes.h"

#include <algorithm>
#include <stdexcept>

namespace hope {
namespace synthetic {

using V = Eigen::Vector3d;

Scene patternObjectScene(double tilt, TiltAxis axis) {
  Scene scene;
  const V centre(kPatternHalfWidth, kPatternHalfWidth, 0.05);  // of the base, object coordinates
  const V tilt_axis = axis == TiltAxis::kPlusX ? V::UnitX() : V(-V::UnitY());
  // Object → world: move the base centre to the origin, tilt about it, lift it back to z=0.05.
  const Eigen::Isometry3d pose = Eigen::Translation3d(0, 0, 0.05) *
                                 Eigen::AngleAxisd(tilt, tilt_axis) * Eigen::Translation3d(-centre);
  addPatternObject(scene, pose, 0);
  return scene;
}

double patternFaceHeight(int label) {
  if (label < 0 || label >= kPatternObjectFaces) {
    throw std::invalid_argument("the pattern object has faces 0 to 25");
  }
  if (label == 0) return 0.10;
  const int i = (label - 1) / 5, j = (label - 1) % 5;
  return 0.12 + 0.02 * std::min(i, j);
}

Camera patternObjectCamera() { return Camera::lookingAt(V(0.0, -0.6, 1.2), V(0.0, 0.0, 0.1)); }

std::vector<NamedScene> falsePositivePrimitives(double slope) {
  std::vector<NamedScene> scenes;
  {
    Scene s;
    const Eigen::Matrix3d tilt = Eigen::AngleAxisd(slope, V::UnitY()).toRotationMatrix();
    s.add<Box>(V(-0.4, -0.4, 0.30), V(0.4, 0.4, 0.32), kNoPlane, tilt);
    scenes.push_back(
        {"(a) plane sloped " + std::to_string(slope).substr(0, 4) + " rad", std::move(s)});
  }
  {
    Scene s;
    s.add<Cone>(V(0, 0, 0.6), 0.4, 0.5);
    scenes.push_back({"(b) cone", std::move(s)});
  }
  {
    Scene s;
    s.add<Cylinder>(V(-0.45, 0, 0.3), V(0.45, 0, 0.3), 0.15);
    scenes.push_back({"(c) lying tube", std::move(s)});
  }
  {
    Scene s;
    s.add<Sphere>(V(0, 0, 0.3), 0.4);
    scenes.push_back({"(d) sphere", std::move(s)});
  }
  return scenes;
}

}  // namespace synthetic
}  // namespace hope
