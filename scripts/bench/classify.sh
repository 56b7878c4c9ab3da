#!/bin/sh
# Classification per entry point at 4K, compute laydown (issue 17).
# Usage: RENDER=path/to/render scripts/bench/classify.sh (default ./target/release/render).
run() {
  echo "=== $*"
  timeout 120 ${RENDER:-./target/release/render} --width 3840 --height 2160 --frames 20 --no-debug-views --out /tmp/o --path deferred --laydown compute --vertex-ring off "$@" > /tmp/r.txt 2>&1
  grep -E "rror|aused|== CPU|pixel-shading" /tmp/r.txt | head -4
  sed -n '/GPU times/,/wall clock/p' /tmp/r.txt | grep -E "classify|_pass|count_pixels|write_|scatter_|entry_waves|laydown_finalize|resolve|total"
}
for s in "forest" "grass" "hillside" "forest --density 4" "grass --density 4" "hillside --density 2"; do
  run --scene $s
done
