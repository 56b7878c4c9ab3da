#!/bin/sh
# Issue 17, last part: the classification reworked; G-buffer fill per scene at 4K (compute laydown vs baseline).
# Usage: RENDER=path/to/render scripts/bench/final3.sh (default ./target/release/render).
run() {
  echo "=== $*"
  timeout 120 ${RENDER:-./target/release/render} --width 3840 --height 2160 --frames 20 --no-debug-views --out /tmp/o --no-wind "$@" > /tmp/r.txt 2>&1
  grep -E "rror|aused|^adapter|== CPU|pixel-shading|vertices: after" /tmp/r.txt | head -5
  sed -n '/GPU times/,/wall clock/p' /tmp/r.txt | grep -v "wall clock\|GPU times"
}
for s in "forest" "grass" "hillside" "forest --density 4" "grass --density 4" "hillside --density 2"; do
  run --scene $s --path deferred --laydown compute --vertex-ring off
  run --scene $s --path baseline
done
