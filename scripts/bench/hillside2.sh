#!/bin/sh
# Issue 17: the rebuilt hillside's two views at 4K: G-buffer fill (compute laydown, each
# classification pass, resolve) against the baseline, and the talk's tables on the H200.
# Usage: RENDER=path/to/render scripts/bench/hillside2.sh
run() {
  echo "=== $*"
  timeout 150 ${RENDER:-./target/release/render} --width 3840 --height 2160 --frames 20 --no-debug-views --out /tmp/o --no-wind "$@" > /tmp/r.txt 2>&1
  grep -E "rror|aused|^adapter|== CPU|pixel-shading|vertices: after|triangles," /tmp/r.txt | head -6
  sed -n '/GPU times/,/wall clock/p' /tmp/r.txt | grep -v "wall clock\|GPU times\|light\|lighting"
}
for s in "hillside" "hillside --density 2" "hillside-grass" "hillside-grass --density 2"; do
  run --scene $s --path deferred --laydown compute --vertex-ring off
  run --scene $s --path baseline
done
