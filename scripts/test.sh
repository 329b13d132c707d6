#!/usr/bin/env bash
# Sets up the machine, builds, runs every test (gtest and rostest through
# catkin) and prints the verdict as a closing line "N passed, N failed".
# Exits non-zero when any test fails or errors, or when no test ran.
set -uo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
bash "$repo/scripts/setup.sh" || exit 1
bash "$repo/scripts/build.sh" -j2 || { echo "build failed"; echo "0 passed, 1 failed"; exit 1; }

export PATH="/usr/bin:$PATH"
ws="$repo/build/ws"
results="$ws/build/test_results"
rm -rf "$results"
# shellcheck disable=SC1091
set +u; source "$ws/devel/setup.bash"; set -u
# The test binaries are built on both cores, then the tests run one at a
# time: run in parallel, the stability suite took a core from the rostests'
# nodes.
(cd "$ws" && catkin_make tests -j2 -DPYTHON_EXECUTABLE=/usr/bin/python3 2>&1 \
  | grep -E 'error:' || true)
(cd "$ws" && catkin_make run_tests -j1 -DPYTHON_EXECUTABLE=/usr/bin/python3 2>&1 \
  | grep -E '^\[ *(RUN|OK|FAILED|PASSED|SKIPPED)|^\[ROSTEST\]|FAILURE|Failure|Expected|Which is|error:' \
  | grep -v '^\[ *RUN' || true)

if [ ! -d "$results" ]; then
  echo "no test results found"
  echo "0 passed, 1 failed"
  exit 1
fi
exec /usr/bin/python3 "$repo/scripts/summarize_tests.py" "$results"
