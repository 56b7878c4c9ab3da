#!/bin/sh
# Issue 17, sixth part: every pass of the G-buffer fill per scene at 4K, the new binary
# against the previous one and the baseline; the "moved" build (the new one with
# scripts/bench/moved.patch applied: the unpack without laydown finalise, the zero fill as
# a pass of its own) for the classification's share of the unpack and raster passes; then
# the classification with the vertex ring (chunk marks on).
# Usage: NEW=path/to/render OLD=path/to/previous-render [MOVED=path/to/moved-render] scripts/bench/final6.sh
. "$(dirname "$0")/run4k.sh"
for s in "forest" "grass" "hillside" "forest --density 4" "grass --density 4" "hillside --density 2" "hillside-grass" "hillside-grass --density 2"; do
  run4k $NEW --scene $s --path deferred --laydown compute --vertex-ring off
  run4k $OLD --scene $s --path deferred --laydown compute --vertex-ring off
  [ -n "$MOVED" ] && run4k $MOVED --scene $s --path deferred --laydown compute --vertex-ring off | grep "===\|laydown\|zero"
  run4k $NEW --scene $s --path baseline
done
for s in "forest" "hillside-grass"; do
  run4k $NEW --scene $s --path deferred --laydown compute | grep "===\|==\|classify\|_pass\|count_pixels\|write_\|scatter\|entry_waves\|laydown"
  run4k $OLD --scene $s --path deferred --laydown compute | grep "===\|==\|classify\|_pass\|count_pixels\|write_\|scatter\|entry_waves\|laydown"
done
