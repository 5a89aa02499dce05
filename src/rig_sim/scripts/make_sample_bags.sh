#!/usr/bin/env bash
# Regenerates the small committed sample bags (rosbags/README.md says what each is).
# Image noise is off in the samples: noise does not compress, and the samples must stay small.
set -euo pipefail
OUT="${1:?usage: make_sample_bags.sh OUTPUT_DIR}"
mkdir -p "$OUT"
make_sample() {  # name, then make_bag arguments
  local name="$1"; shift
  rosrun rig_sim make_bag "$@" --noise-sigma 0 --compression bz2 --seed 1 --output "$OUT/$name.bag"
  rosrun rig_sim validate_bag "$OUT/$name.bag" | tail -1
}
make_sample handheld_sample --scenario handheld --duration 8 --scale 0.25
make_sample look_away_sample --scenario look_away --duration 14 --scale 0.125
make_sample clutter_sample --scenario clutter --duration 4 --scale 0.25
du -ch "$OUT"/*.bag | tail -1
