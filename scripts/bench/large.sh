#!/bin/sh
# Issue 17: the large-triangle pass in 8x8 blocks, several triangles a workgroup set up at
# once, against the previous binary, same machine and run; then the split and the baseline.
# Usage: BINS="render-a render-b ..." NEW=render scripts/bench/large.sh (NEW: the one the
# split and baseline rows use).
run() {
  bin=$1; shift
  echo "=== $(basename $bin) $*"
  timeout 120 $bin --width 3840 --height 2160 --frames 20 --no-debug-views --out /tmp/o --no-wind "$@" > /tmp/r.txt 2>&1
  grep -E "rror|aused|== CPU" /tmp/r.txt | grep -v yes | head -3
  sed -n '/GPU times/,/wall clock/p' /tmp/r.txt | grep -E "laydown( large)? |total|prepass|depth-equal"
}
NEW=${NEW:-.bench/render}
for s in "forest --density 4" "forest" "grass" "grass --density 4" "hillside"; do
  for b in ${BINS:-$NEW}; do
    run $b --scene $s --path deferred --laydown compute --vertex-ring off
  done
done
for s in "forest --density 4" "forest" "grass --density 4" "hillside"; do
  for e in ${EXTENTS:-16 64}; do
    run $NEW --scene $s --path deferred --laydown compute --vertex-ring off --laydown-max-extent $e
  done
done
run $NEW --scene forest --density 4 --path baseline
