// The hope nodelet: a thin adapter between ROS topics and the core's frame pipeline
// (frame_pipeline.h), which decides every frame's orientation, planes, objects and ids. Point
// cloud (and IMU or tf) in; PlaneArray, ObjectArray, labeled cloud and RViz markers out, in the
// reference frame. Parameters: nodelet_settings.cpp; diagnostics: nodelet_status.cpp.
#include "plane_extractor_nodelet.h"

#include <chrono>

#include <tf2_eigen/tf2_eigen.h>
#include <pluginlib/class_list_macros.hpp>

#include "hope_ros/cloud_conversion.h"
#include "hope_ros/object_conversion.h"

namespace hope_ros {

PlaneExtractorNodelet::~PlaneExtractorNodelet() {
  {
    // ~segment requests still waiting return at once ("shutting down").
    std::lock_guard<std::mutex> lock(segment_mutex_);
    shutting_down_ = true;
    segment_cv_.notify_all();
  }
  // No new request, and the service's thread joined: a request in progress has returned.
  segment_srv_.shutdown();
  if (segment_spinner_) segment_spinner_->stop();
  // Inputs first: no callback may run into members being destroyed (the tf filter reads the
  // buffer, the synchronizer calls process()).
  std::lock_guard<std::mutex> lock(connection_mutex_);
  diagnostics_timer_.stop();
  unsubscribe();
  tf_watch_sub_.shutdown();
  std::lock_guard<std::mutex> frame_lock(processing_mutex_);  // a frame in flight ends first
}

void PlaneExtractorNodelet::onInit() {
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  std::vector<std::string> problems, notes;
  settings_ = loadStartupSettings(pnh, getName(), problems, notes);
  for (const auto& p : problems) NODELET_ERROR("hope: %s", p.c_str());
  for (const auto& n : notes) NODELET_WARN("hope: %s", n.c_str());
  if (!settings_.auto_tracking.empty()) NODELET_INFO("hope: %s", settings_.auto_tracking.c_str());
  // surface_map is tracking_mode map under its old name: dynamic_reconfigure reads it at once.
  if (settings_.surface_map && !pnh.hasParam("tracking_mode")) {
    pnh.setParam("tracking_mode", std::string("map"));
  }
  pipeline_ = std::make_unique<hope::FramePipeline>(settings_.pipeline);
  pending_options_ = settings_.pipeline;

  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);
  tf_broadcaster_ = std::make_unique<tf2_ros::TransformBroadcaster>();

  // The extraction parameters come through dynamic_reconfigure, which reads them from the
  // parameter server and calls reconfigure() before the first frame.
  reconfigure_server_ =
      std::make_unique<dynamic_reconfigure::Server<hope::HopeConfig>>(reconfigure_mutex_, pnh);
  reconfigure_server_->setCallback(boost::bind(&PlaneExtractorNodelet::reconfigure, this,
                                               boost::placeholders::_1, boost::placeholders::_2));
  startDiagnostics(nh, pnh);
  const std::string& source = settings_.source;
  if (source == "imu" || source == "fixed" || source == "scene") {
    tf_watch_sub_ = nh.subscribe("/tf", 100, &PlaneExtractorNodelet::onTf, this);
  }
  cloud_topic_ = pnh.resolveName("cloud");
  const ros::SubscriberStatusCallback changed =
      boost::bind(&PlaneExtractorNodelet::connectionChanged, this);
  {
    // Held while advertising: a listener connecting now waits until the publishers exist.
    std::lock_guard<std::mutex> lock(connection_mutex_);
    // Queues of 10 (3 for the ~6 MB labeled clouds): a subscriber in another process that
    // falls behind for a moment (rosbag record on a busy machine) loses no frame.
    planes_pub_ = pnh.advertise<hope::PlaneArray>("planes", 10, changed, changed);
    cloud_pub_ = pnh.advertise<sensor_msgs::PointCloud2>("labeled_cloud", 3, changed, changed);
    markers_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("markers", 10, changed, changed);
    objects_pub_ = pnh.advertise<hope::ObjectArray>("objects", 10, changed, changed);
    obstacles_pub_ = pnh.advertise<sensor_msgs::PointCloud2>("obstacles", 3, changed, changed);
    floor_grid_pub_ = pnh.advertise<nav_msgs::OccupancyGrid>("floor_grid", 3, changed, changed);
  }
  placement_srv_ =
      pnh.advertiseService("find_placement", &PlaneExtractorNodelet::findPlacement, this);
  // On a queue and a thread of its own: a request waits for a cloud the manager delivers.
  ros::NodeHandle segment_nh(pnh);
  segment_nh.setCallbackQueue(&segment_queue_);
  segment_srv_ = segment_nh.advertiseService("segment", &PlaneExtractorNodelet::segment, this);
  segment_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &segment_queue_);
  segment_spinner_->start();
  // Every source: tracking_mode odometry keeps the map without tf (and map or odometry may be
  // chosen live).
  map_pub_ = pnh.advertise<hope::PlaneArray>("map", 1, true);
  map_markers_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("map_markers", 1, true);
  reset_map_srv_ = pnh.advertiseService("reset_map", &PlaneExtractorNodelet::resetMap, this);
  NODELET_INFO("hope: orientation from %s%s, reference frame '%s', %s", source.c_str(),
               settings_.refine ? " refined by the scene" : "", settings_.reference_frame.c_str(),
               settings_.lazy ? "lazy: subscribing to the cloud only while an output has a "
                                "listener (lazy: false processes every cloud)"
                              : "always subscribed");
  if (!settings_.lazy) connectionChanged();
}

void PlaneExtractorNodelet::connectionChanged() {
  std::lock_guard<std::mutex> lock(connection_mutex_);
  const bool wanted = !settings_.lazy || planes_pub_.getNumSubscribers() > 0 ||
                      cloud_pub_.getNumSubscribers() > 0 || markers_pub_.getNumSubscribers() > 0 ||
                      objects_pub_.getNumSubscribers() > 0 ||
                      obstacles_pub_.getNumSubscribers() > 0 ||
                      floor_grid_pub_.getNumSubscribers() > 0 || segments_waiting_ > 0;
  if (wanted == subscribed_) return;
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  const int queue = settings_.cloud_queue;
  if (wanted && settings_.source == "imu") {
    sync_cloud_sub_ = std::make_unique<CloudSubscriber>(pnh, "cloud", queue);
    sync_imu_sub_ = std::make_unique<message_filters::Subscriber<sensor_msgs::Imu>>(pnh, "imu", 50);
    sync_ = std::make_unique<message_filters::Synchronizer<CloudImuPolicy>>(
        CloudImuPolicy(10), *sync_cloud_sub_, *sync_imu_sub_);
    sync_->registerCallback(boost::bind(&PlaneExtractorNodelet::onCloudAndImu, this,
                                        boost::placeholders::_1, boost::placeholders::_2));
  } else if (wanted && settings_.source == "tf") {
    tf_cloud_sub_ = std::make_unique<CloudSubscriber>(pnh, "cloud", queue);
    tf_filter_ = std::make_unique<tf2_ros::MessageFilter<sensor_msgs::PointCloud2>>(
        *tf_cloud_sub_, *tf_buffer_, settings_.reference_frame, settings_.tf_queue, pnh);
    tf_filter_->registerCallback(
        boost::bind(&PlaneExtractorNodelet::onCloud, this, boost::placeholders::_1));
    tf_filter_->registerFailureCallback(boost::bind(&PlaneExtractorNodelet::onCloudWithoutTransform,
                                                    this, boost::placeholders::_1,
                                                    boost::placeholders::_2));
  } else if (wanted) {
    cloud_sub_ = pnh.subscribe("cloud", queue, &PlaneExtractorNodelet::onCloud, this);
  } else {
    unsubscribe();
    std::lock_guard<std::mutex> stats_lock(stats_mutex_);
    gaps_.restart();  // a pause is not a drop
  }
  subscribed_ = wanted;
  NODELET_INFO("hope: %s %s", wanted ? "subscribed to" : "unsubscribed from (no listener left)",
               cloud_topic_.c_str());
}

void PlaneExtractorNodelet::unsubscribe() {
  tf_filter_.reset();  // before the subscriber it reads from
  tf_cloud_sub_.reset();
  sync_.reset();
  sync_cloud_sub_.reset();
  sync_imu_sub_.reset();
  cloud_sub_.shutdown();
}

void PlaneExtractorNodelet::onCloud(const sensor_msgs::PointCloud2ConstPtr& cloud) {
  const std::string& source = settings_.source;
  if (source == "none" || source == "scene") {
    // The sensor at the cloud frame's origin: z-up already (none), or up from the scene.
    process(cloud,
            FrameOrientation{hope::Orientation::identity().withViewpoint(Eigen::Vector3d::Zero()),
                             std::nullopt},
            source == "none" ? frameId(cloud->header.frame_id) : settings_.reference_frame,
            source == "scene");
    return;
  }
  if (source == "fixed") {
    process(cloud, FrameOrientation{settings_.fixed, std::nullopt}, settings_.reference_frame,
            true);
    return;
  }
  // tf: the cloud's frame in the reference frame at the cloud's stamp, translation included.
  // The message filter let the cloud through once that transform was there: no waiting.
  try {
    const geometry_msgs::TransformStamped t = tf_buffer_->lookupTransform(
        settings_.reference_frame, frameId(cloud->header.frame_id), cloud->header.stamp);
    process(
        cloud,
        FrameOrientation{hope::Orientation::fromTransform(tf2::transformToEigen(t)), std::nullopt},
        settings_.reference_frame, false);
  } catch (const std::exception& e) {
    reject(std::string("no transform: ") + e.what());
  }
}

void PlaneExtractorNodelet::onCloudAndImu(const sensor_msgs::PointCloud2ConstPtr& cloud,
                                          const sensor_msgs::ImuConstPtr& imu) {
  FrameOrientation orientation{hope::Orientation::identity(), std::nullopt};
  try {
    orientation = orientationFromImu(*imu, frameId(cloud->header.frame_id));
  } catch (const std::exception& e) {
    reject(std::string("bad IMU message: ") + e.what());
    return;
  }
  // The gravity-aligned frame is broadcast so that RViz can show the outputs with the camera.
  process(cloud, orientation, settings_.reference_frame, true);
}

PlaneExtractorNodelet::FrameOrientation PlaneExtractorNodelet::orientationFromImu(
    const sensor_msgs::Imu& imu, const std::string& cloud_frame) {
  // The fixed rotation from the cloud's frame into the IMU's frame (identity when they agree).
  Eigen::Matrix3d imu_from_cloud = Eigen::Matrix3d::Identity();
  const std::string imu_frame =
      imu.header.frame_id.empty() ? cloud_frame : frameId(imu.header.frame_id);
  if (imu_frame != cloud_frame) {
    // The latest mounting transform, without waiting (the callback thread must not block).
    imu_from_cloud =
        tf2::transformToEigen(tf_buffer_->lookupTransform(imu_frame, cloud_frame, ros::Time(0)))
            .rotation();
  }
  if (imu.orientation_covariance[0] != -1.0) {
    const auto& q = imu.orientation;
    Eigen::Isometry3d world_from_cloud = Eigen::Isometry3d::Identity();
    world_from_cloud.linear() =
        hope::Orientation::fromQuaternion(q.x, q.y, q.z, q.w).sensorToReference().rotation() *
        imu_from_cloud;
    return {hope::Orientation::fromTransform(world_from_cloud), std::nullopt};
  }
  // Gravity only: the pipeline averages the specific force over its window.
  const Eigen::Vector3d a(imu.linear_acceleration.x, imu.linear_acceleration.y,
                          imu.linear_acceleration.z);
  return {hope::Orientation::identity(), Eigen::Vector3d(imu_from_cloud.transpose() * a)};
}

void PlaneExtractorNodelet::process(const sensor_msgs::PointCloud2ConstPtr& cloud,
                                    const FrameOrientation& orientation,
                                    const std::string& reference_frame, bool broadcast) {
  const auto start = std::chrono::steady_clock::now();
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    if (repeated_.repeat(cloud->header.frame_id, cloud->header.stamp.toSec())) {
      NODELET_WARN_THROTTLE(10.0, "hope: cloud of '%s' at %.6f delivered again: skipped",
                            cloud->header.frame_id.c_str(), cloud->header.stamp.toSec());
      return;
    }
    gaps_.arrive(cloud->header.seq, cloud->header.stamp.toSec());
  }
  std::lock_guard<std::mutex> lock(processing_mutex_);
  takePendingOptions();
  hope::PointsView view;
  const std::string problem = viewOf(*cloud, view);
  if (!problem.empty()) {
    reject(problem);
    return;
  }
  // Per-point labels feed the labeled cloud, ~find_placement and ~segment, objects the labeled
  // cloud, ~objects, ~markers, ~segment and the objects' tf frames: each is left out while
  // nothing needs it.
  const bool publish_cloud = cloud_pub_.getNumSubscribers() > 0;
  const bool publish_markers = markers_pub_.getNumSubscribers() > 0;
  const bool publish_objects = objects_pub_.getNumSubscribers() > 0;
  const bool publish_obstacles = obstacles_pub_.getNumSubscribers() > 0;
  const bool publish_grid = floor_grid_pub_.getNumSubscribers() > 0;
  const bool segmenting = segments_waiting_ > 0;
  const bool object_points = publish_objects && switches_.object_points;
  hope::FrameOutputs outputs;
  outputs.obstacles = publish_obstacles;
  outputs.floor_grid = publish_grid;
  outputs.keep_points = switches_.placements || publish_cloud || segmenting || object_points;
  outputs.point_labels = publish_cloud || switches_.placements || segmenting;
  outputs.objects =
      publish_objects || publish_markers || publish_cloud || segmenting || switches_.publish_tf;
  const double stamp = cloud->header.stamp.toSec();
  hope::Frame frame;
  try {
    frame = orientation.specific_force
                ? pipeline_->processWithGravity(view, stamp, *orientation.specific_force, outputs)
                : pipeline_->process(view, stamp, orientation.given, outputs);
  } catch (const std::exception& e) {
    reject(e.what());
    return;
  }
  noteFrame(frame);
  if (!frame.processed) {
    reject("nothing level in view to find up from: " + frame.skipped);
    return;
  }
  if (frame.time_jump) view_centre_.reset();
  for (const auto& w : frame.result.warnings) NODELET_WARN_THROTTLE(30.0, "hope: %s", w.c_str());
  if (broadcast) broadcastReference(cloud->header, frame.orientation);

  std_msgs::Header header = cloud->header;
  header.frame_id = reference_frame;
  const hope::Result& result = frame.result;
  if (planes_pub_.getNumSubscribers() > 0 || !settings_.lazy) {
    planes_pub_.publish(boost::make_shared<hope::PlaneArray>(toMessage(result, header)));
  }
  if (publish_cloud) {
    // The message published last is refilled once nobody holds it (a subscriber's callback,
    // a queue waiting to serialize it): no 6 MB allocation and clearing per VGA frame.
    if (!labeled_cloud_ || labeled_cloud_.use_count() > 1) {
      labeled_cloud_ = boost::make_shared<sensor_msgs::PointCloud2>();
    }
    fillLabeledCloud(frame.points, result, view, header, *labeled_cloud_);
    cloud_pub_.publish(labeled_cloud_);
  }
  if (publish_objects && pipeline_->options().objects) {
    auto objects = boost::make_shared<hope::ObjectArray>(toMessage(result.objects, header));
    if (object_points) attachObjectPoints(frame, *objects);
    objects_pub_.publish(objects);
  }
  if (publish_obstacles) {
    // In the cloud's own frame: a costmap or an octomap takes it as it takes the cloud.
    obstacles_pub_.publish(
        boost::make_shared<sensor_msgs::PointCloud2>(selectedPoints(*cloud, frame.obstacles)));
  }
  if (publish_grid) {
    floor_grid_pub_.publish(
        boost::make_shared<nav_msgs::OccupancyGrid>(toMessage(frame.floor_grid, header)));
  }
  if ((publish_obstacles || publish_grid) && frame.floor_index < 0) {
    // With the map the grid is the map's so far, which this frame leaves as it was.
    const bool mapped = pipeline_->options().identity == hope::Identity::kMap;
    NODELET_WARN_THROTTLE(30.0,
                          "hope: no floor in view (a level surface of 0.25 m² or more seen "
                          "from above): ~obstacles is empty, ~floor_grid %s",
                          mapped ? "unchanged by this frame" : "empty");
  }
  if (publish_markers) {
    auto markers =
        boost::make_shared<visualization_msgs::MarkerArray>(planeMarkers(result, header));
    appendObjectMarkers(result.objects, header, *markers);
    markers_pub_.publish(markers);
  }
  if (!settings_.view_frame.empty()) broadcastView(result, header);
  if (switches_.publish_tf) broadcastThings(result, header);
  if (segmenting) answerSegments(frame, header);
  if (frame.odometry) broadcastOdometry(frame, header);
  if (hope::keepsSurfaceMap(pipeline_->options().identity) &&
      (!frame.events.empty() ||
       ros::WallTime::now() - last_map_publish_ > ros::WallDuration(1.0))) {
    std_msgs::Header map_header = header;
    map_header.frame_id = mapFrame();
    publishMap(map_header);
  }
  last_header_ = header;
  if (switches_.placements) last_frame_ = std::move(frame);
  noteTime(
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
}

void PlaneExtractorNodelet::takePendingOptions() {
  std::lock_guard<std::mutex> lock(pending_mutex_);
  if (!pending_) return;
  // Swapped in between frames, so a frame never sees half a change.
  for (const std::string& note : pipeline_->setOptions(pending_options_)) {
    NODELET_WARN("hope: %s", note.c_str());
  }
  switches_ = pending_switches_;
  last_frame_ = hope::Frame();  // placements answer on frames of the new parameters only
  pending_ = false;
}

void PlaneExtractorNodelet::reconfigure(hope::HopeConfig& config, uint32_t /*level*/) {
  std::lock_guard<std::mutex> lock(pending_mutex_);
  std::vector<std::string> problems;
  pending_options_ = withConfig(pending_options_, config, settings_.source == "tf",
                                settings_.pose_input, problems);
  for (const auto& p : problems) NODELET_WARN("hope: %s", p.c_str());
  pending_switches_.placements = config.placements;
  pending_switches_.object_points = config.object_points;
  pending_switches_.publish_tf = config.publish_tf;
  pending_ = true;
  writeConfig(pending_options_, config);
  NODELET_INFO("hope: parameters: %s, placements %s, object_points %s, publish_tf %s",
               describe(pending_options_).c_str(), pending_switches_.placements ? "on" : "off",
               pending_switches_.object_points ? "on" : "off",
               pending_switches_.publish_tf ? "on" : "off");
}

}  // namespace hope_ros

PLUGINLIB_EXPORT_CLASS(hope_ros::PlaneExtractorNodelet, nodelet::Nodelet)
