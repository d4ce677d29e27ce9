#!/usr/bin/env bash
# Callgrind instructions per step over steps WARM+1 .. WARM+STEPS of a 3D scene, one thread:
#   scripts/window3d.sh SCENE WARM STEPS [BINARY]
# (BINARY defaults to target/release/examples/window3d; build it with
# `cargo build --release --example window3d`). Prints the state hash and M instructions/step.
set -euo pipefail
scene=$1 warm=$2 steps=$3 bin=${4:-target/release/examples/window3d}
dir=$(mktemp -d)
go=$dir/go out=$dir/callgrind.out log=$dir/stdout
GO_FILE=$go valgrind --tool=callgrind --instr-atstart=no ${CG_OPTS:-} \
    --callgrind-out-file="$out" "$bin" "$scene" "$warm" "$steps" >"$log" 2>"$dir/stderr" &
pid=$!
until grep -q ready "$log" 2>/dev/null; do
    kill -0 $pid 2>/dev/null || { cat "$dir/stderr" >&2; exit 1; }
    sleep 0.5
done
callgrind_control -i on $pid >/dev/null 2>&1
touch "$go"
until grep -q done "$log" 2>/dev/null; do
    kill -0 $pid 2>/dev/null || { cat "$dir/stderr" >&2; exit 1; }
    sleep 0.2
done
callgrind_control -i off $pid >/dev/null 2>&1
touch "$go.done"
wait $pid
grep "state hash" "$log"
ir=$(grep "^totals:" "$out" | awk '{print $2}')
echo "$scene steps $((warm + 1))-$((warm + steps)): $(echo "$ir / $steps / 1000000" | bc -l | xargs printf '%.1f') M instructions per step"
if [ -n "${KEEP:-}" ]; then cp "$out" "$KEEP"; fi
rm -rf "$dir"
