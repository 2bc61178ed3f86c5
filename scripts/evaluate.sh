#!/usr/bin/env bash
# Regenerates docs/evaluation.md and docs/evaluation/*.png: the paper's experiments on
# synthetic scenes with exact ground truth, hope beside PCL RANSAC and region growing; then,
# when ../shared/data/mosd_dev and ../shared/tools/objects_score.py are there, the objects and
# placements on mosd_dev beside PCL's tabletop pipeline and LCCP (scripts/score_objects.sh,
# which also writes docs/objects_mosd.txt and the pictures), appended as its own section.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
build/devel/lib/hope/hope_eval --out docs >/dev/null  # prints the headline claims
data=${HOPE_SHARED_DATA:-../shared/data}
if [ -d "$data/mosd_dev" ] && [ -f ../shared/tools/objects_score.py ]; then
  bash scripts/score_objects.sh >/dev/null
  {
    echo
    echo "## 9. Objects and placements on real tabletops (mOSD), beside PCL's pipelines"
    echo
    echo "What stands on each plane and where a 0.10 × 0.10 m footprint (0.02 m clearance) fits, on"
    echo "the labelled scenes of mosd_dev (gravity from the labelled table), scored per labelled"
    echo "part by \`../shared/tools/objects_score.py\` for hope_extract and for"
    echo "\`hope_object_baselines --method tabletop|lccp\` (PCL's classic tabletop pipeline, LCCP on its"
    echo "prism points: src/evaluation/object_baselines.cpp). Weighted overlap (WOv) weighs each part's"
    echo "best IoU by its size; under: a part whose best object holds half of another part; false: an"
    echo "object mostly on no labelled part. The baselines propose no placements. Then the same with"
    echo "each object's parts labelled as one (the dataset's own merge scheme,"
    echo "\`scripts/mosd_whole_objects.py\`): one object per thing a person would name. Times are one"
    echo "run on this machine, the same input for all. Output of \`bash scripts/score_objects.sh\`"
    echo "([objects_mosd.txt](objects_mosd.txt)):"
    echo
    echo '```'
    cat docs/objects_mosd.txt
    echo '```'
    echo
    echo "The pictures: \`bash scripts/object_pictures.sh\` (objects boxed, placements green)."
    echo
    echo "| mOSD test57 | mOSD test45 | mOSD learn34 |"
    echo "|---|---|---|"
    echo "| ![test57](objects_test57.png) | ![test45](objects_test45.png) | ![learn34](objects_learn34.png) |"
  } >>docs/evaluation.md
else
  echo "evaluate: no $data/mosd_dev or ../shared/tools/objects_score.py: the objects section is left out" >&2
fi
echo "wrote docs/evaluation.md and docs/evaluation/"
