#!/usr/bin/env bash
# The overlay test platform experiment (thesis 7.2, figures 7.8 and 7.9): for each trial (a rig_sim
# seed) a handheld bag of layouts/platform.yaml is made, then replayed through the whole graph
# (overlay_platform.launch) with pose_ekf's gyro updates on and off, and once with the true pose
# (the measurement's floor). ar_overlay_platform_monitor writes one CSV per run;
# platform_tables.py turns them into the tables beside the thesis's.
# Usage: overlay_platform.sh OUT_DIR [trials=3] [duration_s=30] [rate=0.5]
# Needs a built workspace (source catkin_ws/devel/setup.bash) with cone_tracker's nodelet.
set -euo pipefail
OUT="$(realpath -m "${1:?usage: overlay_platform.sh OUT_DIR [trials] [duration_s] [rate]}")"
TRIALS="${2:-3}"
DURATION="${3:-30}"
RATE="${4:-0.5}"
HERE="$(cd "$(dirname "$0")" && pwd -P)"
REPLAY="$(realpath "$HERE/../../../launch/replay.launch")"
LAYOUT="$(rospack find rig_model)/config/layouts/platform.yaml"
EKF_BASE="$(rospack find ar_bringup)/config/pose_ekf_rig_sim.yaml"
WORK="$OUT/overlay_platform"
mkdir -p "$WORK"

# One launch on a private master; returns when the bag has played (the player is required).
run() {  # run NAME ARGS...
  local name="$1"; shift
  local port=$((20000 + RANDOM % 20000))
  echo "overlay_platform: $name"
  ROS_MASTER_URI="http://localhost:$port" roslaunch -p "$port" ar_overlay overlay_platform.launch \
    output:="$WORK/$name.csv" rate:="$RATE" "$@" > "$WORK/$name.log" 2>&1 &
  local pid=$!
  local limit
  limit=$(/usr/bin/python3 -c "print(int($DURATION / $RATE) + 90)")
  for ((s = 0; s < limit; s++)); do
    kill -0 "$pid" 2>/dev/null || break
    sleep 1
  done
  if kill -0 "$pid" 2>/dev/null; then
    echo "overlay_platform: $name still running after ${limit} s, stopping it" >&2
    kill -INT "$pid"
  fi
  wait "$pid" || true
}

for ((trial = 1; trial <= TRIALS; trial++)); do
  bag="$WORK/platform_seed$trial.bag"
  [[ -f "$bag" ]] || rosrun rig_sim make_bag --scenario handheld --seed "$trial" --duration "$DURATION" \
    --layout "$LAYOUT" --output "$bag"
  # Three identical cones: the tracker needs the start bearing, atan2(y, x) of the first true position.
  heading="$(/usr/bin/python3 "$HERE/platform_tables.py" --heading "$bag")"
  for gyro in true false; do
    # As in the thesis, the accelerometers stay out of the filter in both runs (ch. 8).
    { cat "$EKF_BASE"; printf 'use_gyro: %s\nuse_accel: false\n' "$gyro"; } > "$WORK/ekf_gyro_$gyro.yaml"
    run "trial${trial}_gyro_${gyro}" bag:="$bag" pose:=ekf heading_prior_deg:="$heading" replay_launch:="$REPLAY" \
      ekf_config:="$WORK/ekf_gyro_$gyro.yaml"
  done
  run "trial${trial}_truth" bag:="$bag" pose:=truth
  rm -f "$bag"  # about 70 MB per second of 1024x768 frames; the seed regenerates it
done
/usr/bin/python3 "$HERE/platform_tables.py" --tables "$WORK" "$TRIALS" | tee "$OUT/overlay_platform.md"
