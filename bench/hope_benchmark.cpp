// Speed of the HoPE pipeline and of each stage, beside PCL's reference implementations of the
// same front-end stages (VoxelGrid, NormalEstimation with a k-d tree) and the paper's two
// reference pipelines built from PCL (region growing, RANSAC), in the same run; the objects
// stage beside the planes, and PCL's tabletop pipeline and LCCP on the same tabletop; and
// the cost of plane tracking per frame (paper's NNPM and the improved tracker).
//
//   build/devel/lib/hope/hope_benchmark [--benchmark_filter=TUM]
//
// Inputs: the TUM freiburg1_desk frame and mOSD's test57 from $HOPE_SHARED_DATA (default
// ../shared/data from the working directory; skipped when absent), and generated on first use: a
// 6-million-point unorganized scan of the synthetic demo room, the pattern object seen by a camera
// and a simulated HDL-64E street scan.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>
#include <thread>
#include <vector>

#include <benchmark/benchmark.h>
#include <pcl/common/transforms.h>
#include <pcl/features/normal_3d.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/search/kdtree.h>
#include <opencv2/imgcodecs.hpp>

#include "hope/depth_image.h"
#include "hope/evaluation/baselines.h"
#include "hope/evaluation/object_baselines.h"
#include "hope/evaluation/table_scenes.h"
#include "hope/extractor.h"
#include "hope/frame_pipeline.h"
#include "hope/plane_tracker.h"
#include "hope/surface_map.h"
#include "hope/synthetic/lidar.h"
#include "hope/synthetic/paper_scenes.h"
#include "hope/synthetic/scene.h"
#include "hope/tools/io.h"
#include "hope/up_estimation.h"
#include "hope_ros/cloud_conversion.h"

namespace {

struct Input {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud{new pcl::PointCloud<pcl::PointXYZ>};
  hope::Orientation pose = hope::Orientation::identity();
  hope::Params params;  // the defaults unless the input needs the paper's fine setting
  std::string error;
};

// A path under $HOPE_SHARED_DATA (default ../shared/data from the working directory).
std::string sharedData(const std::string& relative) {
  const char* shared = std::getenv("HOPE_SHARED_DATA");
  return std::string(shared && *shared ? shared : "../shared/data") + "/" + relative;
}

const Input& tumFrame() {
  static const Input input = [] {
    Input in;
    const std::string dir = sharedData("tum_fr1_desk");
    const cv::Mat depth = cv::imread(dir + "/1305031459.274941.png", cv::IMREAD_ANYDEPTH);
    std::ifstream gt(dir + "/groundtruth.txt");
    if (depth.empty() || !gt) {
      in.error = "TUM frame not found under " + dir + " (set HOPE_SHARED_DATA)";
      return in;
    }
    std::string line;
    double s, tx, ty, tz, qx, qy, qz, qw;
    while (std::getline(gt, line)) {
      if (!line.empty() && line[0] != '#')
        std::istringstream(line) >> s >> tx >> ty >> tz >> qx >> qy >> qz >> qw;
    }
    *in.cloud = hope::depthToCloud(depth, hope::PinholeIntrinsics::tumFreiburg1(), 5000);
    in.pose = hope::Orientation::fromPose(tx, ty, tz, qx, qy, qz, qw);
    return in;
  }();
  return input;
}

// The demo room scanned from above every 2.45 mm over 6 × 6 m: 6.0 M points, z up.
const Input& largeCloud() {
  static const Input input = [] {
    Input in;
    const auto scan =
        hope::synthetic::demoRoom().scanFromAbove(-1.0, -3.0, 5.0, 3.0, 0.00245, 0.002);
    *in.cloud = scan.cloud;
    return in;
  }();
  return input;
}

// The paper's pattern object seen by a 640×480 camera with Kinect-like noise, for the paper's
// fine setting (r_xy 0.009, r_z 0.002): many small planes, many voxels.
const Input& patternView() {
  static const Input input = [] {
    Input in;
    const auto camera = hope::synthetic::patternObjectCamera();
    const auto frame = hope::synthetic::patternObjectScene().render(
        camera, hope::synthetic::SensorNoise::kinectLike());
    *in.cloud = hope::depthToCloud(frame.depth, camera.intrinsics, 1.0);
    in.pose = hope::Orientation::fromTransform(camera.pose);
    in.params.r_xy = 0.009;
    in.params.r_z = 0.002;
    return in;
  }();
  return input;
}

// One revolution of a simulated HDL-64E over the LiDAR street (64 × 2118, organized, sensor
// frame, z up), at the documented LiDAR settings r_xy 0.3, r_z 0.1.
const Input& lidarScan() {
  static const Input input = [] {
    Input in;
    const auto scan = hope::synthetic::scanWithLidar(hope::synthetic::lidarStreet(),
                                                     hope::synthetic::LidarModel::hdl64(),
                                                     hope::synthetic::lidarStreetPose());
    *in.cloud = scan.toCloud();
    in.pose = hope::Orientation::identity().withViewpoint(Eigen::Vector3d::Zero());
    in.params.r_xy = 0.3;
    in.params.r_z = 0.1;
    return in;
  }();
  return input;
}

// mOSD's test57 (mixed and complex clutter on a table, 640×480 Kinect) from
// $HOPE_SHARED_DATA/mosd_dev, with the up every mOSD figure uses (the labelled table top's
// normal, loadLabelledTableScene) and the points and colours as hope_object_baselines reads
// them for PCL's pipelines.
struct TabletopInput : Input {
  hope::tools::InputCloud file;
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  // in the sensor frame
};

const TabletopInput& clutteredTable() {
  static const TabletopInput input = [] {
    TabletopInput in;
    const std::string path = sharedData("mosd_dev/test57.pcd");
    try {
      hope::evaluation::LabelledTableScene scene = hope::evaluation::loadLabelledTableScene(path);
      in.file = hope::tools::loadCloud(path);
      *in.cloud = std::move(scene.cloud);
      in.pose = scene.orientation;
      in.up =
          scene.orientation.sensorToReference().rotation().transpose() * Eigen::Vector3d::UnitZ();
    } catch (const std::exception& e) {
      in.error = std::string(e.what()) + " (set HOPE_SHARED_DATA)";
    }
    return in;
  }();
  return input;
}

const Input& inputFor(int which) {
  return which == 0   ? tumFrame()
         : which == 1 ? largeCloud()
         : which == 2 ? patternView()
         : which == 3 ? lidarScan()
                      : clutteredTable();
}
const char* kInputNames[] = {"TUM_fr1_desk_640x480", "Room_6M_unorganized",
                             "Pattern_object_640x480_r0.009", "HDL64_street_64x2118_r0.3",
                             "mOSD_test57_640x480"};

// The input selected by the benchmark's argument, or nullptr (and the benchmark marked
// skipped, with the reason) when it is unavailable.
const Input* inputOrSkip(benchmark::State& state) {
  const Input& in = inputFor(static_cast<int>(state.range(0)));
  if (!in.error.empty()) {
    state.SkipWithError(in.error.c_str());
    return nullptr;
  }
  return &in;
}

void BM_Hope(benchmark::State& state) {
  const Input* input = inputOrSkip(state);
  if (!input) return;
  const Input& in = *input;
  hope::Params params = in.params;
  // 1: hope's defaults; 0: the paper's pipeline exactly; 2: hope without scan-gap bridging.
  const int mode = static_cast<int>(state.range(1));
  params.merge_fragments = mode != 0;
  params.bridge_scan_gaps = mode == 1;
  params.threads = state.range(2);
  hope::Extractor extractor(params);
  hope::StageTimings sum;
  std::size_t planes = 0, voxels = 0;
  for (auto _ : state) {
    const hope::Result r = extractor.extract(*in.cloud, in.pose);
    benchmark::DoNotOptimize(r.planes.data());
    sum.alignment_ms += r.timings.alignment_ms;
    sum.grid_filter_ms += r.timings.grid_filter_ms;
    sum.normals_ms += r.timings.normals_ms;
    sum.candidates_ms += r.timings.candidates_ms;
    sum.clustering_ms += r.timings.clustering_ms;
    sum.refinement_ms += r.timings.refinement_ms;
    sum.description_ms += r.timings.description_ms;
    sum.merging_ms += r.timings.merging_ms;
    sum.total_ms += r.timings.total_ms;
    planes = r.planes.size();
    voxels = r.voxels;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["align_ms"] = sum.alignment_ms / n;
  state.counters["grid_ms"] = sum.grid_filter_ms / n;
  state.counters["normals_ms"] = sum.normals_ms / n;
  state.counters["cand+clust_ms"] = (sum.candidates_ms + sum.clustering_ms) / n;
  state.counters["refine_ms"] = sum.refinement_ms / n;
  state.counters["describe_ms"] = sum.description_ms / n;
  state.counters["merge_ms"] = sum.merging_ms / n;
  state.counters["planes"] = static_cast<double>(planes);
  state.counters["voxels"] = static_cast<double>(voxels);
  state.counters["total_ms"] = sum.total_ms / n;
  state.counters["points_per_ms"] = static_cast<double>(in.cloud->size()) / (sum.total_ms / n);
  state.SetLabel(std::string(kInputNames[state.range(0)]) +
                 (mode == 0   ? ", paper (no merge, no bridging)"
                  : mode == 2 ? ", no bridging"
                              : "") +
                 (params.threads > 1 ? ", " + std::to_string(params.threads) + " threads" : ""));
}
// The objects standing on the planes and the free areas (ExtractOutputs::objects) beside the
// planes they stand on, in the same calls: the objects stage's time and the rest of the
// extraction's. Arguments: input (0 TUM frame, 3 HDL-64E street scan, 4 mOSD test57).
// Counters: planes_ms (the extraction without the objects stage), objects_ms, their ratio
// objects_per_planes (issue 40's target: at most 1), objects.
void BM_Objects(benchmark::State& state) {
  const Input* input = inputOrSkip(state);
  if (!input) return;
  const Input& in = *input;
  hope::Extractor extractor(in.params);
  hope::ExtractOutputs outputs;
  outputs.objects = true;
  double planes_ms = 0, objects_ms = 0;
  std::size_t objects = 0;
  for (auto _ : state) {
    const hope::Result r = extractor.extract(hope::PointsView::of(*in.cloud), in.pose, outputs);
    benchmark::DoNotOptimize(r.objects.data());
    planes_ms += r.timings.total_ms - r.timings.objects_ms;
    objects_ms += r.timings.objects_ms;
    objects = r.objects.size();
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["planes_ms"] = planes_ms / n;
  state.counters["objects_ms"] = objects_ms / n;
  state.counters["objects_per_planes"] = objects_ms / std::max(planes_ms, 1e-9);
  state.counters["objects"] = static_cast<double>(objects);
  state.SetLabel(kInputNames[state.range(0)]);
}
BENCHMARK(BM_Objects)->Arg(0)->Arg(3)->Arg(4)->Unit(benchmark::kMillisecond)->UseRealTime();

// The reference pipelines for objects on a table, as hope_object_baselines runs them
// (hope/evaluation/object_baselines.h), on the same mOSD scene as BM_Objects/4, from the
// points to the labels. Argument: 0 PCL's classic tabletop pipeline, 1 LCCP.
void BM_PclObjects(benchmark::State& state) {
  const TabletopInput& in = clutteredTable();
  if (!in.error.empty()) {
    state.SkipWithError(in.error.c_str());
    return;
  }
  const bool lccp = state.range(0) == 1;
  int objects = 0;
  for (auto _ : state) {
    const hope::evaluation::ObjectBaselineResult r =
        lccp ? hope::evaluation::lccpObjects(in.file.points, in.file.rgb, in.up)
             : hope::evaluation::tabletopObjects(in.file.points, in.up);
    benchmark::DoNotOptimize(r.point_objects.data());
    objects = r.num_objects;
  }
  state.counters["objects"] = objects;
  state.SetLabel(std::string(kInputNames[4]) + (lccp ? ", LCCP" : ", PCL tabletop pipeline"));
}
BENCHMARK(BM_PclObjects)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// Cores kept busy for as long as it lives, as other nodes on a robot keep them: threads that
// spin, scheduled by the kernel like any other process's.
class BusyCores {
 public:
  explicit BusyCores(int cores) {
    for (int c = 0; c < cores; ++c) {
      spinners_.emplace_back([this] {
        volatile std::uint64_t work = 0;
        while (!stop_.load(std::memory_order_relaxed)) work = work + 1;
      });
    }
  }
  ~BusyCores() {
    stop_ = true;
    for (std::thread& spinner : spinners_) spinner.join();
  }

 private:
  std::atomic<bool> stop_{false};
  std::vector<std::thread> spinners_;
};

// The whole pipeline (hope's defaults) on one thread and on two, on an idle machine and with
// one or two cores kept busy: more threads must never cost time, whatever the load.
// Arguments: input (as BM_Hope), threads, busy cores.
void BM_HopeThreads(benchmark::State& state) {
  const Input* input = inputOrSkip(state);
  if (!input) return;
  const Input& in = *input;
  hope::Params params = in.params;
  params.threads = static_cast<int>(state.range(1));
  hope::Extractor extractor(params);
  extractor.extract(*in.cloud, in.pose);  // buffers grown, pool threads started: steady state
  const int busy = static_cast<int>(state.range(2));
  BusyCores load(busy);
  for (auto _ : state) {
    const hope::Result r = extractor.extract(*in.cloud, in.pose);
    benchmark::DoNotOptimize(r.planes.data());
  }
  state.SetLabel(std::string(kInputNames[state.range(0)]) + ", " + std::to_string(params.threads) +
                 (params.threads == 1 ? " thread" : " threads") +
                 (busy == 0   ? ", idle"
                  : busy == 1 ? ", one core busy"
                              : ", two cores busy"));
}
BENCHMARK(BM_HopeThreads)
    ->Apply([](benchmark::internal::Benchmark* b) {
      for (int input : {0, 1, 3})
        for (int threads : {1, 2})
          for (int busy : {0, 1, 2}) b->Args({input, threads, busy});
    })
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Arguments: input (0 TUM frame, 1 6 M-point room, 2 pattern object at r_xy 0.009, 3 HDL-64E
// street scan), mode (1 hope's defaults; 0 the paper's pipeline: no fragment merge, no scan-gap
// bridging; 2 no bridging), threads (Params::threads).
BENCHMARK(BM_Hope)
    ->Args({0, 1, 1})
    ->Args({0, 0, 1})
    ->Args({0, 1, 2})
    ->Args({1, 1, 1})
    ->Args({1, 0, 1})
    ->Args({1, 1, 2})
    ->Args({2, 1, 1})
    ->Args({2, 0, 1})
    ->Args({3, 1, 1})
    ->Args({3, 2, 1})
    ->Args({3, 0, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Up from the scene (up_estimation.h) on the input in its sensor frame, beside the pipeline's
// time on the same input (BM_Hope): the estimate with no prior, and the refinement of the
// input's own orientation. Counters: the share of the pipeline's time (one thread, defaults)
// measured in the same run. Arguments: input (0 TUM frame, 3 HDL-64E scan), 0 estimate /
// 1 refine.
void BM_UpFromScene(benchmark::State& state) {
  const Input* input = inputOrSkip(state);
  if (!input) return;
  const Input& in = *input;
  const bool refine = state.range(1) == 1;
  const hope::LevellingParams levelling = hope::LevellingParams::forExtraction(in.params);
  hope::UpEstimator estimator(levelling);
  hope::Extractor extractor(in.params);
  // The pipeline's own time on this input, for the share.
  std::vector<double> pipeline_ms;
  for (int k = 0; k < 7; ++k)
    pipeline_ms.push_back(extractor.extract(*in.cloud, in.pose).timings.total_ms);
  std::nth_element(pipeline_ms.begin(), pipeline_ms.begin() + 3, pipeline_ms.end());
  double sum_ms = 0;
  double area = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    const hope::UpEstimate e = refine ? estimator.refine(hope::PointsView::of(*in.cloud), in.pose)
                                      : estimator.estimate(hope::PointsView::of(*in.cloud));
    sum_ms +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    area = e.support_area;
    benchmark::DoNotOptimize(e.up_in_sensor.data());
  }
  const double ms = sum_ms / static_cast<double>(state.iterations());
  state.counters["pipeline_ms"] = pipeline_ms[3];
  state.counters["share_of_pipeline"] = ms / pipeline_ms[3];
  state.counters["level_area_m2"] = area;
  state.SetLabel(std::string(kInputNames[state.range(0)]) +
                 (refine ? ", refining its pose" : ", estimate (no prior)"));
}
BENCHMARK(BM_UpFromScene)
    ->Args({0, 0})
    ->Args({0, 1})
    ->Args({3, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The input transformed into the reference frame and voxelized by PCL with hope's leaf: the
// starting point of each reference stage.
pcl::PointCloud<pcl::PointXYZ>::Ptr alignedForPcl(const Input& in) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr aligned(new pcl::PointCloud<pcl::PointXYZ>);
  pcl::transformPointCloud(*in.cloud, *aligned, in.pose.sensorToReference().cast<float>().matrix());
  return aligned;
}

pcl::VoxelGrid<pcl::PointXYZ> pclGrid(const hope::Params& params) {
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setLeafSize(static_cast<float>(params.r_xy), static_cast<float>(params.r_xy),
                   static_cast<float>(params.r_z));
  return grid;
}

// PCL's VoxelGrid with the same anisotropic leaf, on the already aligned cloud.
void BM_PclVoxelGrid(benchmark::State& state) {
  const Input* input = inputOrSkip(state);
  if (!input) return;
  const Input& in = *input;
  const pcl::PointCloud<pcl::PointXYZ>::Ptr aligned = alignedForPcl(in);
  pcl::VoxelGrid<pcl::PointXYZ> grid = pclGrid(in.params);
  pcl::PointCloud<pcl::PointXYZ> out;
  for (auto _ : state) {
    grid.setInputCloud(aligned);
    grid.filter(out);
    benchmark::DoNotOptimize(out.points.data());
  }
  state.counters["voxels"] = static_cast<double>(out.size());
  state.SetLabel(kInputNames[state.range(0)]);
}
BENCHMARK(BM_PclVoxelGrid)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// PCL's NormalEstimation (k-d tree radius search, δ·r_xy) on the voxel centroids: what the
// paper's implementation runs for its normals stage.
void BM_PclNormals(benchmark::State& state) {
  const Input* input = inputOrSkip(state);
  if (!input) return;
  const Input& in = *input;
  const pcl::PointCloud<pcl::PointXYZ>::Ptr aligned = alignedForPcl(in);
  pcl::VoxelGrid<pcl::PointXYZ> grid = pclGrid(in.params);
  grid.setInputCloud(aligned);
  pcl::PointCloud<pcl::PointXYZ>::Ptr voxels(new pcl::PointCloud<pcl::PointXYZ>);
  grid.filter(*voxels);
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> estimation;
  estimation.setSearchMethod(
      pcl::search::KdTree<pcl::PointXYZ>::Ptr(new pcl::search::KdTree<pcl::PointXYZ>));
  estimation.setRadiusSearch(in.params.normal_radius_factor * in.params.r_xy);
  pcl::PointCloud<pcl::Normal> normals;
  for (auto _ : state) {
    estimation.setInputCloud(voxels);
    estimation.compute(normals);
    benchmark::DoNotOptimize(normals.points.data());
  }
  state.counters["voxels"] = static_cast<double>(voxels->size());
  state.SetLabel(kInputNames[state.range(0)]);
}
BENCHMARK(BM_PclNormals)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// The paper's reference pipelines end to end, as a user would assemble them from PCL: the
// cloud rotated into the gravity frame (pcl::transformPointCloud), PCL's VoxelGrid with hope's
// leaf (r_xy, r_xy, r_z), then region growing (normals from a k-d tree, K = 20, 8°) or RANSAC
// with a plane model perpendicular to z, with the paper's Table 1 settings
// (hope/evaluation/baselines.h). They give planes on voxels only, no per-point labels, so hope
// does more work in its own case. Arg 0: input; arg 1: 0 region growing, 1 RANSAC.
void BM_PclPipeline(benchmark::State& state) {
  const Input* input = inputOrSkip(state);
  if (!input) return;
  const Input& in = *input;
  const bool ransac = state.range(1) == 1;
  const Eigen::Matrix4f to_reference = in.pose.sensorToReference().cast<float>().matrix();
  pcl::VoxelGrid<pcl::PointXYZ> grid = pclGrid(in.params);
  pcl::PointCloud<pcl::PointXYZ>::Ptr aligned(new pcl::PointCloud<pcl::PointXYZ>);
  std::size_t planes = 0, voxels = 0;
  for (auto _ : state) {
    pcl::transformPointCloud(*in.cloud, *aligned, to_reference);
    grid.setInputCloud(aligned);
    hope::evaluation::GriddedCloud gridded;
    grid.filter(*gridded.voxels);
    const hope::evaluation::BaselineResult r =
        ransac ? hope::evaluation::ransacPlanes(gridded, in.params)
               : hope::evaluation::regionGrowingPlanes(gridded, in.params);
    benchmark::DoNotOptimize(r.heights.data());
    planes = r.heights.size();
    voxels = gridded.voxels->size();
  }
  state.counters["planes"] = static_cast<double>(planes);
  state.counters["voxels"] = static_cast<double>(voxels);
  state.SetLabel(std::string(kInputNames[state.range(0)]) +
                 (ransac ? ", PCL RANSAC pipeline" : ", PCL region-growing pipeline"));
}
BENCHMARK(BM_PclPipeline)
    ->Args({0, 0})
    ->Args({0, 1})
    ->Args({1, 0})
    ->Args({1, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The nodelet's work per frame on the TUM frame, beside the core's own time: the PointCloud2
// read in place, extraction, tracking, and building the three output messages (PlaneArray,
// labeled cloud, markers). Within a nodelet manager publishing passes pointers, so this is
// everything the nodelet adds. Target: at most 1.2 × the core.
void BM_NodeletFrame(benchmark::State& state) {
  const Input* input = inputOrSkip(state);
  if (!input) return;
  const Input& in = *input;
  std_msgs::Header camera;
  camera.frame_id = "camera";
  const sensor_msgs::PointCloud2 msg = hope_ros::cloudMessage(*in.cloud, camera);
  hope::Extractor extractor;
  hope::PlaneTracker tracker;
  sensor_msgs::PointCloud2 labeled;
  double core_ms = 0;
  for (auto _ : state) {
    hope::PointsView view;
    if (!hope_ros::viewOf(msg, view).empty()) {
      state.SkipWithError("the PointCloud2 was not readable");
      return;
    }
    hope::Result r = extractor.extract(view, in.pose);
    tracker.update(r.planes, 0.0);
    std_msgs::Header header = msg.header;
    benchmark::DoNotOptimize(hope_ros::toMessage(r, header));
    // As the nodelet does: the labeled cloud published last is refilled once no subscriber
    // holds it (always here).
    hope_ros::fillLabeledCloud(extractor.alignedPoints(), r, view, header, labeled);
    benchmark::DoNotOptimize(labeled.data.data());
    benchmark::DoNotOptimize(hope_ros::planeMarkers(r, header));
    core_ms += r.timings.total_ms;
  }
  state.counters["core_ms"] = core_ms / static_cast<double>(state.iterations());
  state.SetLabel(kInputNames[state.range(0)]);
}
BENCHMARK(BM_NodeletFrame)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();

// What ~obstacles and ~floor_grid add to a frame (FrameOutputs::obstacles and floor_grid): the
// frame pipeline on the input with neither (planes only: no labels, no objects, the cheapest
// frame), with both, and the usual frame (labels and objects, hope's defaults), in turn in each
// iteration, so that all see the same machine. Counters: plain_ms, with_ms, usual_ms,
// added_share (of the plain frame; the target 0.10) and added_share_of_usual, floor (1
// when a floor was in view: without one neither output does any work).
void BM_FloorOutputs(benchmark::State& state) {
  const Input* input = inputOrSkip(state);
  if (!input) return;
  const Input& in = *input;
  hope::PipelineOptions options;
  options.extraction = in.params;
  options.objects = false;
  hope::FramePipeline pipeline(options);
  hope::FrameOutputs plain;
  plain.point_labels = false;
  plain.objects = false;
  hope::FrameOutputs with = plain;
  with.obstacles = true;
  with.floor_grid = true;
  const hope::PointsView view = hope::PointsView::of(*in.cloud);
  double plain_ms = 0, with_ms = 0;
  bool floor = false;
  using Clock = std::chrono::steady_clock;
  // The nodelet's usual frame besides: labels and objects (hope's defaults).
  hope::PipelineOptions usual_options = options;
  usual_options.objects = true;
  hope::FramePipeline usual_pipeline(usual_options);
  double usual_ms = 0;
  int turn = 0;  // the order turned every iteration: none always finds warm caches
  for (auto _ : state) {
    for (int k = 0; k < 3; ++k) {
      const int which = (turn + k) % 3;  // 0 plain, 1 with both outputs, 2 the usual frame
      const auto start = Clock::now();
      const hope::Frame frame =
          which == 2 ? usual_pipeline.processAlone(view, in.pose, hope::FrameOutputs())
                     : pipeline.processAlone(view, in.pose, which == 0 ? plain : with);
      const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
      benchmark::DoNotOptimize(frame.floor_grid.cells.data());
      (which == 0 ? plain_ms : which == 1 ? with_ms : usual_ms) += ms;
      if (which == 1) floor = frame.floor_index >= 0;
    }
    turn = (turn + 1) % 3;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["plain_ms"] = plain_ms / n;
  state.counters["with_ms"] = with_ms / n;
  state.counters["usual_ms"] = usual_ms / n;
  state.counters["added_share"] = (with_ms - plain_ms) / plain_ms;
  state.counters["added_share_of_usual"] = (with_ms - plain_ms) / usual_ms;
  state.counters["floor"] = floor ? 1 : 0;
  state.SetLabel(kInputNames[state.range(0)]);
}
BENCHMARK(BM_FloorOutputs)->Arg(0)->Arg(1)->Arg(3)->Unit(benchmark::kMillisecond)->UseRealTime();

// Tracking cost per frame with 50 planes: a scene of 50 planes (heights 0–2 m, boxes over
// 10 × 10 m) seen in 100 frames with centimetre jitter, a few planes missing in each frame.
// Arg 0: the paper's NNPM; arg 1: the improved tracker.
// 100 frames of a scene of planes seen with centimetre jitter, 5 % of them missing in each
// frame. `layout` 0: 50 planes of 0.2-1.2 m at any height in 10 x 10 m; 1: 1,000 planes of
// 5-35 cm on 8 levels (floor, tables, shelves) in 10 x 10 m; 2: 1,000 fragments of 2-8 cm of
// one 2 x 1 m table top (what r_xy = 1 mm makes of a real table), all competing for each other.
std::vector<std::vector<hope::HorizontalPlane>> makeTrackingFrames(int layout) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> jitter(0.0, 0.01);
  std::vector<hope::HorizontalPlane> scene(layout == 0 ? 50 : 1000);
  for (auto& p : scene) {
    double x, y, w, d;
    if (layout == 0) {
      p.height = 2.0 * u(rng);
      x = 10 * u(rng), y = 10 * u(rng), w = 0.2 + u(rng), d = 0.2 + u(rng);
    } else if (layout == 1) {
      p.height = 0.25 * std::floor(8 * u(rng));
      x = 10 * u(rng), y = 10 * u(rng), w = 0.05 + 0.3 * u(rng), d = 0.05 + 0.3 * u(rng);
    } else {
      p.height = 0.75;
      x = 2 * u(rng), y = u(rng), w = 0.02 + 0.06 * u(rng), d = 0.02 + 0.06 * u(rng);
    }
    p.bbox = {x, y, x + w, y + d};
    p.num_points = 1000;
  }
  std::vector<std::vector<hope::HorizontalPlane>> out(100);
  for (auto& frame : out) {
    for (const auto& p : scene) {
      if (u(rng) < 0.05) continue;  // not seen in this frame
      hope::HorizontalPlane seen = p;
      seen.height += (layout == 2 ? 0.1 : 1.0) * jitter(rng);
      for (double& edge : seen.bbox) edge += (layout == 2 ? 0.1 : 1.0) * jitter(rng);
      frame.push_back(seen);
    }
  }
  return out;
}

// Arg 0: 0 the paper's NNPM, 1 the improved tracker; arg 1: the layout above.
void BM_Tracking(benchmark::State& state) {
  static const std::vector<std::vector<hope::HorizontalPlane>> layouts[3] = {
      makeTrackingFrames(0), makeTrackingFrames(1), makeTrackingFrames(2)};
  const auto& frames = layouts[state.range(1)];
  hope::TrackerOptions options;
  options.mode = state.range(0) == 0 ? hope::TrackingMode::kPaper : hope::TrackingMode::kImproved;
  const char* names[3] = {"50 planes in a room", "1000 planes on 8 levels",
                          "1000 fragments of one table"};
  state.SetLabel(std::string(hope::toString(options.mode)) + ", " + names[state.range(1)]);
  hope::PlaneTracker tracker(options);
  std::size_t f = 0;
  std::vector<hope::HorizontalPlane> planes;
  for (auto _ : state) {
    planes = frames[f++ % frames.size()];  // a copy of small structs: a few µs for 1,000
    benchmark::DoNotOptimize(tracker.update(planes, static_cast<double>(f)));
  }
}
BENCHMARK(BM_Tracking)
    ->Args({0, 0})
    ->Args({1, 0})
    ->Args({0, 1})
    ->Args({1, 1})
    ->Args({0, 2})
    ->Args({1, 2})
    ->Unit(benchmark::kMicrosecond);

// The surface map's update with `range(0)` entries: that many level surfaces of 0.3-1.5 m on 5
// heights in a 20 x 20 m world, seen 8 at a time (a sensor's view; the 8 nearest a spot that
// moves through the world), with 2 cm of jitter in height and position. The map holds all of
// them before timing starts: the cost of a frame against a full map.
void BM_SurfaceMap(benchmark::State& state) {
  const int surfaces = static_cast<int>(state.range(0));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> jitter(0.0, 0.02);
  std::vector<hope::HorizontalPlane> world(static_cast<std::size_t>(surfaces));
  // On a grid, so that no two surfaces at one height overlap: each its own entry.
  const int side = static_cast<int>(std::ceil(std::sqrt(surfaces)));
  for (int k = 0; k < surfaces; ++k) {
    hope::HorizontalPlane& p = world[static_cast<std::size_t>(k)];
    const double x = 20.0 * (k % side) / side, y = 20.0 * (k / side) / side;
    const double w = 0.3 + 1.2 * u(rng) * (20.0 / side - 0.3) / 1.5;
    const double d = 0.3 + 1.2 * u(rng) * (20.0 / side - 0.3) / 1.5;
    p.height = 0.4 * (k % 5);
    p.bbox = {x, y, x + w, y + d};
    p.area = w * d;
    p.centroid = Eigen::Vector3d(x + w / 2, y + d / 2, p.height);
    p.outline = {
        {{x, y, p.height}, {x + w, y, p.height}, {x + w, y + d, p.height}, {x, y + d, p.height}}};
  }
  auto seen = [&](const hope::HorizontalPlane& p) {
    hope::HorizontalPlane q = p;
    const double dz = jitter(rng), dx = jitter(rng), dy = jitter(rng);
    q.translate(Eigen::Vector3d(dx, dy, dz));
    return q;
  };
  hope::SurfaceMap map;
  std::vector<hope::HorizontalPlane> all;
  for (const auto& p : world) all.push_back(seen(p));
  map.update(all, 0.0);
  std::vector<std::vector<hope::HorizontalPlane>> frames(100);
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const Eigen::Vector2d spot(20.0 * u(rng), 20.0 * u(rng));
    std::vector<std::size_t> order(world.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::partial_sort(order.begin(), order.begin() + std::min<std::size_t>(8, order.size()),
                      order.end(), [&](std::size_t a, std::size_t b) {
                        return (world[a].centroid.head<2>() - spot).norm() <
                               (world[b].centroid.head<2>() - spot).norm();
                      });
    for (std::size_t k = 0; k < std::min<std::size_t>(8, order.size()); ++k) {
      frames[f].push_back(seen(world[order[k]]));
    }
  }
  state.SetLabel(std::to_string(map.size()) + " entries, 8 planes a frame");
  std::size_t f = 0;
  std::vector<hope::HorizontalPlane> planes;
  for (auto _ : state) {
    planes = frames[f % frames.size()];
    ++f;
    benchmark::DoNotOptimize(
        map.update(planes, static_cast<double>(f), Eigen::Vector3d(10, 10, 3)));
  }
}
BENCHMARK(BM_SurfaceMap)->Arg(200)->Arg(1000)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
