#!/bin/sh
# Issue 17, sixth part: every pass of the G-buffer fill per scene at 4K, the new binary
# against the previous one and the baseline; the "moved" build (the new one with
# scripts/bench/moved.patch applied: the unpack without laydown finalise, the zero fill as
# a pass of its own) for the classification's share of the unpack and raster passes; then
# the classification with the vertex ring (chunk marks on).
# Usage: NEW=path/to/render OLD=path/to/previous-render MOVED=path/to/moved-render scripts/bench/final6.sh
run() {
  bin=$1; shift
  echo "=== $(basename $bin) $*"
  timeout 150 $bin --width 3840 --height 2160 --frames 20 --no-debug-views --out /tmp/o --no-wind "$@" > /tmp/r.txt 2>&1
  grep -E "rror|aused|^adapter|== CPU|pixel-shading" /tmp/r.txt | head -4
  sed -n '/GPU times/,/wall clock/p' /tmp/r.txt | grep -v "wall clock\|GPU times\|light\|lighting"
}
for s in "forest" "grass" "hillside" "forest --density 4" "grass --density 4" "hillside --density 2" "hillside-grass" "hillside-grass --density 2"; do
  run $NEW --scene $s --path deferred --laydown compute --vertex-ring off
  run $OLD --scene $s --path deferred --laydown compute --vertex-ring off
  run $MOVED --scene $s --path deferred --laydown compute --vertex-ring off | grep "===\|laydown\|zero"
  run $NEW --scene $s --path baseline
done
for s in "forest" "hillside-grass"; do
  run $NEW --scene $s --path deferred --laydown compute | grep "===\|==\|classify\|_pass\|count_pixels\|write_\|scatter\|laydown"
  run $OLD --scene $s --path deferred --laydown compute | grep "===\|==\|classify\|_pass\|count_pixels\|write_\|scatter\|laydown"
done
