#!/usr/bin/env bash
# `make demo`: replays the bundled sample bag through the whole pipeline (launch/demo.launch: the
# nodelets in one manager, rviz, the outputs recorded), headless under Xvfb, then writes the report,
# the overlay video and the rviz screenshot to OUT_DIR (default out/).
# Usage: scripts/demo.sh [OUT_DIR] [BAG]   (needs a built, sourced workspace: `make demo` does both)
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
OUT="$(realpath -m "${1:-$ROOT/out}")"
BAG="$(realpath "${2:-$ROOT/rosbags/handheld_sample.bag}")"
LIB="$ROOT/catkin_ws/devel/lib"
SCREENSHOT_AT_S="${DEMO_SCREENSHOT_AT_S:-6.0}"  # sim seconds into the bag
# The sample's three identical cones look the same every 120 degrees: the tracker starts from the
# camera's bearing around them (handheld_sample.bag starts at 64 degrees; see README.md).
HEADING_PRIOR_DEG="${DEMO_HEADING_PRIOR_DEG:-64}"
mkdir -p "$OUT"
RUN_BAG="$OUT/demo_run.bag"
rm -f "$RUN_BAG" "$OUT/rviz.png"

# The sample bags are bz2-compressed to keep the repository small. rosbag play cannot decompress
# them at the camera rate on a loaded 2-core machine: it falls behind, publishes everything at once
# and never advances /clock. So the demo replays an uncompressed copy.
INPUT="$OUT/.replay_input.bag"
cp "$BAG" "$INPUT"
rosbag decompress -q "$INPUT" >/dev/null
rm -f "${INPUT%.bag}.orig.bag"
# rviz: ar_overlay's overlay.rviz with the view moved to frame this bag's camera path.
RVIZ_CONFIG="$OUT/.demo.rviz"
rosrun ar_demo demo_rviz_config "$(rospack find ar_overlay)/rviz/overlay.rviz" "$INPUT" "$RVIZ_CONFIG"

# A private master on a random port, so a roscore already running is never disturbed; software GL
# for rviz under Xvfb (the overlay nodelet renders through EGL on its own).
export ROS_MASTER_URI="http://localhost:$((20000 + RANDOM % 20000))"
export LIBGL_ALWAYS_SOFTWARE=1
echo "demo: replaying $(basename "$BAG") through launch/demo.launch (log: $OUT/demo_launch.log)"
xvfb-run -a -s "-screen 0 1500x900x24" bash -c '
  set -u
  port="${ROS_MASTER_URI##*:}"
  roslaunch -p "$port" "$1/launch/demo.launch" bag:="$2" record_to:="$3" rviz:=true rviz_config:="$6" heading_prior_deg:="$7" >"$4/demo_launch.log" 2>&1 &
  launch_pid=$!
  rosrun ar_demo grab_screen "$4/rviz.png" --bag "$2" --after-s "$5" --timeout-s 300 &
  grab_pid=$!
  wait "$launch_pid"
  kill "$grab_pid" 2>/dev/null && echo "demo: the replay ended before the rviz screenshot was taken"
  wait "$grab_pid" 2>/dev/null
  true
' _ "$ROOT" "$INPUT" "$RUN_BAG" "$OUT" "$SCREENSHOT_AT_S" "$RVIZ_CONFIG" "$HEADING_PRIOR_DEG"
[[ -f "$RUN_BAG" ]] || { echo "demo: the replay recorded nothing; see $OUT/demo_launch.log" >&2; exit 1; }

SHOT=()
[[ -f "$OUT/rviz.png" ]] && SHOT=(--screenshot "$OUT/rviz.png")
rosrun ar_demo demo_report --run "$RUN_BAG" --truth "$INPUT" --name "$(basename "$BAG")" --out "$OUT" "${SHOT[@]}"
rm -f "$INPUT" "$RVIZ_CONFIG"
REPORT="$OUT/report.md"

# Appendix: the bundled sample bags and the validator's verdict, what the simulated camera sees in
# three scenarios, and pose_math's single-frame uncertainty of the thesis's layout.
{
  echo "## Appendix: sample bags (rig_sim)"
  echo
  for bag in "$ROOT"/rosbags/*.bag; do
    echo "### $(basename "$bag")"
    echo
    echo '```'
    "$LIB/rig_sim/validate_bag" "$bag" 2>&1 | tail -12
    echo '```'
    echo
  done
  echo "## Appendix: simulated camera frames"
  echo
  for spec in "handheld 20.0" "clutter 12.0" "indoor 6.0"; do
    set -- $spec
    "$LIB/rig_sim/render_frame" "$OUT/frame_$1.png" "$2" "$1"
    echo "- [\`frame_$1.png\`](frame_$1.png): scenario $1 at t = $2 s, full size"
  done
  echo
  "$LIB/pose_math/pose_math_demo" | sed 's/^# /## Appendix: /'
} >> "$REPORT"

echo
echo "demo: the results are in $OUT/"
for f in report.md overlay.mp4 overlay_frames overlay_sheet.png rviz.png pose_error.png \
         pose_error_norm.png overlay_error.png gate_rejections.png rates.png demo_run.bag; do
  if [[ -e "$OUT/$f" ]]; then echo "  $OUT/$f"; fi
done
