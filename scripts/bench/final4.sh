#!/bin/sh
# Issue 17: the large-triangle pass in blocks, batched, and the area split: G-buffer fill per
# scene at 4K against the previous binary and the baseline, then the split swept.
# Usage: NEW=path/to/render OLD=path/to/previous-render scripts/bench/final4.sh
run() {
  bin=$1; shift
  echo "=== $(basename $bin) $*"
  timeout 120 $bin --width 3840 --height 2160 --frames 20 --no-debug-views --out /tmp/o --no-wind "$@" > /tmp/r.txt 2>&1
  grep -E "rror|aused|^adapter|== CPU|pixel-shading" /tmp/r.txt | head -4
  sed -n '/GPU times/,/wall clock/p' /tmp/r.txt | grep -v "wall clock\|GPU times\|light\|lighting"
}
NEW=${NEW:-.bench/render}
OLD=${OLD:-.bench/render-old}
for s in "forest" "grass" "hillside" "forest --density 4" "grass --density 4" "hillside --density 2"; do
  run $NEW --scene $s --path deferred --laydown compute --vertex-ring off
  run $OLD --scene $s --path deferred --laydown compute --vertex-ring off | grep "===\|laydown"
  run $NEW --scene $s --path baseline
done
for s in "forest --density 4" "forest" "grass --density 4" "hillside"; do
  for e in 16 20 28; do
    run $NEW --scene $s --path deferred --laydown compute --vertex-ring off --laydown-max-extent $e | grep "===\|laydown"
  done
done
