#!/bin/sh
# Issue 17, fifth part (the classification reworked again): every pass of the G-buffer fill
# per scene at 4K, the new binary against the previous one and the baseline, then the
# classification with the vertex ring (chunk marks on).
# Usage: NEW=path/to/render OLD=path/to/previous-render scripts/bench/final5.sh
run() {
  bin=$1; shift
  echo "=== $(basename $bin) $*"
  timeout 150 $bin --width 3840 --height 2160 --frames 20 --no-debug-views --out /tmp/o --no-wind "$@" > /tmp/r.txt 2>&1
  grep -E "rror|aused|^adapter|== CPU|pixel-shading" /tmp/r.txt | head -4
  sed -n '/GPU times/,/wall clock/p' /tmp/r.txt | grep -v "wall clock\|GPU times\|light\|lighting"
}
NEW=${NEW:-.bench/render}
OLD=${OLD:-.bench/render-old}
for s in "forest" "grass" "hillside" "forest --density 4" "grass --density 4" "hillside --density 2" "hillside-grass" "hillside-grass --density 2"; do
  run $NEW --scene $s --path deferred --laydown compute --vertex-ring off
  run $OLD --scene $s --path deferred --laydown compute --vertex-ring off
  run $NEW --scene $s --path baseline
done
for s in "forest" "hillside-grass"; do
  run $NEW --scene $s --path deferred --laydown compute | grep "===\|==\|classify\|_pass\|count_pixels\|write_\|scatter\|laydown"
  run $OLD --scene $s --path deferred --laydown compute | grep "===\|==\|classify\|_pass\|count_pixels\|write_\|scatter\|laydown"
done
