#!/usr/bin/env bash
# The look-away gyro experiment (thesis 7.3, issue 16 item 7): rig_sim's look_away scenario (a 6 s pan
# away from the cones) at 512x384 with the asymmetric layout, replayed live through launch/replay.launch
# for each filter configuration with pose_ekf's gyro updates on and off; ar_bringup.evaluation scores
# the overlay (the 1 m cube on the cones' centroid, px at 1024x768) by the cones in the true view,
# through the outage and after it. Tables by look_away_tables.py in OUT_DIR/look_away_gyro.md.
# Usage: look_away_gyro.sh OUT_DIR [SEED...]   (default seeds 1 2 3; needs a built, sourced workspace)
# LOOK_AWAY_CONFIGS (default "thesis shipped cones"): as in overlay_platform.sh, each
# ar_bringup/config/pose_ekf_rig_sim.yaml with thesis: use_accel false, shipped: unchanged, cones:
# camera_update cones. LOOK_AWAY_SCENARIO overrides the scenario (e.g. handheld).
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd -P)"
ROOT="$(realpath "$HERE/../../..")"
OUT="$(realpath -m "${1:?usage: look_away_gyro.sh OUT_DIR [SEED...]}")"
shift
SEEDS=("${@:-1 2 3}")
read -r -a SEEDS <<<"${SEEDS[*]}"
read -r -a CONFIGS <<<"${LOOK_AWAY_CONFIGS:-thesis shipped cones}"
SCENARIO="${LOOK_AWAY_SCENARIO:-look_away}"
LAYOUT="$(rospack find rig_model)/config/layouts/asymmetric.yaml"
EKF_BASE="$(rospack find ar_bringup)/config/pose_ekf_rig_sim.yaml"
mkdir -p "$OUT"
# A private master on a random port: a roscore already running is never disturbed.
port=$((20000 + RANDOM % 20000))
export ROS_MASTER_URI="http://localhost:$port"

ekf_config() {  # ekf_config NAME GYRO FILE (as overlay_platform.sh)
  local overrides
  case "$1" in
    thesis) overrides='use_accel: false' ;;
    shipped) overrides='' ;;
    cones) overrides='camera_update: cones' ;;
    *) echo "look_away_gyro: LOOK_AWAY_CONFIGS: unknown configuration '$1' (thesis, shipped, cones)" >&2; exit 2 ;;
  esac
  { grep -v '^camera_update:' "$EKF_BASE"
    grep -q '^camera_update:' <<<"$overrides" || grep '^camera_update:' "$EKF_BASE"
    [[ -z "$overrides" ]] || printf '%s\n' "$overrides"
    printf 'use_gyro: %s\n' "$2"; } > "$3"
}

for config in "${CONFIGS[@]}"; do ekf_config "$config" true /dev/null; done  # refuse a bad name before any run

for seed in "${SEEDS[@]}"; do
  bag="$OUT/${SCENARIO}_seed$seed.input.bag"
  [[ -f "$bag" ]] || rosrun rig_sim make_bag --scenario "$SCENARIO" --seed "$seed" --scale 0.5 --layout "$LAYOUT" \
    --output "$bag" >/dev/null
  for config in "${CONFIGS[@]}"; do
    for gyro in true false; do
      name="${SCENARIO}_seed${seed}_${config}_gyro_${gyro}"
      ekf_config "$config" "$gyro" "$OUT/$name.yaml"
      rm -f "$OUT/$name.bag"
      echo "look_away_gyro: $name ($(date -u +%H:%M:%S))"
      roslaunch -p "$port" "$ROOT/launch/replay.launch" bag:="$bag" layout:="$LAYOUT" overlay:=false \
        required:=true ekf_config:="$OUT/$name.yaml" record:="$OUT/$name.bag" >"$OUT/$name.launch.log" 2>&1 || true
      [[ -f "$OUT/$name.bag" ]] || { echo "look_away_gyro: $name recorded nothing; see $OUT/$name.launch.log" >&2; exit 1; }
      rosrun ar_bringup evaluate_bag "$OUT/$name.bag" >"$OUT/$name.txt"
    done
  done
  [[ "${LOOK_AWAY_KEEP_BAGS:-0}" == 1 ]] || rm -f "$bag"  # the seed regenerates it
done
/usr/bin/python3 "$HERE/look_away_tables.py" "$OUT" "$SCENARIO" "${CONFIGS[*]}" "${SEEDS[*]}" | tee "$OUT/look_away_gyro.md"
