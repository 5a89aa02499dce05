#!/usr/bin/env bash
# `make eval-tracking`: the tracking figures by the cones in the true view (ar_bringup.evaluation's
# view_* figures) on 512x384 rig_sim bags of the handheld and look_away scenarios with the asymmetric
# layout, replayed through launch/replay.launch. Seeds 4-6 are the held-out ones: nothing was tuned
# on them (pose_ekf's README says which seeds the defaults were chosen on).
# Usage: scripts/eval_tracking.sh [OUT_DIR] [SEED...]   (needs a built, sourced workspace)
# EVAL_SCENARIOS overrides the scenarios, EVAL_ARGS adds replay.launch arguments (e.g. ekf_config:=...).
# EVAL_LAYOUT: the layout file the bags are made with and tracked against; by default asymmetric.yaml,
# except the `site` and `site_look_away` scenarios, which keep their own (rig_model's site.yaml; `make eval-site`).
# site_look_away bags also get the re-acquisition figures after each outage (ar_bringup's site_reacquire.py).
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
OUT="$(realpath -m "${1:-$ROOT/out/eval_tracking}")"
shift || true
SEEDS=("${@:-4 5}")
read -r -a SEEDS <<<"${SEEDS[*]}"
SCENARIOS=(${EVAL_SCENARIOS:-handheld look_away})
LAYOUTS="$(rospack find rig_model)/config/layouts"
layout_of() {  # the scenario's layout file
  if [[ -n "${EVAL_LAYOUT:-}" ]]; then realpath -m "$EVAL_LAYOUT"
  elif [[ "$1" == site* ]]; then echo "$LAYOUTS/site.yaml"
  else echo "$LAYOUTS/asymmetric.yaml"; fi
}
mkdir -p "$OUT"
# A private master on a random port: a roscore already running is never disturbed.
export ROS_MASTER_URI="http://localhost:$((20000 + RANDOM % 20000))"
port="${ROS_MASTER_URI##*:}"

for scenario in "${SCENARIOS[@]}"; do
  LAYOUT="$(layout_of "$scenario")"
  [[ -f "$LAYOUT" ]] || { echo "eval_tracking: EVAL_LAYOUT $LAYOUT: no such file" >&2; exit 2; }
  for seed in "${SEEDS[@]}"; do
    name="${scenario}_seed${seed}"
    bag="$OUT/$name.input.bag"
    rosrun rig_sim make_bag --scenario "$scenario" --seed "$seed" --scale 0.5 --layout "$LAYOUT" \
      --output "$bag" >"$OUT/$name.make_bag.txt" || { cat "$OUT/$name.make_bag.txt" >&2; exit 1; }
    rm -f "$OUT/$name.bag"
    # shellcheck disable=SC2086
    roslaunch -p "$port" "$ROOT/launch/replay.launch" bag:="$bag" layout:="$LAYOUT" overlay:=false \
      required:=true record:="$OUT/$name.bag" ${EVAL_ARGS:-} >"$OUT/$name.launch.log" 2>&1 || true
    rm -f "$bag"
    [[ -f "$OUT/$name.bag" ]] || { echo "eval_tracking: $name recorded nothing; see $OUT/$name.launch.log" >&2; exit 1; }
    rosrun ar_bringup evaluate_bag "$OUT/$name.bag" >"$OUT/$name.txt"
    echo "eval_tracking: $name"
    grep -E '^(position_rms_m|orientation_rms_deg|view_)' "$OUT/$name.txt" |
      grep -E 'position_rms_m|orientation_rms_deg|updated_fraction|frames ' | sed 's/^/  /'
    grep -E '^(tracker_poses|images|outages) ' "$OUT/$name.txt" | sed 's/^/  /' || true
    if [[ "$scenario" == site* ]]; then  # nearly every cone is in the image there: split by the resolved ones too
      for px in 15 30; do
        /usr/bin/python3 "$ROOT/scripts/site_view_split.py" --min-px "$px" "$OUT/$name.bag" | tail -1 |
          sed "s|^.*\.bag:|  cones >= $px px tall:|"
      done
    fi
    if [[ "$scenario" == site_look_away ]]; then
      grep 'outage' "$OUT/$name.make_bag.txt" | sed 's/^make_bag: /  /'
      rosrun ar_bringup site_reacquire.py "$OUT/$name.bag" | sed 's/^/  /' || echo "  site_reacquire.py failed"
    fi
  done
done
