#!/usr/bin/env bash
# Builds evsim and core_tests with AddressSanitizer and UndefinedBehaviorSanitizer
# in their own workspace (build/asan_ws) and runs the input fuzz test and the
# loader tests under them: every variant evsim is given runs sanitized, and a
# report (a leak, an overflow, undefined behaviour) fails the case. Long (the
# build takes 10-20 minutes on 2 cores); not part of CI.
# Usage: scripts/sanitize.sh [gtest filter]   (default: the fuzz and loader tests)
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
ws="$repo/build/asan_ws"
filter=${1:-'Fuzz.*:Loader.*:CenterlineVtk.*:StateFile.*:Sleep.AStateFileKeepsTheSleep'}
flags="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined"
# The workspace, its links to the repository and the build: build.sh's, in build/asan_ws.
EVSIM_WS="$ws" bash "$repo/scripts/build.sh" core_tests evsim -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined"
# Leaks in the libraries evsim links (VTK, urdfdom, yaml-cpp) at exit are
# theirs; errors of memory and undefined behaviour stop the run.
export ASAN_OPTIONS=detect_leaks=0:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
"$ws/devel/lib/endovascular_sim/core_tests" --gtest_filter="$filter"
