#!/usr/bin/env bash
# The overlay test platform experiment (thesis 7.2, figures 7.8 and 7.9): for each trial (a rig_sim
# seed) a handheld bag of layouts/platform.yaml is made, then replayed through the whole graph
# (overlay_platform.launch) with pose_ekf's gyro updates on and off, for each filter configuration,
# and once with the true pose (the measurement's floor). ar_overlay_platform_monitor writes one CSV
# per run; platform_tables.py turns them into the tables beside the thesis's.
# Usage: overlay_platform.sh OUT_DIR [trials=3] [duration_s=30] [rate=0.5]
# PLATFORM_CONFIGS (default "thesis shipped cones") picks the filter configurations, each
# ar_bringup/config/pose_ekf_rig_sim.yaml with:
#   thesis   use_accel: false (the thesis ran without the accelerometers, ch. 8)
#   shipped  nothing changed (camera_update: pose, accelerometer with its bias states)
#   cones    camera_update: cones (the per-cone updates)
# Each run also records the pipeline's outputs (cone_tracker/pose, observations, imu, truth, pose_ekf/pose)
# to <run>.outputs.bag, for platform_offline.py. PLATFORM_KEEP_BAGS=1 keeps the input bags for reuse
# (about 70 MB per second at 1024x768); a bag already in OUT_DIR/overlay_platform is reused.
# PLATFORM_FIRST_TRIAL (default 1) starts at a later trial (seed), e.g. to add one to an earlier run.
# Needs a built workspace (source catkin_ws/devel/setup.bash) with cone_tracker's nodelet.
set -euo pipefail
OUT="$(realpath -m "${1:?usage: overlay_platform.sh OUT_DIR [trials] [duration_s] [rate]}")"
TRIALS="${2:-3}"
DURATION="${3:-30}"
RATE="${4:-0.5}"
read -r -a CONFIGS <<<"${PLATFORM_CONFIGS:-thesis shipped cones}"
HERE="$(cd "$(dirname "$0")" && pwd -P)"
REPLAY="$(realpath "$HERE/../../../launch/replay.launch")"
LAYOUT="$(rospack find rig_model)/config/layouts/platform.yaml"
EKF_BASE="$(rospack find ar_bringup)/config/pose_ekf_rig_sim.yaml"
WORK="$OUT/overlay_platform"
TOPICS=(camera/camera_info cone_tracker/pose cone_tracker/observations pose_ekf/pose imu/data_raw
  rig_sim/ground_truth rig_sim/cones /tf_static /diagnostics)
mkdir -p "$WORK"

# The filter configuration NAME with gyro updates on or off, written to FILE.
ekf_config() {  # ekf_config NAME GYRO FILE
  local overrides
  case "$1" in
    thesis) overrides='use_accel: false' ;;
    shipped) overrides='' ;;
    cones) overrides='camera_update: cones' ;;
    *) echo "overlay_platform: PLATFORM_CONFIGS: unknown configuration '$1' (thesis, shipped, cones)" >&2; exit 2 ;;
  esac
  { grep -v '^camera_update:' "$EKF_BASE"
    grep -q '^camera_update:' <<<"$overrides" || grep '^camera_update:' "$EKF_BASE"
    [[ -z "$overrides" ]] || printf '%s\n' "$overrides"
    printf 'use_gyro: %s\n' "$2"; } > "$3"
}

for config in "${CONFIGS[@]}"; do ekf_config "$config" true /dev/null; done  # refuse a bad name before any run

# One launch on a private master; returns when the bag has played (the player is required).
run() {  # run NAME RECORD(0|1) ARGS...
  local name="$1" record="$2"; shift 2
  local port=$((20000 + RANDOM % 20000))
  echo "overlay_platform: $name ($(date -u +%H:%M:%S))"
  ROS_MASTER_URI="http://localhost:$port" roslaunch -p "$port" ar_overlay overlay_platform.launch \
    output:="$WORK/$name.csv" rate:="$RATE" "$@" > "$WORK/$name.log" 2>&1 &
  local pid=$! rec=""
  if [[ "$record" == 1 ]]; then  # rosbag record waits for the master roslaunch starts
    ROS_MASTER_URI="http://localhost:$port" rosbag record -q -O "$WORK/$name.outputs.bag" "${TOPICS[@]}" \
      > "$WORK/$name.record.log" 2>&1 &
    rec=$!
  fi
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
  if [[ -n "$rec" ]]; then
    kill -INT "$rec" 2>/dev/null || true
    wait "$rec" || true
  fi
}

for ((trial = ${PLATFORM_FIRST_TRIAL:-1}; trial <= TRIALS; trial++)); do
  bag="$WORK/platform_seed$trial.bag"
  [[ -f "$bag" ]] || rosrun rig_sim make_bag --scenario handheld --seed "$trial" --duration "$DURATION" \
    --layout "$LAYOUT" --output "$bag"
  # Three identical cones: the tracker needs the start bearing, atan2(y, x) of the first true position.
  heading="$(/usr/bin/python3 "$HERE/platform_tables.py" --heading "$bag")"
  for config in "${CONFIGS[@]}"; do
    for gyro in true false; do
      cfg="$WORK/ekf_${config}_gyro_$gyro.yaml"
      ekf_config "$config" "$gyro" "$cfg"
      run "trial${trial}_${config}_gyro_${gyro}" 1 bag:="$bag" pose:=ekf heading_prior_deg:="$heading" \
        replay_launch:="$REPLAY" ekf_config:="$cfg"
    done
  done
  run "trial${trial}_truth" 0 bag:="$bag" pose:=truth
  [[ "${PLATFORM_KEEP_BAGS:-0}" == 1 ]] || rm -f "$bag"  # the seed regenerates it
done
/usr/bin/python3 "$HERE/platform_tables.py" --tables "$WORK" "$TRIALS" "${CONFIGS[@]}" | tee "$OUT/overlay_platform.md"
