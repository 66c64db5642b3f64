#!/bin/sh
# `make bench`: the engine benchmark side by side with ninja (tools/bench_engine.py; results in
# docs/performance.md, "Engine"). Usage: tools/bench.sh BUILD_DIR [bench_engine.py options]
set -eu
build=${1:-out/build}
[ $# -gt 0 ] && shift
command -v ninja >/dev/null || { echo "tools/bench.sh: ninja (Debian ninja-build) is needed" >&2; exit 2; }
exec python3 "$(dirname "$0")/bench_engine.py" --sylva "$build/app/sylva" "$@"
