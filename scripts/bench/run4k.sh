# Sourced by the final*.sh scripts: run4k BIN [render options...] renders 20 frames at 4K
# (no debug views, no wind, output under /tmp/o) and prints the adapter, the classification
# check, the talk's wave figures and every GPU pass but the lights. TIMEOUT (seconds,
# default 150) bounds one run.
run4k() {
  bin=$1; shift
  echo "=== $(basename $bin) $*"
  timeout "${TIMEOUT:-150}" $bin --width 3840 --height 2160 --frames 20 --no-debug-views --out /tmp/o --no-wind "$@" > /tmp/r.txt 2>&1
  grep -E "rror|aused|^adapter|== CPU|pixel-shading" /tmp/r.txt | head -4
  sed -n '/GPU times/,/wall clock/p' /tmp/r.txt | grep -v "wall clock\|GPU times\|light\|lighting"
}
