#!/bin/sh
# Issue 17, fifth part (the classification reworked again): every pass of the G-buffer fill
# per scene at 4K, the new binary against the previous one and the baseline, then the
# classification with the vertex ring (chunk marks on): final6.sh without its moved build.
# Usage: NEW=path/to/render OLD=path/to/previous-render scripts/bench/final5.sh
MOVED= exec sh "$(dirname "$0")/final6.sh"
