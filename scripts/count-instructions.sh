#!/usr/bin/env bash
# Instructions, branches and mispredicted branches per single ray, ours against Embree's, counted
# by Callgrind in one run of `tg-bench trace`. Counts do not depend on the machine's load, so
# they compare two versions of a walk where timings on a shared machine spread by tens of
# percent; they are no substitute for the timed rows (a mispredicted branch or a cache miss
# costs far more than an instruction).
#
# Usage: scripts/count-instructions.sh TRACE-ARGS...
#   e.g. scripts/count-instructions.sh --scene ../shared/data/bart/robots/aff/Robot.aff \
#          --view scene --size 320x240 [--rays shadow]
# Needs the Release build (scripts/build.sh) and valgrind (Debian package `valgrind`). One
# thread, one round; every row of the suite runs under Callgrind (several minutes), but only
# the single-ray entry points are counted:
#   ours     TopLevelBvh::intersect / TopLevelBvh::occluded (the BVH engine's single rays: its
#            row, the walk-count pass, and for shadow rays the primary hits that place them)
#   embree   rtcIntersect1 / rtcOccluded1 (its HIGH and MEDIUM rows together)
set -euo pipefail
cd "$(dirname "$0")/.."
bench=build/samples/tg-bench/tg-bench
if [ ! -x "$bench" ]; then
  echo "count-instructions: $bench is missing; build it with scripts/build.sh" >&2
  exit 1
fi
if ! command -v valgrind >/dev/null 2>&1; then
  echo "count-instructions: valgrind is missing; install the Debian package valgrind" >&2
  exit 1
fi
if [ "$#" -eq 0 ]; then
  sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//' >&2
  exit 2
fi
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
ours_closest='tg::detail::TopLevelBvh::intersect(tg::Ray const&, tg::Hit&, tg::TraversalContext&) const'
ours_any='tg::detail::TopLevelBvh::occluded(tg::Ray const&, tg::TraversalContext&) const'
echo "count-instructions: tg-bench trace $* under Callgrind (several minutes)" >&2
valgrind --tool=callgrind --callgrind-out-file="$out/callgrind.out" --branch-sim=yes --dump-instr=yes \
  --toggle-collect="$ours_closest" --toggle-collect="$ours_any" \
  --toggle-collect=rtcIntersect1 --toggle-collect=rtcOccluded1 \
  "$bench" trace "$@" --reps 1 --threads 1 >"$out/bench.txt" 2>"$out/valgrind.txt" || {
  tail -20 "$out/valgrind.txt" >&2
  exit 1
}
python3 scripts/count-instructions.py "$out/callgrind.out" \
  "ours, closest hit" "$ours_closest" "ours, any hit" "$ours_any" \
  "embree rtcIntersect1" rtcIntersect1 "embree rtcOccluded1" rtcOccluded1
