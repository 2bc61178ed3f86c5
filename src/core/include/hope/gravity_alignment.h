// Gravity alignment (paper §2.2, Eq 1): bring the cloud from the sensor frame F_s into the
// reference frame F_r whose z axis points up.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "hope/orientation.h"
#include "hope/points_view.h"

namespace hope {

// The reference frame's +z (up) in the sensor's frame: Rᵀ·z of a sensor-to-reference transform.
Eigen::Vector3d upInSensor(const Eigen::Isometry3d& sensor_to_reference);

// Aligned points are stored as float, whose centimetres are gone beyond ~100 km (a pose in
// UTM map coordinates). They are stored relative to this local origin instead: the sensor's
// position rounded to a multiple of 1024 m — zero for any pose within 512 m of the reference
// frame's origin, so ordinary scenes are computed exactly as without it.
Eigen::Vector3d localOrigin(const Orientation& orientation);

// Transforms every point into F_r, minus `origin` (see localOrigin). Non-finite input points
// become NaN so that later stages (and per-point labels) keep the input order. Returns the
// number of finite points; with `finite_box`, also their bounding box (the grid filter needs
// it, and this pass has every point at hand). `threads` as Params::threads (0: every core).
std::size_t alignToGravity(const PointsView& input, const Orientation& orientation,
                           std::vector<Eigen::Vector3f>& aligned,
                           const Eigen::Vector3d& origin = Eigen::Vector3d::Zero(),
                           Eigen::AlignedBox3f* finite_box = nullptr, int threads = 1);

// Whether alignToGravity would copy `input` unchanged: the orientation has no rotation and its
// translation equals `origin`, and x, y, z are packed float32 at the start of each point. The
// stages then read the input in place (see AlignedPoints) and only finiteBox() is needed.
bool alignmentIsIdentity(const PointsView& input, const Orientation& orientation,
                         const Eigen::Vector3d& origin);

// The number of finite points of `input` and their box (a point with any non-finite
// coordinate is skipped), in one read; `threads` as Params::threads. x, y, z must be packed
// float32 at the start of each point, as alignmentIsIdentity() requires.
std::size_t finiteBox(const PointsView& input, Eigen::AlignedBox3f& box, int threads = 1);

}  // namespace hope
