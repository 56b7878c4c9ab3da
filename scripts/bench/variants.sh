#!/bin/sh
# Issue 17: the classification with parts of its WGSL switched off (only the times mean
# anything). Usage: VARIANTS=path/to/classify_variants scripts/bench/variants.sh (built by
# cargo build --release -p gpu --example classify_variants).
for s in forest hillside; do echo "== $s"; timeout 200 ${VARIANTS:-./target/release/examples/classify_variants} --scene $s --frames 20 2>&1 | grep -v "^\s*$" | grep -E "rror|aused|finalize|NVIDIA"; done
