#!/bin/sh
# Issue 17: the large-triangle pass in blocks, batched, and the area split: G-buffer fill per
# scene at 4K against the previous binary and the baseline, then the split swept.
# Usage: NEW=path/to/render OLD=path/to/previous-render scripts/bench/final4.sh
TIMEOUT=${TIMEOUT:-120}
. "$(dirname "$0")/run4k.sh"
NEW=${NEW:-.bench/render}
OLD=${OLD:-.bench/render-old}
for s in "forest" "grass" "hillside" "forest --density 4" "grass --density 4" "hillside --density 2"; do
  run4k $NEW --scene $s --path deferred --laydown compute --vertex-ring off
  run4k $OLD --scene $s --path deferred --laydown compute --vertex-ring off | grep "===\|laydown"
  run4k $NEW --scene $s --path baseline
done
for s in "forest --density 4" "forest" "grass --density 4" "hillside"; do
  for e in 16 20 28; do
    run4k $NEW --scene $s --path deferred --laydown compute --vertex-ring off --laydown-max-extent $e | grep "===\|laydown"
  done
done
