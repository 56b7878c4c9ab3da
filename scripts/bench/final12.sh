#!/bin/sh
# Issue 17, where it ends: every pass of the G-buffer fill per scene at 4K for one binary,
# without and with the vertex ring (`--vertex-ring off` / `ps5`), and the baseline.
# Usage: BIN=path/to/render scripts/bench/final12.sh
. "$(dirname "$0")/run4k.sh"
for s in "forest" "grass" "hillside" "forest --density 4" "grass --density 4" "hillside --density 2" "hillside-grass" "hillside-grass --density 2"; do
  run4k $BIN --scene $s --path deferred --laydown compute --vertex-ring off
  run4k $BIN --scene $s --path deferred --laydown compute --vertex-ring ps5
  run4k $BIN --scene $s --path baseline
done
