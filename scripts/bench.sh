#!/usr/bin/env bash
# Runs every benchmark executable the workspace built (catkin_ws/devel/lib/<pkg>/*_bench).
# Each prints its figure, the baseline's from the same run, their ratio, and
# "BENCH <pkg>.<name> <value> <unit>" lines; this collects the BENCH lines at the end.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
LOG="$(mktemp)"
trap 'rm -f "$LOG"' EXIT
found=0
for exe in "$ROOT"/catkin_ws/devel/lib/*/*_bench; do
  [[ -x "$exe" ]] || continue
  found=1
  echo "=== $(basename "$exe")"
  "$exe" | tee -a "$LOG"
done
[[ $found -eq 1 ]] || { echo "bench: no *_bench executables built" >&2; exit 1; }
echo "=== summary"
grep '^BENCH ' "$LOG"
