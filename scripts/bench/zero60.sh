#!/bin/sh
# Issue 17: the zero fill's share of the large-triangle pass, which it runs beside: the new
# binary (zero fill after the large dispatch, in its pass) against the moved build
# (scripts/bench/moved.patch: the zero fill a pass of its own), 60 frames at 4K, alternated
# three times per scene; prints the small and large laydown passes of every run.
# Usage: NEW=path/to/render MOVED=path/to/moved-render scripts/bench/zero60.sh
for s in "hillside --density 2" "grass" "forest --density 4"; do
  for i in 1 2 3; do
    for bin in $NEW $MOVED; do
      timeout 150 $bin --width 3840 --height 2160 --frames 60 --no-debug-views --out /tmp/o --no-wind --path deferred --laydown compute --vertex-ring off --scene $s > /tmp/r.txt 2>&1
      echo "$(basename $bin) $s $i $(sed -n '/GPU times/,/wall clock/p' /tmp/r.txt | grep -E '^  laydown( large)? ' | awk '{printf "%s ", $NF == "ms" ? $(NF-1) : $NF}')"
    done
  done
done
