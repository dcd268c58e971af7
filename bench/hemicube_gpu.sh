#!/bin/bash
# Hemicube F time against hemicubes per pass (--batch) and reduction, with the per-row stages and the
# renderer: issue 12's measurement. On llvmpipe it documents why batches default to 1 there; on a GPU
# machine (see the developers' guide: make build, then ../shared/tools/device-bundle.sh) run
#   source .gpu/env.sh && bash bench/hemicube_gpu.sh .gpu/bin/hemirad
# Usage: bash bench/hemicube_gpu.sh [HEMIRAD] [BATCHES] [RESOLUTIONS]
#   HEMIRAD      the binary (default build/hemirad)
#   BATCHES      --batch values (default "0 1 16 64 256"; 0 = the renderer's default)
#   RESOLUTIONS  --resolution values (default "128 256")
set -euo pipefail
cd "$(dirname "$0")/.."
hemirad=${1:-build/hemirad}
batches=${2:-0 1 16 64 256}
resolutions=${3:-128 256}
scenes=bench/cache/scenes
mkdir -p "$scenes"
[ -f "$scenes/cornell13k.obj" ] || python3 scenes/generators/cornell13k.py "$scenes"
box46=0.0217391304347826  # unit cube edges / 46: 12,696 patches, drawn as 6 parent faces

run() {  # label, scene, flags...
    local label=$1 scene=$2
    shift 2
    "$hemirad" bench-run "$scene" --label "$label" --method hemicube "$@" 2>/dev/null | tail -1 |
        python3 -c '
import json, sys
r = json.loads(sys.stdin.read())
stages = " ".join("%s %.3f" % (k[len("ms_per_row_hemicube_"):], v) for k, v in sorted(r.items())
                  if k.startswith("ms_per_row_hemicube_"))
print("| %s | %d | %s | %s | %.3f | %s | %s |" % (r["scene"], r["resolution"], r.get("batch", "?"), r["reduce"],
      r["t_ff"], stages, r.get("device", "?")))'
}

echo "| scene | R | batch | reduce | F [s] | ms per row (thread time) | device |"
echo "|---|---|---|---|---|---|---|"
for R in $resolutions; do
    for reduce in cpu gpu; do
        for b in $batches; do
            run cornell13k "$scenes/cornell13k.obj" --resolution "$R" --reduce "$reduce" --batch "$b"
            run box12696 scenes/unit_cube.obj --subdivide "$box46" --resolution "$R" --reduce "$reduce" --batch "$b"
        done
    done
done
