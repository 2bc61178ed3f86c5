// The scenes of the paper's evaluation (§3.3, Fig 3, Fig 9), with exact ground truth.
#pragma once

#include <string>
#include <vector>

#include "hope/synthetic/scene.h"
#include "hope/synthetic/sequences.h"

namespace hope {
namespace synthetic {

// Axis of the tilt experiment (Fig 9): about +x or about −y, through the object's centre.
enum class TiltAxis { kPlusX, kMinusY };

// The pattern object alone, its base centred on the origin (base top at z = 0.10), tilted by
// `tilt` radians about `axis`. Face labels 0 (the base) to 25, as addPatternObject.
Scene patternObjectScene(double tilt = 0.0, TiltAxis axis = TiltAxis::kPlusX);
// Height of face `label` of the untilted object, metres.
double patternFaceHeight(int label);
// The object's xy extent: [-0.48, 0.48]².
constexpr double kPatternHalfWidth = 0.48;
// A camera 1.2 m above the floor, 0.6 m back from the object's centre, looking at it.
Camera patternObjectCamera();

struct NamedScene {
  std::string name;
  Scene scene;
};
// The false positives of Fig 3, each alone, none of them a horizontal plane: (a) a plane
// sloped by `slope` radians, (b) a cone, (c) the top of a lying tube, (d) a sphere's cap.
// All lie within [-0.5, 0.5]² in xy.
std::vector<NamedScene> falsePositivePrimitives(double slope);

}  // namespace synthetic
}  // namespace hope
