#!/bin/sh
# The mixed frame's write_commands: loop-indexed quad (render-old) against spelled out (render).
# Usage: BIN_DIR=dir scripts/bench/mixed.sh, with the two builds as render-old and render
# in that directory.
for b in render-old render; do for s in forest grass; do
  echo "=== $b $s"
  timeout 120 ${BIN_DIR:-./target/release}/$b --width 3840 --height 2160 --frames 20 --no-debug-views --out /tmp/o --no-wind --scene $s --path deferred --laydown compute --vertex-ring off --mixed-frame > /tmp/r.txt 2>&1
  grep -E "rror|aused|== CPU" /tmp/r.txt | head -3
  sed -n '/GPU times/,/wall clock/p' /tmp/r.txt | grep -E "classify|_pass|count_pixels|write_|scatter|entry_waves|finalize|regular|total"
done; done
