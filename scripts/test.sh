#!/usr/bin/env bash
# Builds and runs every test: a Release build (warnings as errors), then an ASan+UBSan build.
# Usage: scripts/test.sh [release|asan|all]   (default: all)
set -euo pipefail
cd "$(dirname "$0")/.."
what="${1:-all}"
jobs="$(nproc 2>/dev/null || echo 2)"
run() {
  scripts/build.sh "$1"
  ctest --test-dir "$2" -j "$jobs" --output-on-failure
}
case "$what" in
  release) run release build ;;
  asan) run asan build-asan ;;
  all) run release build; run asan build-asan ;;
  *) echo "usage: $0 [release|asan|all]" >&2; exit 2 ;;
esac
