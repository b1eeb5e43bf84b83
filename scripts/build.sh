#!/usr/bin/env bash
# Configures and builds Tracegraph. Usage: scripts/build.sh [release|asan] [extra cmake args...]
# Build folders: build/ (Release, warnings as errors) and build-asan/ (ASan+UBSan).
set -euo pipefail
cd "$(dirname "$0")/.."
kind="${1:-release}"
shift || true
jobs="$(nproc 2>/dev/null || echo 2)"
case "$kind" in
  release) dir=build; args=(-DCMAKE_BUILD_TYPE=Release -DTG_WARNINGS_AS_ERRORS=ON) ;;
  asan) dir=build-asan; args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DTG_SANITIZE=ON -DTG_WARNINGS_AS_ERRORS=ON) ;;
  *) echo "usage: $0 [release|asan] [cmake args...]" >&2; exit 2 ;;
esac
generator=()
if command -v ninja >/dev/null 2>&1; then generator=(-G Ninja); fi
if [ ! -f "$dir/CMakeCache.txt" ]; then
  cmake -S . -B "$dir" "${generator[@]}" "${args[@]}" "$@"
else
  cmake -S . -B "$dir" "${args[@]}" "$@" >/dev/null
fi
cmake --build "$dir" -j "$jobs"
