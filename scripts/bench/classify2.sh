#!/bin/sh
# Classification per entry point at 4K, compute laydown (issue 17, fifth part): two
# binaries alternated on every scene, the same machine and run.
# Usage: OLD=path/to/render NEW=path/to/render scripts/bench/classify2.sh [scenes...]
run() {
  bin=$1; shift
  echo "=== $bin $*"
  timeout 150 $bin --width 3840 --height 2160 --frames 20 --no-debug-views --out /tmp/o --path deferred --laydown compute --vertex-ring off --no-wind "$@" > /tmp/r.txt 2>&1
  grep -E "rror|aused|== CPU|mismatch" /tmp/r.txt | head -3
  sed -n '/GPU times/,/wall clock/p' /tmp/r.txt | grep -E "classify|_pass|count_pixels|write_|scatter_|entry_waves|laydown|total"
}
SCENES=${SCENES:-"forest|grass|hillside|forest --density 4|grass --density 4|hillside --density 2|hillside-grass|hillside-grass --density 2"}
echo "$SCENES" | tr '|' '\n' | while read -r s; do
  [ -n "$OLD" ] && run "$OLD" --scene $s
  run "$NEW" --scene $s
done
