#!/usr/bin/env bash
# Runs catkin_test_results (its listing of failures), then counts the cases and
# ends with one line "N passed, N failed, N skipped". Non-zero on any failure.
set -uo pipefail
RESULTS_DIR="${1:?usage: test_summary.sh TEST_RESULTS_DIR}"
export PATH=/usr/bin:$PATH
if [[ ! -d "$RESULTS_DIR" ]]; then
  echo "test_summary: no results in $RESULTS_DIR (the tests did not build; see catkin_ws/run_tests.log)"
  echo "0 passed, 1 failed"
  exit 1
fi
if ! catkin_test_results "$RESULTS_DIR" > /dev/null 2>&1; then
  catkin_test_results --verbose "$RESULTS_DIR" 2>&1 | grep -E -A3 '<failure|<error' | head -60
fi
exec /usr/bin/python3 "$(dirname "$0")/test_summary.py" "$RESULTS_DIR"
