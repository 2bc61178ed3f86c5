#include "levelling_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include "hope/depth_image.h"
#include "hope/evaluation/levelling_cases.h"
#include "hope/evaluation/segmentation_metrics.h"
#include "hope/evaluation/table_scenes.h"
#include "hope/extractor.h"
#include "hope/synthetic/scene.h"
#include "hope/tools/report.h"
#include "hope/up_estimation.h"

namespace hope {
namespace tools {

namespace {

using evaluation::angleDeg;
using evaluation::LevellingCase;

constexpr double kDegree = M_PI / 180.0;

std::string fmt(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

double worst(const std::vector<double>& values) {
  return values.empty() ? NAN : *std::max_element(values.begin(), values.end());
}

std::string degreesOrDash(double value) { return std::isnan(value) ? "–" : fmt("%.2f", value); }

// One group's errors, for the summary table.
struct GroupErrors {
  bool exact = true;
  bool camera = true;
  std::vector<double> hope, tilt_search;
  // Real camera clouds: how far the truth's up is from the normal of the level surfaces found
  // with it (the truth's own tilt), and hope's error against those surfaces.
  std::vector<double> truth_tilt, hope_vs_surfaces;
  int cases = 0, hope_refused = 0, tilt_search_failed = 0;
  std::string worst_case;
  double worst_error = -1;
};

// What one cloud gives with each levelling.
struct CaseOutcome {
  std::optional<UpEstimate> estimate;  // nothing when refused
  std::optional<Eigen::Vector3d> tilt_search;
};

Orientation orientationOfUp(const Eigen::Vector3d& up) {
  return Orientation::fromGravity(up.x(), up.y(), up.z());
}

// Scenes that give no evidence of up: each must be refused.
struct RefusalScene {
  std::string name;
  pcl::PointCloud<pcl::PointXYZ> cloud;
};

std::vector<RefusalScene> refusalScenes() {
  using synthetic::Camera;
  using synthetic::Scene;
  using V = Eigen::Vector3d;
  std::vector<RefusalScene> scenes;
  const synthetic::SensorNoise noise = synthetic::SensorNoise::kinectLike();
  auto render = [&](const std::string& name, const Scene& scene, const Camera& camera) {
    const synthetic::RenderedFrame frame = scene.render(camera, noise);
    scenes.push_back({name, depthToCloud(frame.depth, camera.intrinsics, 1.0)});
  };
  Scene wall;
  wall.add<synthetic::Rectangle>(V(3, 0, 1.5), V(0, 1, 0), V(0, 0, 1), 4.0, 1.5,
                                 synthetic::kNoPlane);
  render("a wall, level camera facing it", wall, evaluation::cameraAt(V(0, 0, 1.5), 0, 0, 0));
  render("a wall, level camera 30° to it", wall,
         evaluation::cameraAt(V(0, 0, 1.5), 30 * kDegree, 0, 0));
  Scene sphere;
  sphere.add<synthetic::Sphere>(V(1.5, 0, 1.5), 0.4);
  render("a lone sphere", sphere, evaluation::cameraAt(V(0, 0, 1.5), 0, 0, 0));
  Scene tube;
  tube.add<synthetic::Cylinder>(V(1.5, 0, 0.5), V(1.5, 0, 2.5), 0.3);
  render("a single upright tube", tube, evaluation::cameraAt(V(0, 0, 1.5), 0, 0, 0));
  scenes.push_back({"an empty cloud", {}});
  pcl::PointCloud<pcl::PointXYZ> nan_cloud(640, 480, pcl::PointXYZ(NAN, NAN, NAN));
  scenes.push_back({"640 × 480, every point NaN", nan_cloud});
  return scenes;
}

}  // namespace

std::vector<std::string> writeLevellingSection(std::ostream& md, const std::string& data_dir,
                                               bool quick) {
  std::vector<std::string> headline;
  const Params defaults;
  const LevellingParams levelling = LevellingParams::forExtraction(defaults);
  UpEstimator estimator(levelling);
  Params lidar_params;  // the README's LiDAR setting
  lidar_params.r_xy = 0.3;
  lidar_params.r_z = 0.1;
  const LevellingParams lidar_levelling = LevellingParams::forExtraction(lidar_params);
  UpEstimator lidar_estimator(lidar_levelling);

  std::map<std::string, GroupErrors> groups;
  std::vector<std::string> group_order;
  std::ostringstream real_rows, mosd_rows;
  std::vector<double> mosd_iou_gaps;
  int room_correct_truth = 0, room_correct_estimate = 0, room_truth_regions = 0;
  std::vector<double> estimate_ms;

  auto level = [&](const LevellingCase& c) {
    CaseOutcome outcome;
    const PointsView view = PointsView::of(c.cloud);
    try {
      // A LiDAR's clouds at the documented LiDAR setting (README), cameras' at the defaults.
      outcome.estimate = (c.camera ? estimator : lidar_estimator).estimate(view);
    } catch (const LevellingError&) {
      // Refused: no estimate, counted as such.
    }
    if (c.camera) outcome.tilt_search = evaluation::tiltSearchUp(view, defaults);
    return outcome;
  };

  auto record = [&](const LevellingCase& c, const CaseOutcome& outcome) {
    if (!groups.count(c.group)) group_order.push_back(c.group);
    GroupErrors& g = groups[c.group];
    g.exact = c.exact;
    g.camera = c.camera;
    ++g.cases;
    const Eigen::Vector3d truth = c.trueUp();
    if (outcome.estimate) {
      const double error = angleDeg(outcome.estimate->up_in_sensor, truth);
      g.hope.push_back(error);
      if (error > g.worst_error) g.worst_error = error, g.worst_case = c.name;
    } else {
      ++g.hope_refused;
      g.worst_case = c.name + " (refused)";
      g.worst_error = INFINITY;
    }
    if (outcome.tilt_search) {
      g.tilt_search.push_back(angleDeg(*outcome.tilt_search, truth));
    } else if (c.camera) {
      ++g.tilt_search_failed;
    }
  };

  auto visitSynthetic = [&](const LevellingCase& c) {
    const CaseOutcome outcome = level(c);
    record(c, outcome);
    if (c.group.rfind("demo room", 0) == 0 && outcome.estimate) {
      // The demo room's planes with the true up and with the estimated one.
      Extractor extractor(defaults);
      const PointsView view = PointsView::of(c.cloud);
      for (int pass = 0; pass < 2; ++pass) {
        const Result result =
            extractor.extract(view, pass == 0 ? c.truth : outcome.estimate->orientation);
        std::vector<int> found(result.point_labels.begin(), result.point_labels.end());
        const auto scores = evaluation::hooverScores(c.labels, found);
        (pass == 0 ? room_correct_truth : room_correct_estimate) += int(scores.correct);
        if (pass == 0) room_truth_regions += int(scores.truth_regions);
      }
    }
    std::fprintf(stderr, "levelling: %s %s done\n", c.group.c_str(), c.name.c_str());
  };
  evaluation::syntheticLevellingCases(quick, visitSynthetic);

  std::vector<std::string> missing;
  auto visitReal = [&](const LevellingCase& c) {
    const CaseOutcome outcome = level(c);
    record(c, outcome);
    const Eigen::Vector3d truth = c.trueUp();
    if (c.camera && c.is_table.empty()) {
      // The level surfaces the truth itself gives (planes of 0.1 m² or more, extracted with the
      // true orientation): the area-weighted mean of their normals, in the sensor frame.
      Extractor extractor(defaults);
      const Result with_truth = extractor.extract(PointsView::of(c.cloud), c.truth);
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (const HorizontalPlane& p : with_truth.planes) {
        if (p.area >= 0.1) sum += p.area * p.normal;
      }
      if (sum.norm() > 0) {
        const Eigen::Vector3d surfaces =
            with_truth.sensor_to_reference.linear().transpose() * sum.normalized();
        GroupErrors& g = groups.at(c.group);
        g.truth_tilt.push_back(angleDeg(surfaces, truth));
        if (outcome.estimate) {
          g.hope_vs_surfaces.push_back(angleDeg(outcome.estimate->up_in_sensor, surfaces));
        }
      }
    }
    if (outcome.estimate && c.group.rfind("TUM", 0) == 0) {
      estimate_ms.push_back(outcome.estimate->time_ms);
    }
    const bool sequence_frame = c.group.find("(sequence poses)") != std::string::npos;
    if (!sequence_frame) {
      real_rows << "| " << c.group.substr(0, c.group.find(" (")) << " | " << c.name << " | "
                << (outcome.estimate ? fmt("%.2f", angleDeg(outcome.estimate->up_in_sensor, truth))
                                     : std::string("refused"))
                << " | " << (outcome.estimate ? fmt("%.2f", outcome.estimate->support_area) : "–")
                << " | "
                << (outcome.estimate ? fmt("%.1f", outcome.estimate->angle_spread_deg) : "–")
                << " | "
                << (outcome.estimate ? std::to_string(outcome.estimate->level_heights) : "–")
                << " | "
                << (c.camera
                        ? (outcome.tilt_search ? fmt("%.2f", angleDeg(*outcome.tilt_search, truth))
                                               : std::string("none"))
                        : std::string("n/a"))
                << " |\n";
    }
    if (!c.is_table.empty()) {
      // The table as one plane, with the true up, the estimate and the tilt search.
      Extractor extractor(defaults);
      const PointsView view = PointsView::of(c.cloud);
      auto iouWith = [&](const std::optional<Orientation>& orientation) -> double {
        if (!orientation) return NAN;
        const Result result = extractor.extract(view, *orientation);
        const std::vector<int> labels(result.point_labels.begin(), result.point_labels.end());
        return evaluation::bestPlaneIoU(labels, c.is_table);
      };
      const double with_truth = iouWith(c.truth);
      const double with_estimate =
          iouWith(outcome.estimate ? std::optional<Orientation>(outcome.estimate->orientation)
                                   : std::nullopt);
      const double with_search = iouWith(
          outcome.tilt_search ? std::optional<Orientation>(orientationOfUp(*outcome.tilt_search))
                              : std::nullopt);
      mosd_iou_gaps.push_back(std::isnan(with_estimate) ? 1.0 : with_truth - with_estimate);
      mosd_rows << "| " << c.name << " | " << fmt("%.3f", with_truth) << " | "
                << (std::isnan(with_estimate) ? "refused" : fmt("%.3f", with_estimate)) << " | "
                << (std::isnan(with_search) ? "none" : fmt("%.3f", with_search)) << " |\n";
    }
    std::fprintf(stderr, "levelling: %s %s done\n", c.group.c_str(), c.name.c_str());
  };
  evaluation::realLevellingCases(data_dir, quick ? 10 : 1, visitReal, missing);

  md << "\n## 8. Up from the scene: levelling a cloud without IMU or tf\n\n"
        "Each cloud is given in its sensor's own frame with no orientation, and hope estimates up "
        "from the scene (`hope_extract --level`; `up_estimation.h`): normals of a cubic grid of "
        "2·r_xy over a sample of at most "
     << levelling.max_points
     << " points, the directions many of them share where a camera's "
        "up can be (pitched from 15° up to straight down, rolled up to 35°; a LiDAR's within 45° "
        "of z), each refined to the direction that makes all level patches flattest at once. "
        "Beside it, the search hope_eval used before: up = −y tilted down 0, 15, … 75°, the "
        "first tilt that finds a plane of 0.1 m², then that plane's normal (cameras only). "
        "Error: the angle between the estimated up and the truth, degrees. Default r_xy, r_z "
        "for cameras, the LiDAR setting (0.3, 0.1) for scans. On mOSD the tilt search ends in "
        "the table's own least-squares normal, which is how the truth is defined there.\n\n"
        "| clouds | truth | n | hope refused | hope median | hope worst | worst cloud | "
        "tilt search: no answer | tilt search median | tilt search worst |\n"
        "|---|---|---:|---:|---:|---:|---|---:|---:|---:|\n";
  bool synthetic_met = true, real_met = true;
  std::string synthetic_detail, real_detail;
  for (const std::string& name : group_order) {
    const GroupErrors& g = groups.at(name);
    const bool synthetic = name.find("demo") == 0 || name.find("tracking") == 0 ||
                           name.find("HDL") == 0 || name.find("VLP") == 0;
    md << "| " << name << " | "
       << (synthetic ? "exact"
           : g.exact ? "measured"
                     : "approximate")
       << " | " << g.cases << " | " << g.hope_refused << " | " << degreesOrDash(median(g.hope))
       << " | " << (g.hope_refused ? "refused" : degreesOrDash(worst(g.hope))) << " | "
       << g.worst_case << " | " << (g.camera ? std::to_string(g.tilt_search_failed) : "n/a")
       << " | " << (g.camera ? degreesOrDash(median(g.tilt_search)) : "n/a") << " | "
       << (g.camera ? degreesOrDash(worst(g.tilt_search)) : "n/a") << " |\n";
    if (synthetic) {
      if (g.hope_refused || worst(g.hope) > 0.5) synthetic_met = false;
      synthetic_detail += (synthetic_detail.empty() ? "" : ", ") + name + " " +
                          (g.hope_refused ? std::string("refused ") + std::to_string(g.hope_refused)
                                          : fmt("%.2f", worst(g.hope)) + "°");
    } else if (g.exact) {
      if (g.hope_refused || median(g.hope) > 1.0 || worst(g.hope) > 3.0) real_met = false;
      real_detail += (real_detail.empty() ? "" : "; ") + name.substr(0, name.find(" (")) + " " +
                     fmt("%.2f", median(g.hope)) + "° / " +
                     (g.hope_refused ? std::string("refused") : fmt("%.2f", worst(g.hope)) + "°");
    }
  }
  md << "\nThe truth of the TUM frame and of the recorded sequences is a pose from motion "
        "capture or camera tracking, and under it their own level surfaces are not level. Here, "
        "for "
        "each, the angle between the true up and the area-weighted normal of the planes of "
        "0.1 m² or more extracted with the true pose (the truth's own tilt), and hope's error "
        "against that normal:\n\n| clouds | n | truth's own tilt: median | worst | hope "
        "against its surfaces: median | worst |\n|---|---:|---:|---:|---:|---:|\n";
  for (const std::string& name : group_order) {
    const GroupErrors& g = groups.at(name);
    if (g.truth_tilt.empty()) continue;
    md << "| " << name << " | " << g.truth_tilt.size() << " | "
       << degreesOrDash(median(g.truth_tilt)) << " | " << degreesOrDash(worst(g.truth_tilt))
       << " | " << degreesOrDash(median(g.hope_vs_surfaces)) << " | "
       << degreesOrDash(worst(g.hope_vs_surfaces)) << " |\n";
  }
  if (!missing.empty()) {
    md << "\nAbsent, so not measured here:";
    for (const auto& m : missing) md << " `" << m << "`";
    md << ".\n";
  }
  md << "\nPer real cloud (the sequences' frames are summed up above): the estimate's error, "
        "the level area it rests on (m²), the RMS angle of its cells' normals from up (°), the "
        "distinct heights of its level surfaces, and the tilt search's error.\n\n"
        "| data | cloud | hope error (°) | level area (m²) | spread (°) | heights | tilt search "
        "error (°) |\n|---|---|---:|---:|---:|---:|---:|\n"
     << real_rows.str();
  md << "\nThe TUM frame's truth is its motion-capture pose, under which the desk itself comes "
        "out tilted (see the refinement below): the estimate levels the desk and the floor.\n";

  headline.push_back(std::string(synthetic_met ? "Met" : "**Missed**") +
                     ": up from the scene within 0.5° on every synthetic view and scan (worst: " +
                     synthetic_detail + ").");
  headline.push_back(std::string(real_met ? "Met" : "**Missed**") +
                     ": up from the scene within 1° median and 3° worst on every real cloud "
                     "with a measured up (median / worst: " +
                     real_detail + ").");

  if (!mosd_iou_gaps.empty()) {
    md << "\n### The table with the estimated up (mOSD)\n\nIntersection over union of the best "
          "plane with the labelled table top, with the true up (the table's normal), hope's "
          "estimate and the tilt search.\n\n| scene | true up | hope's up | tilt search |\n"
          "|---|---:|---:|---:|\n"
       << mosd_rows.str();
    const double gap = worst(mosd_iou_gaps);
    headline.push_back(std::string(gap <= 0.01 ? "Met" : "**Missed**") +
                       ": with the estimated up every mOSD table IoU is within 0.01 of the true "
                       "up's (largest loss " +
                       fmt("%.3f", gap) + ").");
  }
  md << "\nThe demo room's planes (Hoover, T = 0.8) over every view above: " << room_correct_truth
     << " of " << room_truth_regions << " true surfaces found correctly with the true up, "
     << room_correct_estimate << " with the estimated up.\n";

  // Refinement of a given orientation.
  md << "\n### Refinement of a given orientation\n\n"
        "`--level` with another orientation option turns the given orientation by at most 5° "
        "(the default bound) so that the level surfaces come out level, and only by more than "
        "they can tell: a surface L across at range d, its ends each off by the sensor's noise "
        "σ(d), shows up to atan(2σ(d) / L) of tilt while level.\n\n";
  {
    std::vector<std::string> absent;
    bool tum_done = false;
    evaluation::realLevellingCases(
        data_dir, 1,
        [&](const LevellingCase& c) {
          tum_done = true;
          const PointsView view = PointsView::of(c.cloud);
          const UpEstimate refined = estimator.refine(view, c.truth);
          Extractor extractor(defaults);
          md << "TUM fr1_desk with its motion-capture pose: " << refined.describe()
             << ".\n\n| plane | height (m) | area (m²) | tilt with the pose (°) | tilt refined (°) "
                "|\n|---|---:|---:|---:|---:|\n";
          const Result before = extractor.extract(view, c.truth);
          const Result after = extractor.extract(view, refined.orientation);
          double desk_before = 0, desk_after = 0;
          for (const HorizontalPlane& p : before.planes) {
            if (p.area < 0.1) continue;
            // The same surface after: the plane nearest in height and centroid.
            const HorizontalPlane* match = nullptr;
            for (const HorizontalPlane& q : after.planes) {
              if (!match ||
                  (q.centroid - p.centroid).norm() < (match->centroid - p.centroid).norm())
                match = &q;
            }
            md << "| " << p.id << " | " << fmt("%.3f", p.height) << " | " << fmt("%.2f", p.area)
               << " | " << fmt("%.2f", p.tilt / kDegree) << " | "
               << (match ? fmt("%.2f", match->tilt / kDegree) : "–") << " |\n";
            if (p.height > 0.6 && p.height < 0.9 && p.tilt / kDegree > desk_before) {
              desk_before = p.tilt / kDegree;
              desk_after = match ? match->tilt / kDegree : NAN;
            }
          }
          headline.push_back(std::string(desk_after < 0.5 ? "Met" : "**Missed**") +
                             ": the TUM desk's tilt with its motion-capture pose refined " +
                             fmt("%.2f", desk_before) + "° → " + fmt("%.2f", desk_after) +
                             "° (target < 0.5°).");
        },
        absent, evaluation::kTumDesk);
    if (!tum_done) md << "TUM fr1_desk absent: not measured.\n";

    // A gravity vector off by 3° (an IMU's typical error), refined, on the synthetic views.
    std::vector<double> before, after;
    int kept = 0;
    evaluation::syntheticLevellingCases(true, [&](const LevellingCase& c) {
      if (!c.camera) return;
      const Eigen::Vector3d truth = c.trueUp();
      const Eigen::Vector3d axis = truth.cross(Eigen::Vector3d(0.3, 0.5, 0.8)).normalized();
      const Eigen::Vector3d off = Eigen::AngleAxisd(3 * kDegree, axis) * truth;
      const UpEstimate refined = estimator.refine(PointsView::of(c.cloud), orientationOfUp(off));
      before.push_back(angleDeg(off, truth));
      after.push_back(angleDeg(refined.up_in_sensor, truth));
      if (!refined.applied) ++kept;
    });
    md << "\nA gravity vector 3° off (an IMU's typical error), refined, on " << before.size()
       << " synthetic camera views: error " << fmt("%.2f", median(before)) << "° → median "
       << fmt("%.2f", median(after)) << "°, worst " << fmt("%.2f", worst(after)) << "°; " << kept
       << " left uncorrected.\n";
  }

  // Refusals.
  md << "\n### Scenes without level evidence\n\nEach must be refused with a clear error, "
        "never answered.\n\n| scene | outcome |\n|---|---|\n";
  bool all_refused = true;
  for (const RefusalScene& scene : refusalScenes()) {
    std::string outcome;
    try {
      const UpEstimate e = estimator.estimate(PointsView::of(scene.cloud));
      outcome = "**answered**: " + e.describe();
      all_refused = false;
    } catch (const LevellingError& error) {
      std::string what = error.what();
      outcome = "refused: " + what.substr(0, what.find(';'));
    }
    md << "| " << scene.name << " | " << outcome << " |\n";
  }
  headline.push_back(std::string(all_refused ? "Met" : "**Missed**") +
                     ": every scene without level evidence (a wall, a sphere, a tube, an empty "
                     "or all-NaN cloud) is refused.");
  if (!estimate_ms.empty()) {
    md << "\nThe estimate took " << fmt("%.2f", median(estimate_ms))
       << " ms on the TUM frame in this run (the benchmark's figure, beside the pipeline's, is "
          "in the README's Speed section).\n";
  }
  return headline;
}

}  // namespace tools
}  // namespace hope
