// The overlay's labels (hope/tools/overlay.h): each readable, none covering another where the
// picture has room, and the pictures themselves naming every plane and object.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "hope/tools/overlay.h"

namespace {

using hope::tools::LabelRequest;
using hope::tools::layoutLabels;

bool inside(const cv::Rect& r, const cv::Size& image) {
  return r.x >= 0 && r.y >= 0 && r.x + r.width <= image.width && r.y + r.height <= image.height;
}

// A label preferring `first`, else the places 40 px apart along a row below it.
LabelRequest labelAt(cv::Point first, cv::Size size = cv::Size(36, 18)) {
  LabelRequest request{size, {first}};
  for (int k = 1; k <= 6; ++k) request.places.push_back(first + cv::Point(0, 24 * k));
  return request;
}

TEST(LabelLayout, AnUncontestedLabelTakesItsFirstPlace) {
  const cv::Size image(640, 480);
  const std::vector<cv::Rect> placed =
      layoutLabels(image, {labelAt(cv::Point(100, 100)), labelAt(cv::Point(400, 300))});
  ASSERT_EQ(placed.size(), 2u);
  // Centred on the first place: 36 x 18 around (100, 100) and (400, 300).
  EXPECT_EQ(placed[0], cv::Rect(82, 91, 36, 18));
  EXPECT_EQ(placed[1], cv::Rect(382, 291, 36, 18));
}

// Seven tags that all prefer one spot (small objects side by side, as on a cluttered desk):
// each goes to the first of its places that no earlier tag covers, so none covers another.
TEST(LabelLayout, LabelsThatWouldCoverOneAnotherMoveToFreePlaces) {
  const cv::Size image(640, 480);
  std::vector<LabelRequest> requests;
  for (int k = 0; k < 7; ++k) requests.push_back(labelAt(cv::Point(200 + 3 * k, 100)));
  const std::vector<cv::Rect> placed = layoutLabels(image, requests);
  ASSERT_EQ(placed.size(), requests.size());
  for (std::size_t a = 0; a < placed.size(); ++a) {
    EXPECT_TRUE(inside(placed[a], image)) << a;
    for (std::size_t b = a + 1; b < placed.size(); ++b) {
      EXPECT_EQ((placed[a] & placed[b]).area(), 0) << a << " and " << b;
    }
  }
  // The k-th goes to its k-th place: the earlier ones hold the rows above.
  for (std::size_t k = 0; k < placed.size(); ++k) {
    EXPECT_EQ(placed[k].y, 91 + 24 * static_cast<int>(k)) << k;
  }
}

// A label near the border (an object at the image's edge) is moved inside the image.
TEST(LabelLayout, ALabelAtTheBorderStaysInsideThePicture) {
  const cv::Size image(640, 480);
  const std::vector<cv::Rect> placed = layoutLabels(
      image, {labelAt(cv::Point(2, -5)), labelAt(cv::Point(639, 479), cv::Size(80, 20))});
  EXPECT_EQ(placed[0], cv::Rect(0, 0, 36, 18));
  EXPECT_EQ(placed[1], cv::Rect(560, 460, 80, 20));
}

// With no free place, a label still goes in (a crowded picture names everything), where it
// covers the least of the others.
TEST(LabelLayout, WithNoFreePlaceALabelCoversTheLeast) {
  const cv::Size image(100, 40);
  const LabelRequest wide{cv::Size(100, 20), {cv::Point(50, 10)}};
  const LabelRequest half{cv::Size(50, 20), {cv::Point(25, 30)}};
  // Its places: over the wide label (covers 1000 px²), over the half one (500 px²).
  const LabelRequest last{cv::Size(50, 20), {cv::Point(50, 10), cv::Point(75, 30)}};
  const std::vector<cv::Rect> placed = layoutLabels(image, {wide, half, last});
  EXPECT_EQ(placed[2], cv::Rect(50, 20, 50, 20));  // free after all: the half's other side
  const LabelRequest crowded{cv::Size(50, 20), {cv::Point(50, 10), cv::Point(50, 30)}};
  const std::vector<cv::Rect> full = layoutLabels(image, {wide, half, last, crowded});
  // Over the wide label: 1000 px²; lower down: the half's 25 columns and last's 25, 1000 px².
  // Equal: the first place.
  EXPECT_EQ(full[3], cv::Rect(25, 0, 50, 20));
  const std::vector<cv::Rect> none = layoutLabels(image, {LabelRequest{cv::Size(10, 10), {}}});
  EXPECT_EQ(none[0], cv::Rect(45, 15, 10, 10));
}

}  // namespace
