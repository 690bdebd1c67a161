#!/usr/bin/env bash
# Benchmark (not a test): time to generate a 10 m x 10 m hexagonal panel (target: < 1 s).
# usage: generators/bench.sh [PATH/TO/wirenet-gen]   (default: build/bin/wirenet-gen)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
GEN=${1:-$here/../build/bin/wirenet-gen}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
timed() {  # timed LABEL CMD...: prints the wall time in seconds and the generator's summary
    local label=$1; shift
    local t0 t1; t0=$(date +%s%N)
    "$@" >"$tmp/log"
    t1=$(date +%s%N)
    local ms=$(( (t1 - t0) / 1000000 ))
    printf '%-22s %d.%03d s   %s\n' "$label" $((ms / 1000)) $((ms % 1000)) "$(head -1 "$tmp/log" | sed 's/^wirenet-gen [a-z]*: //')"
}
timed "hex 3 m x 3 m"       "$GEN" hex --out "$tmp/a"
timed "hex 10 m x 10 m"     "$GEN" hex --width 10 --height 10 --out "$tmp/b"
timed "compound 10 m x 10 m" "$GEN" compound --width 10 --height 10 --out "$tmp/c"
