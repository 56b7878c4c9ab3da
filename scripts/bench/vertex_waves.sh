#!/bin/sh
# The vertex wave commands at 4K with the vertex ring on (compute laydown, 20 frames, no
# wind), every binary of BINS on every scene in turn: the vertex side's passes (a build
# with scripts/bench/vertex_waves_steps.patch times each entry point on its own) and the frame.
# Usage: BINS="path/a path/b" [SCENES="forest|grass"] scripts/bench/vertex_waves.sh
SCENES=${SCENES:-"forest|grass|hillside|forest --density 4|grass --density 4|hillside --density 2|hillside-grass|hillside-grass --density 2"}
echo "$SCENES" | tr '|' '\n' | while read -r s; do
  for bin in $BINS; do
    echo "=== $bin --scene $s"
    timeout 150 $bin --width 3840 --height 2160 --frames 20 --no-debug-views --out /tmp/o --path deferred --laydown compute --vertex-ring ps5 --no-wind --scene $s > /tmp/r.txt 2>&1
    grep -E "rror|aused|== CPU|mismatch|vertices" /tmp/r.txt | head -4
    sed -n '/GPU times/,/wall clock/p' /tmp/r.txt | grep -E "vertex|uber|pyramid|delta|commands|pass_args|resolve|total"
  done
done
