#!/usr/bin/env bash
# The suite built with AddressSanitizer + UndefinedBehaviorSanitizer (GCC). Any sanitizer report
# fails the run (UBSan does not recover; ASan aborts; leak checking is on for hope's own
# executables).
#
#   bash scripts/sanitize.sh          what CI runs (about 30 min here): the core, the tools and
#                                     the unit tests, built on the core's portable scalar paths
#                                     (what an ARM robot runs; src/core/simd.h) in
#                                     build_asan_scalar. The SSE2 paths run under ASan + UBSan in
#                                     scripts/fuzz.sh, whose targets run the whole extractor.
#   bash scripts/sanitize.sh --whole  everything (about 60 min here, over CI's limit beside the
#                                     rest): the SSE2 paths, every unit test case, the rostests
#                                     and the Python tests, in build_asan.
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
root=$(cd "$(dirname "$0")/.." && pwd)
whole=0
case "${1:-}" in
  "") ;;
  --whole) whole=1 ;;
  *) echo "usage: scripts/sanitize.sh [--whole]" >&2; exit 2 ;;
esac
# GCC warns of maybe-uninitialized falsely under ASan (boost::optional, std::regex).
flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -Wno-maybe-uninitialized"
link="-fsanitize=address,undefined"
# -g1 (line tables, enough for the sanitizers' stack traces) instead of -g: the full debug
# information of PCL's and Eigen's templates made this build three times the plain one.
common=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG"
  -DPYTHON_EXECUTABLE=/usr/bin/python3 "-DCMAKE_CXX_FLAGS=$flags" "-DCMAKE_EXE_LINKER_FLAGS=$link"
  "-DCMAKE_SHARED_LINKER_FLAGS=$link" "-DCMAKE_MODULE_LINKER_FLAGS=$link")
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# The core's unit tests: CMakeLists.txt's HOPE_TESTS, so that a new one is sanitized too.
unit_tests=$(sed -n '/set(HOPE_TESTS/,/)/p' "$root/CMakeLists.txt" | sed 's/set(HOPE_TESTS//; s/)//' |
  tr -s ' \n' ' ')
if [ -z "${unit_tests// /}" ]; then
  echo "sanitize: no HOPE_TESTS list found in CMakeLists.txt" >&2
  exit 1
fi

if [ "$whole" = 0 ]; then
  out=$root/build_asan_scalar
  cmake -S "$root" -B "$out" "${common[@]}" -Dhope_SCALAR_ONLY=ON >/dev/null
  # shellcheck disable=SC2086
  cmake --build "$out" -j2 --target $unit_tests >/dev/null
  cd "$out"
  # The cases left out take a second or more each in the plain build and 15-25 times that here:
  # they replay real sequences and whole scenes for quality figures (the plain suite runs them).
  # Their stages run here in the cases kept; every hostile-input case (bad input, broken
  # sequences, the CLI's refusals) and every plain-against-optimized comparison is kept.
  heavy="Tracking.FloorAndTableKeepOneIdThroughAnOcclusionWhenFragmentsMerge"
  heavy+=":PlaneTracker.PairsPlanesThatMovedApartAsFarAsTheCostAllowsAndNoFurther"
  heavy+=":PlaneTrackerOnRenderedScenes.*:UpEstimationOnRealData.*"
  heavy+=":UpEstimation.AStoreyOfStairsGivesTheTreadsOrARefusalNeverTheRisers"
  heavy+=":UpEstimation.DemoRoomAtEveryPitchAndRollWithinHalfADegree"
  heavy+=":UpEstimation.AFlightsSlopeIsNotTakenForLevel"
  heavy+=":Cli.LevelFindsUpRefinesAGivenOneAndSpeaksUpWhenNoneIsGiven"
  heavy+=":Sequence.TheFoldersOwnIntrinsicsAreReadAndNamed"
  heavy+=":Sequence.PosesThatNeverMoveGetTheTrackerNotTheMap"
  heavy+=":Sequence.TumFolderWithGroundTruthKeepsTheTableIdAtItsRealHeight"
  heavy+=":Sequence.AccelerometerGivesHeightsRelativeToTheCamera:Sequence.EveryNthFrameOnly"
  heavy+=":StandingObjects.ACabinetOnTheFloorIsOneObjectFromEverySide"
  heavy+=":StandingObjects.AnUpOneDegreeOffMakesNoObjectOfTheFloor"
  heavy+=":StandingObjects.ABottleAgainstTheFrontOfABoxStaysApartFromIt"
  heavy+=":FragmentMerging.RealTabletopScenesGiveTheWholeTableAsOnePlane"
  heavy+=":FramePipeline.TheMapAndTheTrackerKeepTheFloorsAndTablesIdOverAPan"
  heavy+=":FramePipeline.PlacementsAreAnsweredOnTheFrameAskedAfterLaterFrames"
  heavy+=":FramePipeline.WithTheMapTheFloorGridAddsUpThePansFrames"
  heavy+=":FramePipeline.TheMapForgetsASurfaceOutOfViewLongerThanItsMemory"
  heavy+=":SurfaceMap.ARobotTurningInPlaceMapsWhatTheSameSceneSeenAtOnceGives"
  echo "== unit tests under ASan + UBSan, on the scalar paths"
  regex=$(echo $unit_tests | sed 's/ /|/g')
  GTEST_FILTER="-$heavy" ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
    ctest --output-on-failure -R "_ctest_hope_gtest_($regex)\$"
  exit 0
fi

out=$root/build_asan
cmake -S "$root" -B "$out" "${common[@]}" >/dev/null
cmake --build "$out" -j2 >/dev/null
cmake --build "$out" -j2 --target tests >/dev/null
export ROS_HOSTNAME=localhost ROS_HOME="$out/ros_home" ROS_LOG_DIR="$out/ros_home/log"
asan_runtime=$(gcc -print-file-name=libasan.so)
cd "$out"
# The downstream test installs and builds against the install space; an instrumented install
# is no use to an uninstrumented downstream build, so it runs in the ordinary suite only.
# The quality guard measures every figure over whole data sets, and the docs-examples test runs
# every command the docs print: 24 and 9 minutes under ASan; the ordinary (release) suite runs
# both. Under the sanitizers the same code paths run in the unit, CLI and hostile-input tests.
echo "== unit tests under ASan + UBSan"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 ctest --output-on-failure \
  -E "rostest|python_|downstream_install|quality_guard"
# The nodelet manager and the other ROS binaries from Debian are not instrumented, so the ASan
# runtime is preloaded into every process of the rostests (leak checking off for them).
echo "== rostests under ASan + UBSan (runtime preloaded into the ROS processes)"
LD_PRELOAD=$asan_runtime ASAN_OPTIONS=detect_leaks=0:abort_on_error=1:verify_asan_link_order=0 \
  ctest --output-on-failure -R rostest
# python3 loads libstdc++ only with the bindings, after the ASan runtime has looked for the
# real __cxa_throw (ASan then aborts on the first C++ exception): preload libstdc++ too.
echo "== the Python tests under ASan + UBSan (runtime preloaded into the interpreter)"
LD_PRELOAD="$asan_runtime $(gcc -print-file-name=libstdc++.so.6)" \
  ASAN_OPTIONS=detect_leaks=0:abort_on_error=1:verify_asan_link_order=0 \
  ctest --output-on-failure -R "^python_" -E "^python_docs_examples$"
