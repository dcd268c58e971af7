#!/bin/bash
# Hemicube F time against hemicubes per pass (--batch), passes in flight (--in-flight) and reduction,
# with the per-row stages, the passes' GPU time and the renderer: issue 12's measurement. On llvmpipe
# it documents why batches and passes in flight default to 1 there; on a GPU machine (see the
# developers' guide: make build, then ../shared/tools/device-bundle.sh) run
#   source .gpu/env.sh && bash bench/hemicube_gpu.sh .gpu/bin/hemirad
# The first rows of each resolution are the default flags (batch 0, in flight 0, reduce auto): the
# figures issue 12's goals are about.
# Usage: bash bench/hemicube_gpu.sh [HEMIRAD] [BATCHES] [RESOLUTIONS] [IN_FLIGHT]
#   HEMIRAD      the binary (default build/hemirad)
#   BATCHES      --batch values (default "0 1 16 64 256"; 0 = the renderer's default)
#   RESOLUTIONS  --resolution values (default "128 256")
#   IN_FLIGHT    --in-flight values (default "0 1 2 3"; 0 = the renderer's default)
set -euo pipefail
cd "$(dirname "$0")/.."
hemirad=${1:-build/hemirad}
batches=${2:-0 1 16 64 256}
resolutions=${3:-128 256}
inflight=${4:-0 1 2 3}
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
flags = sys.argv[1]
ms = {k[len("ms_per_row_"):]: v for k, v in r.items() if k.startswith("ms_per_row_")}
stages = " ".join("%s %.3f" % (k[len("hemicube_"):], v) for k, v in sorted(ms.items()) if k.startswith("hemicube_"))
# The share of the passes GPU time the CPU did not wait for (1 = fully overlapped).
gpu = ms.get("hemicube_gpu_draw", 0) + ms.get("hemicube_gpu_results", 0)
overlap = "%.2f" % max(0.0, 1 - ms.get("hemicube_wait", 0) / gpu) if gpu > 0 else "-"
print("| %s | %d | %s | %.3f | %s | %s | %s |" % (r["scene"], r["resolution"], flags, r["t_ff"], stages, overlap,
      r.get("device", "?")))' "$*"
}

echo "| scene | R | flags | F [s] | ms per row (thread time) | overlap | device |"
echo "|---|---|---|---|---|---|---|"
for R in $resolutions; do
    run cornell13k "$scenes/cornell13k.obj" --resolution "$R"
    run box12696 scenes/unit_cube.obj --subdivide "$box46" --resolution "$R"
    for reduce in cpu gpu; do
        for b in $batches; do
            for f in $inflight; do
                run cornell13k "$scenes/cornell13k.obj" --resolution "$R" --reduce "$reduce" --batch "$b" --in-flight "$f"
                run box12696 scenes/unit_cube.obj --subdivide "$box46" --resolution "$R" --reduce "$reduce" --batch "$b" \
                    --in-flight "$f"
            done
        done
    done
done
