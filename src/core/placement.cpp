#include "hope/placement.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace hope {

void validate(const Footprint& footprint) {
  auto fail = [&](const char* what, double value, const char* range) {
    std::ostringstream msg;
    msg << "footprint " << what << " = " << value << " is out of range " << range << " m";
    throw std::invalid_argument(msg.str());
  };
  if (!(footprint.width > 0 && footprint.width <= 100)) fail("width", footprint.width, "(0, 100]");
  if (!(footprint.depth > 0 && footprint.depth <= 100)) fail("depth", footprint.depth, "(0, 100]");
  if (!(footprint.clearance >= 0 && footprint.clearance <= 10)) {
    fail("clearance", footprint.clearance, "[0, 10]");
  }
}

namespace {

// Largest side of a plane's placement grid, in cells: a 20 m floor at 1 cm. A larger plane
// is rasterized with coarser cells, so memory stays bounded (the turned copies of a grid are
// 1.4 times its side: 32 MB of distances at most).
constexpr int kMaxGridSide = 2000;

// One plane's surface as a placement sees it, on square cells in the plane's local xy.
struct SurfaceGrid {
  double cell = 0.01;
  double x0 = 0, y0 = 0;  // local coordinates of cell (0, 0)'s lower-left corner
  cv::Mat observed;       // CV_8U: 255 where the plane has points
  cv::Mat blocked;        // CV_8U: 255 where something stands (grown by the clearance)
  cv::Mat free() const {
    cv::Mat f;
    cv::bitwise_and(observed, ~blocked, f);
    return f;
  }
};

// The grid of `plane`: its bounding box on cells of r_z / 2 (coarser for a very large plane),
// with a cell of border, both masks empty. Its masks are the grid's own, or with `cells` given
// (2 · rows · cols of gridSize, zeroed), headers over those.
void gridSize(const HorizontalPlane& plane, const Params& params, double& cell, int& rows,
              int& cols) {
  const double span = std::max(plane.bbox[2] - plane.bbox[0], plane.bbox[3] - plane.bbox[1]);
  cell = std::max(params.r_z / 2, span / (kMaxGridSide - 4));
  cols = static_cast<int>(std::ceil((plane.bbox[2] - plane.bbox[0]) / cell)) + 3;
  rows = static_cast<int>(std::ceil((plane.bbox[3] - plane.bbox[1]) / cell)) + 3;
}
SurfaceGrid emptyGrid(const HorizontalPlane& plane, const Eigen::Vector3d& local_origin,
                      const Params& params, std::uint8_t* cells = nullptr) {
  SurfaceGrid grid;
  int rows = 0, cols = 0;
  gridSize(plane, params, grid.cell, rows, cols);
  grid.x0 = plane.bbox[0] - local_origin.x() - grid.cell;
  grid.y0 = plane.bbox[1] - local_origin.y() - grid.cell;
  if (cells) {
    grid.observed = cv::Mat(rows, cols, CV_8U, cells);
    grid.blocked = cv::Mat(rows, cols, CV_8U, cells + static_cast<std::size_t>(rows) * cols);
  } else {
    grid.observed = cv::Mat::zeros(rows, cols, CV_8U);
    grid.blocked = cv::Mat::zeros(rows, cols, CV_8U);
  }
  return grid;
}

// The cell of a local point, or false when it is outside the grid (NaN compares false too).
bool cellOf(const SurfaceGrid& grid, const Eigen::Vector3f& q, int& row, int& col) {
  const double c = (q.x() - grid.x0) / grid.cell, r = (q.y() - grid.y0) / grid.cell;
  if (!(c >= 0 && r >= 0 && c < grid.observed.cols && r < grid.observed.rows)) return false;
  col = static_cast<int>(c);
  row = static_cast<int>(r);
  return true;
}

// Grows `standing` by the clearance, as a disc; a cell is blocked when any point within the
// clearance of it stands there (plus half a cell for where in the cell the point lies).
void grownInto(const cv::Mat& standing, double clearance, double cell, cv::Mat& grown) {
  const int radius = static_cast<int>(std::ceil(clearance / cell + 0.5));
  const cv::Mat disc =
      cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1));
  cv::dilate(standing, grown, disc);
}
cv::Mat grownBy(const cv::Mat& standing, double clearance, double cell) {
  cv::Mat grown;
  grownInto(standing, clearance, cell, grown);
  return grown;
}

SurfaceGrid rasterize(const AlignedPoints& points, const HorizontalPlane& plane, int plane_index,
                      const std::vector<std::int32_t>& point_labels,
                      const Eigen::Vector3d& local_origin, const Params& params, double clearance) {
  SurfaceGrid grid = emptyGrid(plane, local_origin, params);
  const int cols = grid.observed.cols, rows = grid.observed.rows;
  cv::Mat standing = cv::Mat::zeros(rows, cols, CV_8U);
  const double base = plane.height - local_origin.z();
  // Anything above the surface that is not the surface blocks it: the objects standing there,
  // and a wall or a shelf board rising over it. The plane's own noise stays below r_z / 2.
  const double low = base + params.r_z / 2, high = base + 2.0;
  // The grid's extent as float bounds, so that most points (outside it) cost two compares.
  const float x_lo = static_cast<float>(grid.x0), y_lo = static_cast<float>(grid.y0);
  const float x_hi = static_cast<float>(grid.x0 + cols * grid.cell);
  const float y_hi = static_cast<float>(grid.y0 + rows * grid.cell);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f q = points[i];
    if (!(q.x() >= x_lo && q.x() < x_hi && q.y() >= y_lo && q.y() < y_hi)) continue;
    const int c = static_cast<int>(std::floor((q.x() - grid.x0) / grid.cell));
    const int r = static_cast<int>(std::floor((q.y() - grid.y0) / grid.cell));
    if (c < 0 || r < 0 || c >= cols || r >= rows) continue;  // NaN compares false too
    if (point_labels[i] == plane_index) {
      grid.observed.at<std::uint8_t>(r, c) = 255;
    } else if (q.z() > low && q.z() <= high) {
      standing.at<std::uint8_t>(r, c) = 255;
    }
  }
  grid.blocked = grownBy(standing, clearance, grid.cell);
  return grid;
}

struct Candidate {
  float margin;
  double x, y, yaw;
};

// Every pose of `footprint` with `yaw` whose cells all lie on `free`, with its margin.
void fitFootprint(const SurfaceGrid& grid, const cv::Mat& free, const cv::Mat& distance,
                  const Footprint& footprint, double yaw, std::vector<Candidate>& out) {
  // Turn the grid by -yaw into a canvas large enough to hold all of it, so that the footprint
  // is axis-aligned there: its fit is then an erosion by a rectangle.
  const cv::Point2f centre(free.cols / 2.0f, free.rows / 2.0f);
  const double degrees = yaw * 180.0 / M_PI;
  cv::Mat turn = cv::getRotationMatrix2D(centre, degrees, 1.0);
  const int side = static_cast<int>(std::ceil(std::hypot(free.cols, free.rows))) + 2;
  turn.at<double>(0, 2) += side / 2.0 - centre.x;
  turn.at<double>(1, 2) += side / 2.0 - centre.y;
  cv::Mat turned_free, turned_distance;
  cv::warpAffine(free, turned_free, turn, cv::Size(side, side), cv::INTER_NEAREST,
                 cv::BORDER_CONSTANT, 0);
  cv::warpAffine(distance, turned_distance, turn, cv::Size(side, side), cv::INTER_NEAREST,
                 cv::BORDER_CONSTANT, 0);
  // One more cell each way than the footprint covers: the turned cells sample the grid.
  const int w = static_cast<int>(std::ceil(footprint.width / grid.cell)) + 1;
  const int d = static_cast<int>(std::ceil(footprint.depth / grid.cell)) + 1;
  cv::Mat fits;
  cv::erode(turned_free, fits, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(w, d)),
            cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, 0);
  cv::Mat back;
  cv::invertAffineTransform(turn, back);
  for (int r = 0; r < fits.rows; ++r) {
    const std::uint8_t* row = fits.ptr<std::uint8_t>(r);
    for (int c = 0; c < fits.cols; ++c) {
      if (!row[c]) continue;
      // The centre of the kernel's window in OpenCV's pixel coordinates (a pixel's index is its
      // centre): with an even size the anchor is right of the middle by half a cell.
      const double tc = c - (w % 2 == 0 ? 0.5 : 0.0), tr = r - (d % 2 == 0 ? 0.5 : 0.0);
      const double gc =
          back.at<double>(0, 0) * tc + back.at<double>(0, 1) * tr + back.at<double>(0, 2);
      const double gr =
          back.at<double>(1, 0) * tc + back.at<double>(1, 1) * tr + back.at<double>(1, 2);
      out.push_back({turned_distance.at<float>(r, c) * static_cast<float>(grid.cell),
                     grid.x0 + (gc + 0.5) * grid.cell, grid.y0 + (gr + 0.5) * grid.cell, yaw});
    }
  }
}

// The grid's columns grow with x and its rows with y, so OpenCV's turn of the image by θ
// (getRotationMatrix2D: [cos sin; -sin cos]) turns xy by -θ; a footprint upright in the turned
// grid has its width along θ in xy.
double yawInPlane(double image_angle) {
  double yaw = std::fmod(image_angle, M_PI);
  if (yaw < 0) yaw += M_PI;
  return yaw;
}

bool carries(const HorizontalPlane& plane) { return plane.facing != Facing::kDown; }

}  // namespace

std::vector<Placement> findPlacements(const AlignedPoints& points,
                                      const std::vector<HorizontalPlane>& planes,
                                      const std::vector<std::int32_t>& point_labels,
                                      const Eigen::Vector3d& local_origin, const Params& params,
                                      const PlacementQuery& query) {
  validate(query.footprint);
  if (point_labels.size() != points.size()) {
    throw std::invalid_argument("findPlacements: one plane label per point is needed");
  }
  if (query.plane_index >= static_cast<int>(planes.size()) || query.plane_index < -1) {
    throw std::invalid_argument("placement plane index " + std::to_string(query.plane_index) +
                                " is not one of the " + std::to_string(planes.size()) + " planes");
  }
  const Footprint& footprint = query.footprint;
  const double longer = std::max(footprint.width, footprint.depth);
  std::vector<int> eligible;
  double widest = 0, longest = 0;
  for (std::size_t p = 0; p < planes.size(); ++p) {
    if (query.plane_index >= 0 && static_cast<int>(p) != query.plane_index) continue;
    if (!carries(planes[p])) continue;
    const double a = planes[p].bbox[2] - planes[p].bbox[0],
                 b = planes[p].bbox[3] - planes[p].bbox[1];
    widest = std::max(widest, std::min(a, b));
    longest = std::max(longest, std::max(a, b));
    // Necessary for the footprint to fit a box of a x b in some turn (the grid search decides
    // the rest): no more area, and the longer side within the diagonal.
    if (footprint.width * footprint.depth <= a * b && longer <= std::hypot(a, b)) {
      eligible.push_back(static_cast<int>(p));
    }
  }
  if (eligible.empty()) {
    std::ostringstream msg;
    msg << "footprint " << footprint.width << " x " << footprint.depth
        << " m is larger than every plane it may go on (";
    if (widest > 0) {
      msg << "the largest spans " << longest << " x " << widest << " m";
    } else {
      msg << "there is none seen from above";
    }
    msg << ")";
    throw std::invalid_argument(msg.str());
  }

  std::vector<Candidate> candidates;
  std::vector<int> candidate_plane;
  for (int p : eligible) {
    const SurfaceGrid grid =
        rasterize(points, planes[p], p, point_labels, local_origin, params, footprint.clearance);
    const cv::Mat free = grid.free();
    cv::Mat distance;
    cv::distanceTransform(free, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    // Every 15°: a 10 cm footprint turned 7.5° off its best yaw moves its corners 0.7 cm.
    for (int step = 0; step < 12; ++step) {
      const double angle = step * M_PI / 12;
      std::vector<Candidate> found;
      fitFootprint(grid, free, distance, footprint, angle, found);
      for (Candidate& c : found) c.yaw = yawInPlane(angle);
      candidates.insert(candidates.end(), found.begin(), found.end());
    }
    candidate_plane.resize(candidates.size(), p);
  }
  // Best first, and no two placements closer than the footprint's longer side: five poses a
  // millimetre apart are one answer.
  std::vector<std::size_t> order(candidates.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return candidates[a].margin > candidates[b].margin;
  });
  std::vector<Placement> placements;
  for (std::size_t k : order) {
    if (placements.size() >= query.max_results) break;
    const Candidate& c = candidates[k];
    const Eigen::Vector3d centre(c.x + local_origin.x(), c.y + local_origin.y(),
                                 planes[candidate_plane[k]].height);
    bool apart = true;
    for (const Placement& chosen : placements) {
      apart = apart && (chosen.centre - centre).head<2>().norm() >= longer;
    }
    if (!apart) continue;
    Placement placement;
    placement.plane_index = candidate_plane[k];
    placement.plane_id = planes[candidate_plane[k]].id;
    placement.centre = centre;
    placement.yaw = c.yaw;
    placement.margin = c.margin;
    placements.push_back(placement);
  }
  return placements;
}

std::vector<double> freeAreas(const AlignedPoints& points,
                              const std::vector<HorizontalPlane>& planes,
                              const std::vector<std::int32_t>& point_labels,
                              const StandingObjects& standing, const Eigen::Vector3d& local_origin,
                              const Params& params) {
  if (point_labels.size() != points.size() || standing.point_objects.size() != points.size()) {
    throw std::invalid_argument("freeAreas: one plane label and one object label per point");
  }
  // All planes in one pass over the points: a plane's own points are its observed cells, the
  // points of the objects standing on it the cells taken.
  // The grids' masks (observed, blocked, blocked grown) in one buffer the thread keeps from
  // frame to frame (as the objects' scratch, cell_keys.h): a street scan's road takes a grid of
  // up to 2000 × 2000 cells, and fresh each frame its pages were faulted in again.
  std::vector<std::size_t> first_cell(planes.size() + 1, 0);
  for (std::size_t p = 0; p < planes.size(); ++p) {
    double cell = 0;
    int rows = 0, cols = 0;
    if (carries(planes[p])) gridSize(planes[p], params, cell, rows, cols);
    first_cell[p + 1] = first_cell[p] + 3 * static_cast<std::size_t>(rows) * cols;
  }
  thread_local std::vector<std::uint8_t> cells;
  cells.resize(first_cell.back());
  for (std::size_t p = 0; p < planes.size(); ++p) {  // observed and blocked empty; grown is written
    const std::size_t size = (first_cell[p + 1] - first_cell[p]) / 3;
    std::fill_n(cells.begin() + static_cast<std::ptrdiff_t>(first_cell[p]), 2 * size, 0);
  }
  std::vector<SurfaceGrid> grids(planes.size());
  for (std::size_t p = 0; p < planes.size(); ++p) {
    if (carries(planes[p])) {
      grids[p] = emptyGrid(planes[p], local_origin, params, cells.data() + first_cell[p]);
    }
  }
  int row = 0, col = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int p = point_labels[i], o = standing.point_objects[i];
    if (p < 0 && o < 0) continue;
    const Eigen::Vector3f q = points[i];
    if (p >= 0 && !grids[p].observed.empty() && cellOf(grids[p], q, row, col)) {
      grids[p].observed.at<std::uint8_t>(row, col) = 255;
    }
    if (o >= 0) {
      SurfaceGrid& under = grids[standing.objects[o].plane_index];
      if (!under.observed.empty() && cellOf(under, q, row, col)) {
        under.blocked.at<std::uint8_t>(row, col) = 255;
      }
    }
  }
  std::vector<double> areas(planes.size(), 0.0);
  for (std::size_t p = 0; p < planes.size(); ++p) {
    if (grids[p].observed.empty()) continue;
    const cv::Mat& observed = grids[p].observed;
    const std::size_t size = observed.total();
    cv::Mat grown(observed.rows, observed.cols, CV_8U, observed.data + 2 * size);
    grownInto(grids[p].blocked, 0.0, grids[p].cell, grown);  // into its cells: no new buffer
    cv::bitwise_not(grown, grown);  // free: observed and not grown, in place
    cv::bitwise_and(observed, grown, grown);
    areas[p] = cv::countNonZero(grown) * grids[p].cell * grids[p].cell;
  }
  return areas;
}

}  // namespace hope
