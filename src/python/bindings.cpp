// Python bindings of the core (module hope._hope, re-exported by the package hope): the
// extractor, the tracker and the depth-image path, taking and returning NumPy arrays. Uses
// only pybind11 APIs present in 2.4 (Ubuntu 20.04, ROS Noetic).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "hope/depth_image.h"
#include "hope/extractor.h"
#include "hope/frame_pipeline.h"
#include "hope/parameters.h"
#include "hope/plane_colors.h"
#include "hope/plane_tracker.h"
#include "hope/surface_map.h"
#include "hope/tools/io.h"
#include "hope/up_estimation.h"

namespace py = pybind11;

namespace {

// What Extractor.extract returns: the core's result and the per-point labels as an array
// that owns the core's label vector (no copy).
struct ExtractionResult {
  hope::Result result;
  py::array labels;
  py::object object_labels = py::none();  // with objects=True: int32 per point, -1 for none
  // What up from the scene found (level=True), or nothing.
  std::optional<hope::UpEstimate> levelling;
  // Pipeline.process only: the ids' events, why the frame was skipped (empty: it was not),
  // whether the last up was held or time went back, and the frame (its points kept) that
  // Pipeline.place answers on.
  std::vector<hope::TrackEvent> events;
  std::string skipped;
  bool level_held = false, time_jump = false;
  // tracking_mode="odometry": {"tracked", "started", "overlap", "ms", "world_from_frame"}
  // (hope::Frame::Odometry), else None.
  py::object odometry = py::none();
  std::shared_ptr<const hope::Frame> frame;
  // Pipeline.process(obstacles=True): the input indices of the obstacle points (uint32), and
  // the floor's plane id (-1: none in view).
  py::object obstacles = py::none();
  int floor_id = -1;
  // Pipeline.process(floor_grid=True): {"cells": int8 (height, width), "resolution",
  // "origin": (x, y), "floor_height"}, or None without a floor in view.
  py::object floor_grid = py::none();
};

std::string shapeText(const py::array& array) {
  std::ostringstream out;
  out << "(";
  for (py::ssize_t d = 0; d < array.ndim(); ++d) out << (d ? ", " : "") << array.shape(d);
  out << (array.ndim() == 1 ? ",)" : ")");
  return out.str();
}

std::string dtypeText(const py::array& array) { return py::str(array.attr("dtype")); }

// A NumPy array that owns `values` (moved to the heap), shaped `shape`.
template <class T>
py::array ownedArray(std::vector<T>&& values, const std::vector<py::ssize_t>& shape) {
  auto* owned = new std::vector<T>(std::move(values));
  py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  std::vector<py::ssize_t> strides(shape.size(), sizeof(T));
  for (std::size_t d = shape.size(); d-- > 1;) strides[d - 1] = strides[d] * shape[d];
  return py::array_t<T>(shape, strides, owned->data(), owner);
}

std::vector<double> numbers(const py::object& value, std::size_t count, const char* name,
                            const char* meaning) {
  std::vector<double> out;
  try {
    out = value.cast<std::vector<double>>();
  } catch (const py::cast_error&) {
    throw py::type_error(std::string(name) + " must be a sequence of " + std::to_string(count) +
                         " numbers " + meaning);
  }
  if (out.size() != count) {
    throw py::value_error(std::string(name) + " must have " + std::to_string(count) + " numbers " +
                          meaning + ", got " + std::to_string(out.size()));
  }
  return out;
}

Eigen::Vector3d viewpointOf(const py::object& viewpoint) {
  const auto v = numbers(viewpoint, 3, "viewpoint", "(the sensor's position, reference frame)");
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

// At most one of gravity, quaternion, pose, transform; none means the cloud is already z-up.
hope::Orientation orientationOf(const py::object& gravity, const py::object& quaternion,
                                const py::object& pose, const py::object& transform,
                                const py::object& viewpoint) {
  const int given =
      !gravity.is_none() + !quaternion.is_none() + !pose.is_none() + !transform.is_none();
  if (given > 1) {
    throw py::value_error(
        "give at most one of gravity, quaternion, pose and transform (the sensor's orientation)");
  }
  hope::Orientation orientation = hope::Orientation::identity();
  if (!gravity.is_none()) {
    const auto g = numbers(gravity, 3, "gravity", "(the accelerometer at rest, sensor frame)");
    orientation = hope::Orientation::fromGravity(g[0], g[1], g[2]);
  } else if (!quaternion.is_none()) {
    const auto q = numbers(quaternion, 4, "quaternion", "(x, y, z, w)");
    orientation = hope::Orientation::fromQuaternion(q[0], q[1], q[2], q[3]);
  } else if (!pose.is_none()) {
    const auto p = numbers(pose, 7, "pose", "(tx, ty, tz, qx, qy, qz, qw)");
    orientation = hope::Orientation::fromPose(p[0], p[1], p[2], p[3], p[4], p[5], p[6]);
  } else if (!transform.is_none()) {
    Eigen::Matrix4d m;
    try {
      m = transform.cast<Eigen::Matrix4d>();
    } catch (const py::cast_error&) {
      throw py::type_error("transform must be a 4 x 4 matrix (sensor to reference frame)");
    }
    if (!m.allFinite()) throw py::value_error("transform has NaN or infinite entries");
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.matrix().topRows<3>() = m.topRows<3>();
    orientation = hope::Orientation::fromTransform(t);
  }
  if (!viewpoint.is_none()) orientation = orientation.withViewpoint(viewpointOf(viewpoint));
  return orientation;
}

// The points of an N x 3 or H x W x 3 array, read in place when they are float32 and evenly
// spaced in memory; otherwise converted into `converted` (float64, strided views...).
hope::PointsView pointsOf(const py::array& points, py::array& converted) {
  const py::ssize_t ndim = points.ndim();
  if (!((ndim == 2 || ndim == 3) && points.shape(ndim - 1) == 3)) {
    throw py::value_error("points must have shape (N, 3) or (H, W, 3), got " + shapeText(points));
  }
  const bool is_float32 = py::isinstance<py::array_t<float>>(points);
  if (!is_float32 && !py::isinstance<py::array_t<double>>(points)) {
    throw py::type_error("points must be float32 or float64, got " + dtypeText(points));
  }
  const std::size_t height = ndim == 3 ? static_cast<std::size_t>(points.shape(0)) : 1;
  const std::size_t width = static_cast<std::size_t>(points.shape(ndim - 2));
  if (height * width == 0) {
    throw py::value_error("points is empty (shape " + shapeText(points) + "): nothing to extract");
  }
  if (height * width > std::numeric_limits<std::uint32_t>::max()) {
    throw py::value_error("points has more than 2^32 - 1 points");
  }
  const py::ssize_t coordinate_step = points.strides(ndim - 1);
  const py::ssize_t point_step = points.strides(ndim - 2);
  const bool rows_follow =
      ndim == 2 || height == 1 || points.strides(0) == point_step * static_cast<py::ssize_t>(width);
  const py::array* source = &points;
  if (!(is_float32 && coordinate_step > 0 && point_step > 0 && rows_follow)) {
    converted = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(points);
    if (!converted) throw py::error_already_set();
    source = &converted;
  }
  hope::PointsView view;
  view.data = static_cast<const std::uint8_t*>(source->data());
  view.count = height * width;
  view.stride = static_cast<std::size_t>(source->strides(ndim - 2));
  view.x_offset = 0;
  view.y_offset = static_cast<std::size_t>(source->strides(ndim - 1));
  view.z_offset = 2 * view.y_offset;
  view.width = static_cast<std::uint32_t>(width);
  view.height = static_cast<std::uint32_t>(height);
  return view;
}

// The index into `planes` of the plane with id `plane_id` (None: -1, any plane); ValueError
// naming `where` when no plane has it.
int planeIndexOf(const std::vector<hope::HorizontalPlane>& planes, const py::object& plane_id,
                 const char* where) {
  if (plane_id.is_none()) return -1;
  const int id = plane_id.cast<int>();
  for (std::size_t p = 0; p < planes.size(); ++p) {
    if (planes[p].id == id) return static_cast<int>(p);
  }
  throw py::value_error("plane_id " + std::to_string(id) + " is not a plane of " + where);
}

// Placements as dicts: plane_id, x, y, z, yaw, margin.
py::list placementDicts(const std::vector<hope::Placement>& placements) {
  py::list out;
  for (const hope::Placement& p : placements) {
    py::dict d;
    d["plane_id"] = p.plane_id;
    d["x"] = p.centre.x();
    d["y"] = p.centre.y();
    d["z"] = p.centre.z();
    d["yaw"] = p.yaw;
    d["margin"] = p.margin;
    out.append(d);
  }
  return out;
}

// The Python-facing extractor: one cloud at a time through the core's frame pipeline
// (FramePipeline::processAlone, as hope_extract --input), which reuses its buffers between
// calls, and a lock, since the GIL is released while it runs.
class PyExtractor {
 public:
  explicit PyExtractor(const hope::Params& params) : pipeline_(optionsFor(params)) {}

  ExtractionResult extract(const py::array& points, const py::object& gravity,
                           const py::object& quaternion, const py::object& pose,
                           const py::object& transform, const py::object& viewpoint, bool level,
                           double level_bound, bool objects, double object_max_height) {
    const bool given =
        !gravity.is_none() || !quaternion.is_none() || !pose.is_none() || !transform.is_none();
    hope::Orientation orientation = orientationOf(gravity, quaternion, pose, transform, viewpoint);
    // Levelled clouds are in the sensor's frame: the sensor at the origin unless told.
    if (level && !orientation.viewpoint()) {
      orientation = orientation.withViewpoint(Eigen::Vector3d::Zero());
    }
    hope::PipelineOptions options = pipeline_.options();
    options.levelling = !level  ? hope::SceneLevelling::kOff
                        : given ? hope::SceneLevelling::kRefine
                                : hope::SceneLevelling::kEstimate;
    options.level_bound_deg = level_bound;
    options.objects = objects;
    options.object_params.max_height = object_max_height;
    hope::validate(options);  // ValueError naming level_bound's or object_max_height's range
    hope::FrameOutputs outputs;
    outputs.objects = objects;
    outputs.keep_points = objects;  // place() answers on this call's points
    py::array converted;
    const hope::PointsView view = pointsOf(points, converted);
    ExtractionResult out;
    {
      py::gil_scoped_release released;
      std::lock_guard<std::mutex> lock(mutex_);
      const hope::PipelineOptions& now = pipeline_.options();
      if (options.levelling != now.levelling || options.level_bound_deg != now.level_bound_deg ||
          options.objects != now.objects ||
          options.object_params.max_height != now.object_params.max_height) {
        pipeline_.setOptions(options);
      }
      hope::Frame frame = pipeline_.processAlone(view, orientation, outputs);
      if (!frame.processed) throw hope::LevellingError(frame.skipped);
      out.levelling = frame.levelling;
      if (objects) {
        out.result = frame.result;
        last_ = std::move(frame);
      } else {
        out.result = std::move(frame.result);
        last_.reset();
      }
    }
    if (out.result.finite_points == 0) {
      throw py::value_error("points has no finite point (all " +
                            std::to_string(out.result.input_points) + " are NaN or infinite)");
    }
    if (out.levelling && out.levelling->refinement && !out.levelling->applied) {
      out.result.warnings.push_back("level=True kept the given orientation: " +
                                    out.levelling->note);
    }
    if (!level && !given) {
      // Nothing said which way is up: say so when the cloud does not look z-up.
      for (const auto& warning :
           hope::unorientedCloudWarnings(view, out.result.planes, !viewpoint.is_none())) {
        out.result.warnings.push_back(warning);
      }
    }
    // Python shows a UserWarning once per calling line (its default filter).
    for (const auto& warning : out.result.warnings) {
      if (PyErr_WarnEx(PyExc_UserWarning, ("hope: " + warning).c_str(), 1) < 0) {
        throw py::error_already_set();  // warnings turned into errors by the caller's filter
      }
    }
    std::vector<py::ssize_t> shape;
    if (points.ndim() == 3)
      shape = {points.shape(0), points.shape(1)};
    else
      shape = {points.shape(0)};
    out.labels = ownedArray(std::move(out.result.point_labels), shape);
    out.result.point_labels.clear();
    if (objects) {
      out.object_labels = ownedArray(std::move(out.result.point_objects), shape);
      out.result.point_objects.clear();
    }
    return out;
  }

  // Placements on the planes of the last extract(objects=True) call.
  py::list place(double width, double depth, double clearance, const py::object& plane_id,
                 std::size_t max_results) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!last_) {
      throw py::value_error("place() needs a previous extract(..., objects=True) call");
    }
    hope::PlacementQuery query;
    query.footprint = {width, depth, clearance};
    query.max_results = max_results;
    query.plane_index = planeIndexOf(last_->result.planes, plane_id, "the last call");
    std::vector<hope::Placement> placements;
    {
      py::gil_scoped_release released;
      placements = pipeline_.findPlacements(*last_, query);
    }
    return placementDicts(placements);
  }

  const hope::Params& params() const { return pipeline_.options().extraction; }

 private:
  static hope::PipelineOptions optionsFor(const hope::Params& params) {
    hope::PipelineOptions options;
    options.extraction = params;
    return options;
  }

  hope::FramePipeline pipeline_;
  std::optional<hope::Frame> last_;  // the last extract(objects=True) call, with its points
  std::mutex mutex_;
};

// The Python-facing frame pipeline (frame_pipeline.h): the policy of the nodelet and of
// hope_extract --sequence, frame by frame.
class PyPipeline {
 public:
  explicit PyPipeline(const hope::PipelineOptions& options)
      : pipeline_(options), identity_asked_(options.identity) {}

  ExtractionResult process(const py::array& points, double stamp, const py::object& gravity,
                           const py::object& quaternion, const py::object& pose,
                           const py::object& transform, const py::object& viewpoint,
                           bool placements, bool obstacles, bool floor_grid) {
    std::optional<Eigen::Vector3d> force;
    hope::Orientation given = hope::Orientation::identity();
    if (!gravity.is_none()) {
      if (!quaternion.is_none() || !pose.is_none() || !transform.is_none()) {
        throw py::value_error(
            "give at most one of gravity, quaternion, pose and transform (the sensor's "
            "orientation)");
      }
      const auto g = numbers(gravity, 3, "gravity", "(an accelerometer sample, sensor frame)");
      force = Eigen::Vector3d(g[0], g[1], g[2]);
    } else {
      given = orientationOf(py::none(), quaternion, pose, transform, py::none());
    }
    // A cloud in its sensor's frame: the sensor at the origin unless told.
    const Eigen::Vector3d at =
        viewpoint.is_none() ? Eigen::Vector3d::Zero() : viewpointOf(viewpoint);
    if (!viewpoint.is_none() || (quaternion.is_none() && pose.is_none() && transform.is_none())) {
      given = given.withViewpoint(at);
    }
    hope::FrameOutputs outputs;
    outputs.keep_points = placements;
    outputs.obstacles = obstacles;
    outputs.floor_grid = floor_grid;
    py::array converted;
    const hope::PointsView view = pointsOf(points, converted);
    auto frame = std::make_shared<hope::Frame>();
    {
      py::gil_scoped_release released;
      std::lock_guard<std::mutex> lock(mutex_);
      // tracking_mode='auto': the first frame's orientation says what the input is, a pose or
      // transform being one in a fixed frame (hope::defaultIdentity).
      if (identity_asked_ == hope::Identity::kAuto) {
        const hope::PoseInput input = pose.is_none() && transform.is_none()
                                          ? hope::PoseInput::kOrientation
                                          : hope::PoseInput::kFixedFramePoses;
        hope::PipelineOptions resolved = pipeline_.options();
        resolved.identity = hope::defaultIdentity(input);
        pipeline_.setOptions(resolved);
        identity_asked_ = resolved.identity;
      }
      *frame = force ? pipeline_.processWithGravity(view, stamp, *force, outputs, at)
                     : pipeline_.process(view, stamp, given, outputs);
    }
    ExtractionResult out;
    out.result = frame->result;
    out.levelling = frame->levelling;
    out.events = frame->events;
    out.skipped = frame->processed ? std::string() : frame->skipped;
    out.level_held = frame->level_held;
    out.time_jump = frame->time_jump;
    if (frame->odometry) {
      py::dict odometry;
      odometry["tracked"] = frame->odometry->tracked;
      odometry["started"] = frame->odometry->started;
      odometry["overlap"] = frame->odometry->overlap;
      odometry["ms"] = frame->odometry->ms;
      odometry["world_from_frame"] = Eigen::Matrix4d(frame->odometry->world_from_frame.matrix());
      out.odometry = odometry;
    }
    for (const auto& warning : out.result.warnings) {
      if (PyErr_WarnEx(PyExc_UserWarning, ("hope: " + warning).c_str(), 1) < 0) {
        throw py::error_already_set();
      }
    }
    std::vector<py::ssize_t> shape;
    if (points.ndim() == 3)
      shape = {points.shape(0), points.shape(1)};
    else
      shape = {points.shape(0)};
    std::vector<std::int32_t> labels = out.result.point_labels;
    if (labels.empty()) labels.assign(static_cast<std::size_t>(view.count), -1);  // skipped
    out.labels = ownedArray(std::move(labels), shape);
    out.result.point_labels.clear();
    if (!out.result.point_objects.empty()) {
      out.object_labels = ownedArray(std::move(out.result.point_objects), shape);
    }
    out.result.point_objects.clear();
    if ((obstacles || floor_grid) && frame->floor_index >= 0) {
      out.floor_id = frame->result.planes[frame->floor_index].id;
    }
    if (floor_grid && frame->floor_grid.width > 0) {
      hope::FloorGrid& grid = frame->floor_grid;
      py::dict d;
      d["cells"] = ownedArray(std::move(grid.cells), {grid.height, grid.width});
      d["resolution"] = grid.resolution;
      d["origin"] = py::make_tuple(grid.origin.x(), grid.origin.y());
      d["floor_height"] = grid.floor_height;
      out.floor_grid = std::move(d);
    }
    if (obstacles) {
      out.obstacles = ownedArray(std::vector<std::uint32_t>(frame->obstacles),
                                 {static_cast<py::ssize_t>(frame->obstacles.size())});
    }
    if (placements) out.frame = std::move(frame);
    return out;
  }

  py::list place(const ExtractionResult& result, double width, double depth, double clearance,
                 const py::object& plane_id, std::size_t max_results) {
    if (!result.frame) {
      throw py::value_error("place() needs a result of process(..., placements=True)");
    }
    hope::PlacementQuery query;
    query.footprint = {width, depth, clearance};
    query.max_results = max_results;
    query.plane_index = planeIndexOf(result.frame->result.planes, plane_id, "that frame");
    std::vector<hope::Placement> placements;
    {
      py::gil_scoped_release released;
      std::lock_guard<std::mutex> lock(mutex_);
      placements = pipeline_.findPlacements(*result.frame, query);
    }
    return placementDicts(placements);
  }

  std::vector<hope::HorizontalPlane> mapSurfaces() {
    std::lock_guard<std::mutex> lock(mutex_);
    return pipeline_.mapSurfaces();
  }
  const hope::PipelineOptions& options() const { return pipeline_.options(); }
  // "auto" until the first frame resolves it.
  std::string trackingMode() {
    std::lock_guard<std::mutex> lock(mutex_);  // process() resolves it with the GIL released
    return hope::toString(identity_asked_ == hope::Identity::kAuto ? identity_asked_
                                                                   : pipeline_.options().identity);
  }

 private:
  hope::FramePipeline pipeline_;
  // kAuto until the first frame resolves it.
  hope::Identity identity_asked_;
  std::mutex mutex_;
};

// hope.read_cloud: a .pcd (ASCII, binary, binary_compressed) or .ply file as hope_extract reads
// it: H x W x 3 float32 for an organized cloud, N x 3 otherwise, NaN where nothing was seen.
py::array readCloud(const std::string& path) {
  hope::tools::InputCloud cloud;
  {
    py::gil_scoped_release released;
    cloud = hope::tools::loadCloud(path);
  }
  std::vector<float> flat;
  flat.reserve(cloud.points.size() * 3);
  for (const Eigen::Vector3f& p : cloud.points) flat.insert(flat.end(), {p.x(), p.y(), p.z()});
  const auto n = static_cast<py::ssize_t>(cloud.points.size());
  if (cloud.height > 1) {
    return ownedArray(std::move(flat), {static_cast<py::ssize_t>(cloud.height),
                                        static_cast<py::ssize_t>(cloud.width), 3});
  }
  return ownedArray(std::move(flat), {n, 3});
}

// hope.Pipeline(levelling="off", **parameters): every keyword is a row of the parameter table
// (parameters.h), so Python takes exactly the parameters the nodelet and hope_extract take.
std::unique_ptr<PyPipeline> makePipeline(const std::string& levelling, const py::kwargs& kwargs) {
  hope::PipelineOptions options;
  options.levelling = hope::sceneLevellingFromString(levelling);
  const std::vector<hope::ParameterSpec>& table = hope::pipelineParameters();
  for (const auto& item : kwargs) {
    const std::string name = py::str(item.first);
    const auto spec = std::find_if(table.begin(), table.end(),
                                   [&](const hope::ParameterSpec& p) { return p.name == name; });
    if (spec == table.end()) {
      std::string known;
      for (const auto& p : table) known += (known.empty() ? "" : ", ") + p.name;
      throw py::type_error("Pipeline() got an unexpected keyword '" + name + "' (it takes " +
                           "levelling and " + known + ")");
    }
    const py::handle value = item.second;
    if (spec->type == hope::ParameterSpec::Type::kChoice) {
      const auto choice =
          std::find(spec->choices.begin(), spec->choices.end(),
                    py::isinstance<py::str>(value) ? value.cast<std::string>() : std::string("?"));
      if (choice == spec->choices.end()) {
        throw py::value_error(name + " must be one of " +
                              py::str(py::cast(spec->choices)).cast<std::string>());
      }
      spec->set(options, static_cast<double>(choice - spec->choices.begin()));
    } else if (spec->type == hope::ParameterSpec::Type::kBool) {
      if (!py::isinstance<py::bool_>(value)) throw py::type_error(name + " must be True or False");
      spec->set(options, value.cast<bool>() ? 1.0 : 0.0);
    } else {
      if (py::isinstance<py::bool_>(value) ||
          !(py::isinstance<py::int_>(value) || py::isinstance<py::float_>(value))) {
        throw py::type_error(name + " must be a number");
      }
      const double number = value.cast<double>();
      if (spec->type == hope::ParameterSpec::Type::kInt && number != std::floor(number)) {
        throw py::value_error(name + " must be a whole number");
      }
      spec->set(options, number);
    }
  }
  return std::make_unique<PyPipeline>(options);  // validates: ValueError naming the parameter
}

// The class's docstring: every keyword with its default, unit and meaning, from the table.
std::string pipelineDoc() {
  std::ostringstream doc;
  doc << "One frame's whole policy, as the nodelet and hope_extract --sequence apply it: "
         "orientation (given, an accelerometer averaged over gravity_window_s, or up from the "
         "scene), planes, objects and persistent ids (include/hope/frame_pipeline.h).\n\n"
         "Pipeline(levelling='off', **parameters): levelling 'off', 'estimate' (up from each "
         "frame's scene) or 'refine' (the given orientation corrected). Parameters:\n";
  for (const hope::ParameterSpec& p : hope::pipelineParameters()) {
    doc << "  " << p.name << " = ";
    if (p.type == hope::ParameterSpec::Type::kChoice) {
      doc << "'" << p.default_choice << "'";
    } else if (p.type == hope::ParameterSpec::Type::kBool) {
      doc << (p.default_value != 0 ? "True" : "False");
    } else {
      doc << p.default_value;
    }
    doc << (p.unit.empty() ? "" : " " + p.unit) << ": " << p.doc << "\n";
  }
  return doc.str();
}

// hope.parameters(): the table as dicts.
py::list parameterTable() {
  py::list out;
  for (const hope::ParameterSpec& p : hope::pipelineParameters()) {
    py::dict d;
    d["name"] = p.name;
    d["option"] = p.option;
    const char* types[] = {"double", "int", "bool", "choice"};
    d["type"] = types[static_cast<int>(p.type)];
    if (p.type == hope::ParameterSpec::Type::kChoice) {
      d["default"] = p.default_choice;
      d["choices"] = p.choices;
    } else if (p.type == hope::ParameterSpec::Type::kBool) {
      d["default"] = p.default_value != 0;
    } else {
      d["default"] = p.default_value;
      d["min"] = p.min;
      d["max"] = p.max;
      d["min_excluded"] = p.min_excluded;
    }
    d["unit"] = p.unit;
    d["stage"] = p.stage;
    d["live"] = p.live;
    d["doc"] = p.doc;
    out.append(d);
  }
  return out;
}

py::array rows(const std::vector<Eigen::Vector3d>& points) {
  std::vector<double> flat;
  flat.reserve(points.size() * 3);
  for (const Eigen::Vector3d& p : points) flat.insert(flat.end(), {p.x(), p.y(), p.z()});
  return ownedArray(std::move(flat), {static_cast<py::ssize_t>(points.size()), 3});
}

py::list outlineOf(const hope::HorizontalPlane& plane) {
  py::list rings;
  for (const auto& ring : plane.outline) rings.append(rows(ring));
  return rings;
}

// Every field of hope_extract's JSON output for one plane.
py::dict planeDict(const hope::HorizontalPlane& p) {
  py::dict d;
  d["id"] = p.id;
  d["height"] = p.height;
  d["bbox"] = py::make_tuple(p.bbox[0], p.bbox[1], p.bbox[2], p.bbox[3]);
  d["centroid"] = py::make_tuple(p.centroid.x(), p.centroid.y(), p.centroid.z());
  d["normal"] = py::make_tuple(p.normal.x(), p.normal.y(), p.normal.z());
  d["tilt"] = p.tilt;
  d["area"] = p.area;
  d["free_area"] = p.free_area;
  d["num_points"] = p.num_points;
  d["num_voxels"] = p.num_voxels;
  d["num_parts"] = p.num_parts;
  d["facing"] = hope::toString(p.facing);
  d["age"] = p.age;
  d["last_seen"] = p.last_seen;
  d["split_from"] = p.split_from;
  d["surface_id"] = p.surface_id;
  d["hull"] = rows(p.hull);
  d["outline"] = outlineOf(p);
  return d;
}

// Every field of hope_extract's JSON output for one object.
py::dict objectDict(const hope::StandingObject& o) {
  py::dict d;
  d["index"] = o.index;
  d["plane_id"] = o.plane_id;
  d["num_points"] = o.num_points;
  d["centroid"] = py::make_tuple(o.centroid.x(), o.centroid.y(), o.centroid.z());
  py::dict box;
  box["centre"] = py::make_tuple(o.box_centre.x(), o.box_centre.y(), o.box_centre.z());
  box["yaw"] = o.yaw;
  box["size"] = py::make_tuple(o.box_size.x(), o.box_size.y(), o.box_size.z());
  d["box"] = box;
  d["height_above_plane"] = o.height;
  d["footprint"] = rows(o.footprint);
  return d;
}

py::dict statsOf(const hope::Result& r) {
  py::dict d;
  d["input_points"] = r.input_points;
  d["finite_points"] = r.finite_points;
  d["voxels"] = r.voxels;
  d["candidates"] = r.candidates;
  d["clusters"] = r.clusters;
  d["rejected_by_refinement"] = r.rejected_by_refinement;
  d["rejected_by_band_or_area"] = r.rejected_by_band_or_area;
  d["merged_fragments"] = r.merged_fragments;
  d["bridged_voxels"] = r.bridged_voxels;
  return d;
}

py::dict timingsOf(const hope::Result& r) {
  const hope::StageTimings& t = r.timings;
  py::dict d;
  d["alignment"] = t.alignment_ms;
  d["grid_filter"] = t.grid_filter_ms;
  d["normals"] = t.normals_ms;
  d["candidates"] = t.candidates_ms;
  d["clustering"] = t.clustering_ms;
  d["refinement"] = t.refinement_ms;
  d["description"] = t.description_ms;
  d["merging"] = t.merging_ms;
  d["objects"] = t.objects_ms;
  d["total"] = t.total_ms;
  return d;
}

// The levelling block of hope_extract's JSON.
py::object levellingOf(const ExtractionResult& r) {
  if (!r.levelling) return py::none();
  const hope::UpEstimate& e = *r.levelling;
  py::dict d;
  d["source"] = e.refinement ? "refined" : "scene";
  d["up_in_sensor"] = py::make_tuple(e.up_in_sensor.x(), e.up_in_sensor.y(), e.up_in_sensor.z());
  d["support_area_m2"] = e.support_area;
  d["angle_spread_deg"] = e.angle_spread_deg;
  d["level_surfaces"] = e.level_surfaces;
  d["level_heights"] = e.level_heights;
  d["prior"] = hope::toString(e.prior);
  if (e.prior == hope::UpPrior::kCamera) {
    d["pitch_deg"] = e.pitch_deg;
    d["roll_deg"] = e.roll_deg;
  }
  if (e.refinement) {
    d["correction_deg"] = e.correction_deg;
    d["resolution_deg"] = e.resolution_deg;
    d["applied"] = e.applied;
    d["note"] = e.note;
  }
  d["ms"] = e.time_ms;
  return std::move(d);
}

py::tuple upInSensorOf(const ExtractionResult& r) {
  const Eigen::Vector3d up = hope::upInSensor(r.result.sensor_to_reference);
  return py::make_tuple(up.x(), up.y(), up.z());
}

std::string planeRepr(const hope::HorizontalPlane& p) {
  char text[160];
  std::snprintf(text, sizeof(text), "Plane(id=%d, height=%.3f, area=%.3f, num_points=%zu)", p.id,
                p.height, p.area, p.num_points);
  return text;
}

std::unique_ptr<PyExtractor> makeExtractor(double r_xy, double r_z, double normal_radius_factor,
                                           int min_cluster_voxels, double min_height,
                                           double max_height, double min_area, bool merge_fragments,
                                           double max_merge_gap, bool bridge_scan_gaps,
                                           int threads) {
  hope::Params p;
  p.r_xy = r_xy;
  p.r_z = r_z;
  p.normal_radius_factor = normal_radius_factor;
  p.min_cluster_voxels = min_cluster_voxels;
  p.min_height = min_height;
  p.max_height = max_height;
  p.min_area = min_area;
  p.merge_fragments = merge_fragments;
  p.max_merge_gap = max_merge_gap;
  p.bridge_scan_gaps = bridge_scan_gaps;
  p.threads = threads;
  // The core validates: its std::invalid_argument, naming the parameter, becomes ValueError.
  return std::make_unique<PyExtractor>(p);
}

py::array depthToCloud(const py::array& depth, const py::object& intrinsics, double scale) {
  if (depth.ndim() != 2) {
    throw py::value_error("depth must be a 2-D image (H, W), got shape " + shapeText(depth));
  }
  int type = 0;
  py::array image;
  if (py::isinstance<py::array_t<std::uint16_t>>(depth)) {
    type = CV_16UC1;
    image = py::array_t<std::uint16_t, py::array::c_style>::ensure(depth);
  } else if (py::isinstance<py::array_t<float>>(depth)) {
    type = CV_32FC1;
    image = py::array_t<float, py::array::c_style>::ensure(depth);
  } else {
    throw py::type_error(
        "depth must be uint16 (raw units, `scale` per metre) or float32 (metres), got " +
        dtypeText(depth));
  }
  const auto k = numbers(intrinsics, 4, "intrinsics", "(fx, fy, cx, cy)");
  const cv::Mat mat(static_cast<int>(depth.shape(0)), static_cast<int>(depth.shape(1)), type,
                    const_cast<void*>(image.data()));
  auto cloud = std::make_unique<pcl::PointCloud<pcl::PointXYZ>>(
      hope::depthToCloud(mat, hope::PinholeIntrinsics{k[0], k[1], k[2], k[3]}, scale));
  // A view onto the cloud's points (x y z and PCL's padding float): H x W x 3, 16-byte steps,
  // which Extractor.extract reads in place.
  auto* owned = cloud.release();
  py::capsule owner(owned, [](void* p) { delete static_cast<pcl::PointCloud<pcl::PointXYZ>*>(p); });
  const py::ssize_t h = depth.shape(0), w = depth.shape(1);
  const py::ssize_t step = sizeof(pcl::PointXYZ);
  return py::array_t<float>({h, w, py::ssize_t(3)}, {w * step, step, py::ssize_t(sizeof(float))},
                            &owned->points[0].x, owner);
}

}  // namespace

PYBIND11_MODULE(_hope, m) {
  m.doc() = "HoPE: horizontal plane extraction (Dong et al., Sensors 2018), the C++ core";
  py::register_exception<hope::LevellingError>(m, "LevellingError", PyExc_ValueError);

  py::class_<hope::HorizontalPlane>(m, "Plane", "One horizontal plane (reference frame, metres)")
      .def_readwrite("id", &hope::HorizontalPlane::id)
      .def_readwrite("height", &hope::HorizontalPlane::height)
      .def_property_readonly(
          "bbox",
          [](const hope::HorizontalPlane& p) {
            return py::make_tuple(p.bbox[0], p.bbox[1], p.bbox[2], p.bbox[3]);
          },
          "(x_min, y_min, x_max, y_max)")
      .def_readonly("centroid", &hope::HorizontalPlane::centroid)
      .def_readonly("normal", &hope::HorizontalPlane::normal)
      .def_readonly("tilt", &hope::HorizontalPlane::tilt, "radians from the z axis")
      .def_readonly("area", &hope::HorizontalPlane::area, "m² at grid resolution")
      .def_readonly("free_area", &hope::HorizontalPlane::free_area,
                    "m² observed with nothing standing on it (objects=True), else 0")
      .def_readonly("num_voxels", &hope::HorizontalPlane::num_voxels)
      .def_readonly("num_points", &hope::HorizontalPlane::num_points)
      .def_readonly("num_parts", &hope::HorizontalPlane::num_parts)
      .def_property_readonly(
          "facing", [](const hope::HorizontalPlane& p) { return hope::toString(p.facing); })
      .def_property_readonly(
          "hull", [](const hope::HorizontalPlane& p) { return rows(p.hull); },
          "K x 3, counter-clockwise seen from above")
      .def_property_readonly(
          "outline", &outlineOf,
          "rings (K x 3): counter-clockwise around parts, clockwise around holes")
      .def_readonly("mean_normal_tilt", &hope::HorizontalPlane::mean_normal_tilt)
      .def_readonly("group_angle", &hope::HorizontalPlane::group_angle)
      .def_readonly("age", &hope::HorizontalPlane::age)
      .def_readonly("last_seen", &hope::HorizontalPlane::last_seen)
      .def_readonly("split_from", &hope::HorizontalPlane::split_from)
      .def_readonly(
          "surface_id", &hope::HorizontalPlane::surface_id,
          "the surface it is a piece of: pieces of one surface in a frame share it, and a "
          "surface keeps it from frame to frame")
      .def("to_dict", &planeDict, "every field of hope_extract's JSON output")
      .def("__repr__", &planeRepr);

  py::class_<ExtractionResult>(m, "ExtractionResult")
      .def_property(
          "planes", [](const ExtractionResult& r) { return r.result.planes; },
          [](ExtractionResult& r, const std::vector<hope::HorizontalPlane>& planes) {
            r.result.planes = planes;
          })
      .def_readonly("labels", &ExtractionResult::labels,
                    "int32 per point (N or H x W): index into planes, -1 for none")
      .def_readonly("object_labels", &ExtractionResult::object_labels,
                    "with objects=True, int32 per point: index into objects, -1 for none")
      .def_property_readonly(
          "objects",
          [](const ExtractionResult& r) {
            py::list objects;
            for (const auto& o : r.result.objects) objects.append(objectDict(o));
            return objects;
          },
          "with objects=True: what stands on each plane (dicts as in hope_extract's JSON)")
      .def_property_readonly("stats", [](const ExtractionResult& r) { return statsOf(r.result); })
      .def_property_readonly("timings_ms",
                             [](const ExtractionResult& r) { return timingsOf(r.result); })
      .def_property_readonly("warnings",
                             [](const ExtractionResult& r) { return r.result.warnings; })
      .def_property_readonly(
          "sensor_to_reference",
          [](const ExtractionResult& r) -> Eigen::Matrix4d {
            return r.result.sensor_to_reference.matrix();
          },
          "4 x 4, the transform applied to the points")
      .def_property_readonly("up_in_sensor", &upInSensorOf,
                             "the unit up vector in the input cloud's frame")
      .def_property_readonly("levelling", &levellingOf,
                             "what up from the scene found (level=True), else None")
      .def_readonly("events", &ExtractionResult::events,
                    "Pipeline.process: what happened to ids (new, lost, merged...)")
      .def_property_readonly(
          "skipped",
          [](const ExtractionResult& r) -> py::object {
            if (r.skipped.empty()) return py::none();
            return py::str(r.skipped);
          },
          "Pipeline.process: why the frame was skipped (nothing level in view), else None")
      .def_readonly("level_held", &ExtractionResult::level_held,
                    "Pipeline.process: nothing level in view, the last up held")
      .def_readonly("time_jump", &ExtractionResult::time_jump,
                    "Pipeline.process: the stamp went back; tracks started afresh")
      .def_readonly("odometry", &ExtractionResult::odometry,
                    "Pipeline.process with tracking_mode='odometry': a dict, tracked (the "
                    "frame aligned with the last), started (the frame began the odometry's "
                    "world), overlap (the share of its voxels that met the "
                    "last frame's surfaces), ms, world_from_frame (4 x 4: this frame's "
                    "reference-frame coordinates into the odometry's world, the map's frame); "
                    "else None")
      .def_readonly("obstacles", &ExtractionResult::obstacles,
                    "Pipeline.process(obstacles=True): the indices (uint32, into the points "
                    "flattened) of the points between obstacle_min_height and "
                    "obstacle_max_height above the floor, else None")
      .def_readonly("floor_id", &ExtractionResult::floor_id,
                    "Pipeline.process(obstacles=True or floor_grid=True): the floor's plane "
                    "id, -1 for none")
      .def_readonly("floor_grid", &ExtractionResult::floor_grid,
                    "Pipeline.process(floor_grid=True): a dict, cells (int8, height x width, "
                    "row y, column x: -1 unseen, 0 floor seen free, 100 something standing), "
                    "resolution (m), origin (x, y of cell [0, 0]'s corner, reference frame, m), "
                    "floor_height (m); None without a floor in view")
      .def(
          "to_dict",
          [](const ExtractionResult& r) {
            py::dict d;
            py::list planes;
            for (const auto& p : r.result.planes) planes.append(planeDict(p));
            d["planes"] = planes;
            py::list objects;
            for (const auto& o : r.result.objects) objects.append(objectDict(o));
            d["objects"] = objects;
            d["sensor_to_reference"] = Eigen::Matrix4d(r.result.sensor_to_reference.matrix());
            d["up_in_sensor"] = upInSensorOf(r);
            if (r.levelling) d["levelling"] = levellingOf(r);
            d["stats"] = statsOf(r.result);
            d["warnings"] = r.result.warnings;
            d["timings_ms"] = timingsOf(r.result);
            return d;
          },
          "the structure of hope_extract's JSON output")
      .def("__len__", [](const ExtractionResult& r) { return r.result.planes.size(); })
      .def("__repr__", [](const ExtractionResult& r) {
        return "ExtractionResult(" + std::to_string(r.result.planes.size()) + " planes, " +
               std::to_string(r.result.finite_points) + " finite points)";
      });

  const hope::Params defaults;
  py::class_<PyExtractor>(m, "Extractor",
                          "The HoPE pipeline; reuses its buffers, so keep one per stream")
      .def(py::init(&makeExtractor), py::arg("r_xy") = defaults.r_xy, py::arg("r_z") = defaults.r_z,
           py::arg("normal_radius_factor") = defaults.normal_radius_factor,
           py::arg("min_cluster_voxels") = defaults.min_cluster_voxels,
           py::arg("min_height") = defaults.min_height, py::arg("max_height") = defaults.max_height,
           py::arg("min_area") = defaults.min_area,
           py::arg("merge_fragments") = defaults.merge_fragments,
           py::arg("max_merge_gap") = defaults.max_merge_gap,
           py::arg("bridge_scan_gaps") = defaults.bridge_scan_gaps,
           py::arg("threads") = defaults.threads)
      .def("extract", &PyExtractor::extract, py::arg("points"), py::arg("gravity") = py::none(),
           py::arg("quaternion") = py::none(), py::arg("pose") = py::none(),
           py::arg("transform") = py::none(), py::arg("viewpoint") = py::none(),
           py::arg("level") = false,
           py::arg("level_bound") = hope::LevellingParams().max_correction_deg,
           py::arg("objects") = hope::PipelineOptions().objects,
           py::arg("object_max_height") = hope::ObjectParams().max_height,
           "points: N x 3 or H x W x 3 float32/float64 in the sensor frame. Orientation: at "
           "most one of gravity (accelerometer, 3), quaternion (x y z w), pose (tx ty tz qx qy "
           "qz qw) or transform (4 x 4); none = already z-up (with a warning when the cloud does "
           "not look it). level=True: up from the scene, estimated when no orientation is given "
           "(hope.LevellingError when nothing level is in view), else the given one corrected "
           "by at most level_bound degrees. viewpoint: the sensor's position. objects (on by "
           "default, as in every front-end): also what stands on each plane (result.objects, "
           "result.object_labels, each plane's free_area), points up to object_max_height "
           "above it; objects=False for the planes alone.")
      .def("place", &PyExtractor::place, py::arg("width"), py::arg("depth"),
           py::arg("clearance") = hope::Footprint().clearance, py::arg("plane_id") = py::none(),
           py::arg("max_results") = 5,
           "Where a width x depth footprint fits on the planes of the last "
           "extract(objects=True) call: dicts plane_id, x, y, z, yaw, margin (reference "
           "frame), best first; only on observed surface clear of every object by clearance.")
      .def_property_readonly("r_xy", [](const PyExtractor& e) { return e.params().r_xy; })
      .def_property_readonly("r_z", [](const PyExtractor& e) { return e.params().r_z; });

  py::class_<hope::TrackEvent>(m, "TrackEvent")
      .def_property_readonly("kind",
                             [](const hope::TrackEvent& e) { return hope::toString(e.kind); })
      .def_readonly("id", &hope::TrackEvent::id)
      .def_readonly("other_id", &hope::TrackEvent::other_id)
      .def("__repr__", [](const hope::TrackEvent& e) {
        return std::string("TrackEvent(") + hope::toString(e.kind) +
               ", id=" + std::to_string(e.id) + ", other_id=" + std::to_string(e.other_id) + ")";
      });

  const hope::TrackerOptions tracker_defaults;
  py::class_<hope::PlaneTracker>(m, "PlaneTracker", "Persistent plane ids across frames")
      .def(py::init([](const std::string& mode, double max_height_change, double max_xy_gap,
                       double height_scale, double xy_scale, double max_match_cost,
                       int max_missed_frames, double merge_split_overlap) {
             hope::TrackerOptions o;
             o.mode = hope::trackingModeFromString(mode);
             o.max_height_change = max_height_change;
             o.max_xy_gap = max_xy_gap;
             o.height_scale = height_scale;
             o.xy_scale = xy_scale;
             o.max_match_cost = max_match_cost;
             o.max_missed_frames = max_missed_frames;
             o.merge_split_overlap = merge_split_overlap;
             return hope::PlaneTracker(o);  // validates: ValueError naming the option
           }),
           py::arg("mode") = std::string(hope::toString(tracker_defaults.mode)),
           py::arg("max_height_change") = tracker_defaults.max_height_change,
           py::arg("max_xy_gap") = tracker_defaults.max_xy_gap,
           py::arg("height_scale") = tracker_defaults.height_scale,
           py::arg("xy_scale") = tracker_defaults.xy_scale,
           py::arg("max_match_cost") = tracker_defaults.max_match_cost,
           py::arg("max_missed_frames") = tracker_defaults.max_missed_frames,
           py::arg("merge_split_overlap") = tracker_defaults.merge_split_overlap)
      .def(
          "update",
          [](hope::PlaneTracker& t, ExtractionResult& r, double stamp) {
            return t.update(r.result.planes, stamp);
          },
          py::arg("result"), py::arg("stamp"),
          "gives result's planes their persistent ids (in place); returns the events")
      .def(
          "update",
          [](hope::PlaneTracker& t, std::vector<hope::HorizontalPlane> planes, double stamp) {
            auto events = t.update(planes, stamp);
            return py::make_tuple(planes, events);
          },
          py::arg("planes"), py::arg("stamp"), "returns (planes with persistent ids, events)")
      .def("lost_planes", &hope::PlaneTracker::lostPlanes)
      .def("reset", &hope::PlaneTracker::reset)
      .def_property_readonly(
          "mode", [](const hope::PlaneTracker& t) { return hope::toString(t.options().mode); });

  const hope::SurfaceMapOptions map_defaults;
  py::class_<hope::SurfaceMap>(
      m, "SurfaceMap",
      "One entry per surface, extents grown over frames; its id ends after forget_after_frames "
      "unseen, and it takes a new one when seen again: for planes in a "
      "fixed frame (a pose per frame). See include/hope/surface_map.h")
      .def(py::init([](double cell, double max_height_change, double max_extension_height_change,
                       std::size_t max_entries, double emptied_share, double tilt_error_deg,
                       double height_error, int forget_after_frames) {
             hope::SurfaceMapOptions o;
             o.cell = cell;
             o.max_height_change = max_height_change;
             o.max_extension_height_change = max_extension_height_change;
             o.max_entries = max_entries;
             o.emptied_share = emptied_share;
             o.tilt_error_deg = tilt_error_deg;
             o.height_error = height_error;
             o.forget_after_frames = forget_after_frames;
             return hope::SurfaceMap(o);  // validates: ValueError naming the option
           }),
           py::arg("cell") = map_defaults.cell,
           py::arg("max_height_change") = map_defaults.max_height_change,
           py::arg("max_extension_height_change") = map_defaults.max_extension_height_change,
           py::arg("max_entries") = map_defaults.max_entries,
           py::arg("emptied_share") = map_defaults.emptied_share,
           py::arg("tilt_error_deg") = map_defaults.tilt_error_deg,
           py::arg("height_error") = map_defaults.height_error,
           py::arg("forget_after_frames") = map_defaults.forget_after_frames)
      .def(
          "update",
          [](hope::SurfaceMap& map, ExtractionResult& r, double stamp,
             std::optional<Eigen::Vector3d> viewpoint) {
            return map.update(r.result.planes, stamp, viewpoint);
          },
          py::arg("result"), py::arg("stamp"), py::arg("viewpoint") = py::none(),
          "gives result's planes their map ids (in place); returns the events (new, merged, "
          "ended). viewpoint: the sensor's position in the map's frame, needed to see a space "
          "empty")
      .def(
          "update",
          [](hope::SurfaceMap& map, std::vector<hope::HorizontalPlane> planes, double stamp,
             std::optional<Eigen::Vector3d> viewpoint) {
            auto events = map.update(planes, stamp, viewpoint);
            return py::make_tuple(planes, events);
          },
          py::arg("planes"), py::arg("stamp"), py::arg("viewpoint") = py::none(),
          "returns (planes with map ids, events)")
      .def("surfaces", &hope::SurfaceMap::surfaces,
           "the entries as Planes, oldest first, with their grown outlines")
      .def(
          "reset", [](hope::SurfaceMap& map) { map.reset(); },
          "forgets every entry; ids go on (never given twice)")
      .def("__len__", &hope::SurfaceMap::size);

  py::class_<PyPipeline>(m, "Pipeline", pipelineDoc().c_str())
      .def(py::init(&makePipeline), py::arg("levelling") = std::string("off"))
      .def("process", &PyPipeline::process, py::arg("points"), py::arg("stamp"),
           py::arg("gravity") = py::none(), py::arg("quaternion") = py::none(),
           py::arg("pose") = py::none(), py::arg("transform") = py::none(),
           py::arg("viewpoint") = py::none(), py::arg("placements") = false,
           py::arg("obstacles") = false, py::arg("floor_grid") = false,
           "One frame (stamp in seconds). Orientation: at most one of gravity (an accelerometer "
           "sample in m/s², sensor frame, averaged over gravity_window_s seconds), quaternion, "
           "pose or transform (4 x 4); with levelling='estimate' none. Returns an "
           "ExtractionResult with persistent ids, objects, events; skipped is set when the frame "
           "was skipped. placements=True keeps the frame's points for place(); obstacles=True "
           "gives result.obstacles (see Pipeline's obstacle_min_height, obstacle_max_height); "
           "floor_grid=True gives result.floor_grid (cells of grid_resolution).")
      .def("place", &PyPipeline::place, py::arg("result"), py::arg("width"), py::arg("depth"),
           py::arg("clearance") = hope::Footprint().clearance, py::arg("plane_id") = py::none(),
           py::arg("max_results") = 5,
           "Where a width x depth footprint fits on the planes of `result` (a process(..., "
           "placements=True) result): dicts plane_id, x, y, z, yaw, margin, best first.")
      .def("map_surfaces", &PyPipeline::mapSurfaces,
           "tracking_mode='map': the map's entries as Planes, oldest first")
      .def_property_readonly("tracking_mode", &PyPipeline::trackingMode,
                             "the tracking mode in effect: 'auto' until the first frame, then "
                             "'map' for a pose or transform, 'odometry' otherwise")
      .def_property_readonly(
          "levelling", [](const PyPipeline& p) { return hope::toString(p.options().levelling); });

  m.def("parameters", &parameterTable,
        "every parameter of hope.Pipeline, the nodelet and hope_extract (include/hope/"
        "parameters.h): dicts name, option (hope_extract's), type, default, min, max, unit, "
        "stage, live (the nodelet takes it while running), doc");
  m.def("read_cloud", &readCloud, py::arg("path"),
        "a .pcd (ascii, binary, binary_compressed) or .ply file as hope_extract reads it: "
        "H x W x 3 float32 for an organized cloud, N x 3 otherwise (metres, NaN where nothing "
        "was seen); ValueError/RuntimeError naming what is wrong with the file");
  m.def("depth_to_cloud", &depthToCloud, py::arg("depth"), py::arg("intrinsics"),
        py::arg("scale") = 5000.0,
        "depth (H x W uint16 raw, `scale` units per metre, TUM 5000, OpenNI 1000; or float32 "
        "metres) and intrinsics (fx, fy, cx, cy) -> H x W x 3 float32 points in the camera's "
        "optical frame, NaN where there is no depth");
  m.def(
      "plane_color",
      [](int id) {
        const hope::Rgb c = hope::planeColor(id);
        return py::make_tuple(c.r, c.g, c.b);
      },
      py::arg("id"), "(r, g, b) 0-255 of plane id, as in the pictures and RViz");
}
