#!/usr/bin/env bash
# Starts rviz with rviz/overlay.rviz under Xvfb, fed by rviz_demo.launch (the overlay
# nodelet and the demo publisher), and saves a screenshot PNG.
# Usage: rviz_screenshot.sh [out.png] [seconds to wait, default 20]
# Needs a built workspace (source catkin_ws/devel/setup.bash) and /usr/bin/python3 with PIL.
set -euo pipefail
OUT="$(realpath -m "${1:-rviz_overlay.png}")"
WAIT="${2:-20}"
PORT=$((20000 + RANDOM % 20000))  # a private master: never disturb one already running
export ROS_MASTER_URI="http://localhost:${PORT}"
export LIBGL_ALWAYS_SOFTWARE=1
xvfb-run -a -s "-screen 0 1500x900x24" bash -c '
  set -u
  roslaunch -p "$1" ar_overlay rviz_demo.launch >/tmp/ar_overlay_rviz_demo.log 2>&1 &
  launch_pid=$!
  sleep "$2"
  /usr/bin/python3 -c "import sys, os; from PIL import ImageGrab; ImageGrab.grab(xdisplay=os.environ[\"DISPLAY\"]).save(sys.argv[1])" "$3"
  status=$?
  kill -INT "$launch_pid"
  wait "$launch_pid" || true
  exit $status
' _ "$PORT" "$WAIT" "$OUT"
echo "rviz_screenshot: wrote $OUT"
