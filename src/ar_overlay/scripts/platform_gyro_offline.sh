#!/usr/bin/env bash
# The gyro study on the overlay test platform without images (issue 16, item 7): for each trial of an
# overlay_platform.sh run, the tracker output recorded in one run (default: the shipped filter with
# gyros, trial<N>_shipped_gyro_true.outputs.bag) is replayed through ekf_replay with every filter
# configuration, gyros on and off, in the recorded order (the live run's latency) and at the frames'
# stamps (none), and scored by platform_offline.py; so every configuration sees the same cones.
# Usage: platform_gyro_offline.sh PLATFORM_DIR ["TRIAL..."="1 2 3"] [source_run=shipped_gyro_true]
#   PLATFORM_DIR: overlay_platform.sh's OUT_DIR/overlay_platform (its ekf_<config>_gyro_<g>.yaml are used).
# GYRO_OLD_CONFIG=FILE adds FILE (+ use_gyro true/false) as configuration "old": e.g. the rig_sim
# config of the November runs with the options that did not exist then turned off.
set -euo pipefail
DIR="$(realpath "${1:?usage: platform_gyro_offline.sh PLATFORM_DIR [trials] [source_run]}")"
read -r -a TRIALS <<<"${2:-1 2 3}"
SOURCE="${3:-shipped_gyro_true}"
HERE="$(cd "$(dirname "$0")" && pwd -P)"
LAYOUT="$(rospack find rig_model)/config/layouts/platform.yaml"
runs=()
for cfg in "$DIR"/ekf_*_gyro_*.yaml; do
  name="$(basename "$cfg" .yaml)"
  runs+=("${name#ekf_}=$cfg")
done
if [[ -n "${GYRO_OLD_CONFIG:-}" ]]; then
  for g in true false; do
    { cat "$GYRO_OLD_CONFIG"; printf 'use_gyro: %s\n' "$g"; } > "$DIR/old_gyro_$g.yaml"
    runs+=("old_gyro_$g=$DIR/old_gyro_$g.yaml")
  done
fi
[[ ${#runs[@]} -gt 0 ]] || { echo "platform_gyro_offline: no ekf_*_gyro_*.yaml in $DIR (run overlay_platform.sh first)" >&2; exit 1; }
for trial in "${TRIALS[@]}"; do
  bag="$DIR/trial${trial}_${SOURCE}.outputs.bag"
  [[ -f "$bag" ]] || { echo "platform_gyro_offline: $bag is missing" >&2; exit 1; }
  for order in arrival stamp; do
    echo "### Trial $trial, tracker output of the run \`$SOURCE\`, frames in $order order"
    echo
    /usr/bin/python3 "$HERE/platform_offline.py" --bag "$bag" --layout "$LAYOUT" --series \
      --out "$DIR/offline/trial${trial}_$order" --order "$order" "${runs[@]}" "live_${SOURCE}=live"
    echo
  done
done
