#!/usr/bin/env bash
# `make bench`: the benchmark sweep of issues #2-#4 on this machine (about 17 minutes on 2 cores),
# then bench/BENCHMARKS.md and its plots. Wall-clock times on a shared VM vary by ~10%: compare
# figures from the same run. References are cached in bench/cache (not committed).
set -euo pipefail
build=${1:-build}
cd "$(dirname "$0")/.."
hemirad="./$build/hemirad"
results=bench/results
cache=bench/cache
scenes=$cache/scenes
mkdir -p "$results" "$scenes"
box46=0.0217391304347826   # unit cube edges / 46: 46 x 46 quads per face, 12,696 patches

step() { echo; echo "== $*"; }

step "generated scenes (scenes/generators)"
/usr/bin/python3 scenes/generators/cornell13k.py "$scenes"
/usr/bin/python3 scenes/generators/street64k.py "$scenes"
"$hemirad" subdivide scenes/unit_cube.obj -o "$scenes/box12696.obj" --max-edge "$box46" --quiet

step "issue #2: F against a bare rtcIntersect1 loop; solvers (12,696-patch box, 3072 directions)"
"./$build/bench_rays" scenes/unit_cube.obj --subdivide "$box46" --samples 3072 --origins 1 --rho 0.73,0.5,0.3 \
    --repeat 2 | tee "$results/box12696_rays_and_solvers.txt"

# References: Lambert factors from a 2 x 2 Gauss-Legendre rule over each emitter, shadow rays to
# random points, silhouettes split twice (--reference-origins 4, ~2.5 min per scene). Measured on
# cornell13k against 16 origins: mean row |dF| 1.8e-7, far below every error reported here.
reference=(--reference-estimator analytic --reference-origins 4 --cache "$cache")

step "time against error: the subdivided box (hemisphere rays sweep, hemicube R = 64/128/256 drawing parents)"
"$hemirad" bench scenes/unit_cube.obj --subdivide "$box46" --label box12696 -o "$results/box12696.csv" \
    --methods hemisphere,hemicube --estimator rays --sweep-samples 96,384,768,1536,3072 --sweep-origins 1 \
    --sweep-resolutions 64,128,256 "${reference[@]}" | tee "$results/box12696.log"

step "time against error: cornell13k, the reference system's method (centroid, fixed directions), rays, analytic"
"$hemirad" bench "$scenes/cornell13k.obj" -o "$results/cornell13k_reference_method.csv" --methods hemisphere \
    --estimator rays --sweep-samples 96,384,768,1536,3072,6144,12288 --sweep-origins 1 --fixed-directions \
    "${reference[@]}" | tee "$results/cornell13k_reference_method.log"
"$hemirad" bench "$scenes/cornell13k.obj" -o "$results/cornell13k_rays.csv" --methods hemisphere --estimator rays \
    --sweep-samples 96,384,768,1536,3072 --sweep-origins 1 "${reference[@]}" | tee "$results/cornell13k_rays.log"
"$hemirad" bench "$scenes/cornell13k.obj" -o "$results/cornell13k_analytic.csv" --methods hemisphere \
    --estimator analytic --sweep-samples 3072 --sweep-origins 1,4 "${reference[@]}" | tee "$results/cornell13k_analytic.log"
"$hemirad" bench "$scenes/cornell13k.obj" -o "$results/cornell13k_reciprocity.csv" --methods hemisphere \
    --estimator rays --sweep-samples 768,3072 --sweep-origins 1 --enforce-reciprocity "${reference[@]}" \
    | tee "$results/cornell13k_reciprocity.log"

step "hemicube timings: Cornell box subdivided to 13,186 patches (parents) and the unsubdivided 12,696-patch box"
: > "$results/hemicube_timings.jsonl"
for r in 64 128 256; do
    "$hemirad" bench-run scenes/cornell_box.obj --subdivide 15 --label cornell15mm --method hemicube \
        --resolution "$r" | tee -a "$results/hemicube_timings.jsonl"
done
for r in 64 128; do
    "$hemirad" bench-run "$scenes/box12696.obj" --label box12696_unsubdivided --method hemicube \
        --resolution "$r" | tee -a "$results/hemicube_timings.jsonl"
done

step "street64k at 3072 directions: time and peak memory"
"$hemirad" bench-run "$scenes/street64k.obj" --label street64k --method hemisphere --samples 3072 \
    | tee "$results/street64k.jsonl"

step "street64k across MPI ranks: F on 1 vs 2 ranks, the PETSc solve"
bash bench/mpi_scaling.sh "$build"

step "what --solver auto picks above 2000 patches: Gauss-Seidel or Jacobi by thread count"
bash bench/auto_solver.sh "$build"

step "the Python module's overhead over the CLI: cornell13k F and solve"
bash bench/python_overhead.sh "$build"

step "the scale-out job: street64k x 4 (~250k patches) on 2 MPI ranks, F sharded"
bash bench/mpi_street_tiled.sh "$build"

step "what skipping saves: black rows, the mirror pass, F reuse after a material-only edit"
"$hemirad" bench-run "$scenes/street64k.obj" --label street64k_all_rows --method hemisphere --samples 3072 \
    --all-rows | tee "$results/skip_black_rows.jsonl"
sed -e 's/^illum 3/illum 1/' -e 's/^Ks 0.8 0.8 0.8/Ks 0 0 0/' "$scenes/street64k.mtl" > "$scenes/street64k_no_mirrors.mtl"
sed 's/^mtllib street64k.mtl/mtllib street64k_no_mirrors.mtl/' "$scenes/street64k.obj" > "$scenes/street64k_no_mirrors.obj"
"$hemirad" bench-run "$scenes/street64k_no_mirrors.obj" --label street64k_no_mirrors --method hemisphere \
    --samples 3072 | tee "$results/skip_mirrors.jsonl"
cp "$scenes/cornell13k.obj" "$scenes/cornell13k_edit.obj"
sed 's/^mtllib cornell13k.mtl/mtllib cornell13k_edit.mtl/' "$scenes/cornell13k.obj" > "$scenes/cornell13k_edit.obj"
cp "$scenes/cornell13k.mtl" "$scenes/cornell13k_edit.mtl"
rm -f "$cache/cornell13k_edit.hff"
"$hemirad" solve "$scenes/cornell13k_edit.obj" --ff "$cache/cornell13k_edit.hff" -o "$cache/B_before.csv" \
    | tee "$results/reuse_first.txt"
sed -i 's/^Ke 17 12 4/Ke 8.5 6 2/' "$scenes/cornell13k_edit.mtl"   # a material-only edit: the light at half power
"$hemirad" solve "$scenes/cornell13k_edit.obj" --ff "$cache/cornell13k_edit.hff" -o "$cache/B_after.csv" \
    | tee "$results/reuse_second.txt"

step "exact form factors against closed forms (issue 16): the subdivided cube, plates past a blocker, Cornell at 60 mm"
/usr/bin/python3 bench/exact_factors.py "$build" | tee "$results/exact_factors.md"

step "form factors on meshes users bring (issue 34): non-conforming districts, a closed district, spheres"
/usr/bin/python3 bench/real_meshes.py "$build" | tee "$results/real_meshes.md"

step "sensor points (issue 37): 10^5 against street64k by rays, rays against exact"
/usr/bin/python3 bench/sensors.py "$build" | tee "$results/sensors.md"

step "numerical stress"
"./$build/bench_stress" | tee "$results/stress.md"

step "the demo image"
"$hemirad" render scenes/cornell_box.obj -o bench/cornell.png --subdivide 20 --samples 1024 --origins 4 \
    --size 640x640 | tee "$results/cornell_demo.txt"
"$hemirad" render scenes/cornell_mirror.obj -o bench/cornell_mirror.png --subdivide 20 --samples 1024 \
    --origins 4 --size 640x640 | tee "$results/cornell_mirror_demo.txt"

step "plots and bench/BENCHMARKS.md"
/usr/bin/python3 bench/plot.py "$results"/box12696.csv "$results"/cornell13k_*.csv --out bench
/usr/bin/python3 bench/report.py --results "$results" --out bench/BENCHMARKS.md
