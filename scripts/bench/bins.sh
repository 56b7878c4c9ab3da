#!/bin/sh
# Every binary of BINS on every scene of SCENES (4K, compute laydown, 20 frames), one after
# another in the same run: the laydown and classification passes of each.
# Usage: BINS="path/a path/b" [SCENES="forest|grass"] [VERTEX_RING=ps5] scripts/bench/bins.sh [render options...]
SCENES=${SCENES:-"forest|grass|hillside|forest --density 4|grass --density 4|hillside --density 2|hillside-grass|hillside-grass --density 2"}
echo "$SCENES" | tr '|' '\n' | while read -r s; do
  for bin in $BINS; do
    echo "=== $bin --scene $s $*"
    timeout 150 $bin --width 3840 --height 2160 --frames 20 --no-debug-views --out /tmp/o --path deferred --laydown compute --vertex-ring ${VERTEX_RING:-off} --no-wind --scene $s "$@" > /tmp/r.txt 2>&1
    grep -E "rror|aused|== CPU|mismatch" /tmp/r.txt | head -3
    sed -n '/GPU times/,/wall clock/p' /tmp/r.txt | grep -E "classify|_pass|count_pixels|mark_chunks|write_|scatter_|entry_waves|laydown|total"
  done
done
