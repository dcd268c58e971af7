#!/usr/bin/env bash
# Issue 36's benchmark: the thermal solve against the radiosity solve on the same stored F, on
# cornell13k and street64k (ground at a fixed temperature, heat fluxes on the walls, the sky dome and
# the environment at 260 K), and the conductor export (Gebhart factors by column solves) per object
# and per patch, and the gray solve across MPI ranks. Usage: bench/thermal.sh [HEMIRAD] [WORK]; prints
# Markdown tables. PARTS="conductors" runs the per-patch conductors alone (the solves need cornell13k's
# and street64k's F: minutes to hours), PARTS="mpi" the ranks alone (cornell13k's F).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
hemirad=${1:-$root/build/hemirad}
work=${2:-$root/bench/cache/thermal}
mkdir -p "$work"
[ -f "$work/cornell13k.obj" ] || /usr/bin/python3 "$root/scenes/generators/cornell13k.py" "$work" >/dev/null
[ -f "$work/street64k.obj" ] || /usr/bin/python3 "$root/scenes/generators/street64k.py" "$work" >/dev/null

cat >"$work/cornell13k_bc.toml" <<'TOML'
[environment]
temperature_K = 260
[default]
flux_W_m2 = 20
[objects.floor]
temperature_K = 300
[objects.light_sphere]
temperature_K = 400
TOML
cat >"$work/street64k_bc.toml" <<'TOML'
[environment]
temperature_K = 260
[default]
flux_W_m2 = 15           # the buildings' walls, roofs and windows lose heat from inside
[objects.ground]
temperature_K = 305
[objects.sky]
temperature_K = 260
TOML

stage() {  # the seconds of a stage in hemirad's timing table
  awk -v s="$1" 'index($0, s) == 1 && index($0, ":") == 0 { print $NF; exit }'
}

parts=${PARTS:-solves conductors mpi}
if [[ " $parts " == *" solves "* ]]; then
echo "| scene | patches | F nonzeros | radiosity solve (s) | thermal solve (s) | thermal / radiosity | conductors per object (s) | energy balance |"
echo "|---|---|---|---|---|---|---|---|"
for scene in cornell13k street64k; do
  obj="$work/$scene.obj"
  unit=m
  [ "$scene" = cornell13k ] && unit=mm
  ff="$work/$scene.hff"
  [ -f "$ff" ] || "$hemirad" formfactors "$obj" --all-rows -o "$ff" --quiet
  nnz=$("$hemirad" info "$ff" | awk '/nonzeros/ { for (i = 1; i <= NF; ++i) if ($i ~ /^[0-9]+$/) { print $i; exit } }')
  radiosity=$("$hemirad" solve "$obj" --ff "$ff" -o "$work/B.csv" | stage "solve (")
  log=$("$hemirad" thermal "$obj" --unit "$unit" --ff "$ff" --bc "$work/${scene}_bc.toml" -o "$work/T.csv" --conductors "$work/GR.csv")
  echo "$log" | grep -E '^(thermal solve|energy balance|conductors):' >&2
  thermal=$(echo "$log" | stage "thermal solve")
  conductors=$(echo "$log" | stage "Gebhart factors")
  balance=$(echo "$log" | sed -n 's/^energy balance: |sum Q + Q_env| \/ max |Q| = \([^;]*\);.*/\1/p')
  patches=$(grep -c '^f ' "$obj")
  ratio=$(awk -v a="$thermal" -v b="$radiosity" 'BEGIN { printf "%.2f", (b > 0 ? a / b : 0) }')
  echo "| $scene | $patches | $nnz | $radiosity | $thermal | $ratio | $conductors | $balance |"
done

fi

# Conductors per patch, every patch a node: one dense Cholesky inverse over every patch pair (auto
# here) against a column solve per patch (a batch of 64 shares a sweep over F); the 17 mm box is the
# issue's 10k-node model (10,247 patches).
if [[ " $parts " == *" conductors "* ]]; then
echo
echo "| conductors per patch | patches | route | Gebhart factors (s) | written (s) | couplings | peak memory (MiB) |"
echo "|---|---|---|---|---|---|---|"
# The bundled box's objects: cornell13k's conditions with its light (cornell13k has a light sphere).
sed 's/objects.light_sphere/objects.light/' "$work/cornell13k_bc.toml" >"$work/cornell_box_bc.toml"
for run in "60 auto" "40 auto" "30 auto" "30 columns" "17 auto"; do
  set -- $run
  edge=$1 route=$2
  obj="$root/scenes/cornell_box.obj"
  log=$(/usr/bin/time -f "peak %M" "$hemirad" thermal "$obj" --subdivide "$edge" --bc "$work/cornell_box_bc.toml" \
        --lump patches --gebhart "$route" --conductors "$work/GRp.csv" 2>&1)
  patches=$(echo "$log" | sed -n 's/.*subdivided to \([0-9]*\) patches.*/\1/p')
  seconds=$(echo "$log" | stage "Gebhart factors")
  written=$(echo "$log" | stage "write thermal results")
  taken=$(echo "$log" | sed -n 's/.*; \(one dense factorisation\|a column solve\).*/\1/p')
  couplings=$(echo "$log" | sed -n 's/^conductors: \([0-9]*\) couplings.*/\1/p')
  peak=$(echo "$log" | awk '/^peak/ { printf "%.0f", $2 / 1024 }')
  echo "| cornell_box --subdivide $edge | $patches | ${taken:-$route} | $seconds | $written | $couplings | $peak |"
done
rm -f "$work/GRp.csv"
fi

# The gray solve across MPI ranks (mpi/distributed_thermal.hpp): each rank reads its share of the
# stored F's rows and the bands go to PETSc where the rows are, against one process holding F whole.
# cornell13k's conditions above; one process with two threads, two ranks with one each.
if [[ " $parts " == *" mpi "* ]]; then
obj="$work/cornell13k.obj"
ff="$work/cornell13k.hff"
[ -f "$ff" ] || "$hemirad" formfactors "$obj" --all-rows -o "$ff" --quiet
echo
echo "| cornell13k thermal (run) | processes | thermal solve | thermal solve (s) | whole run (s) | peak memory, largest process (MiB) | energy balance |"
echo "|---|---|---|---|---|---|---|"
mpi="mpirun --allow-run-as-root --oversubscribe -np 2"
for run in "1 a" "2 a" "1 b" "2 b"; do  # interleaved, twice each
  set -- $run
  ranks=$1
  launch=""
  threads=2
  if [ "$ranks" = 2 ]; then launch="$mpi"; threads=1; fi
  log=$(/usr/bin/time -f "peak %M" $launch "$hemirad" thermal "$obj" --unit mm --ff "$ff" --bc "$work/cornell13k_bc.toml" \
        -o "$work/T$ranks.csv" --threads "$threads" 2>&1)
  thermal=$(echo "$log" | stage "thermal solve")
  total=$(echo "$log" | stage "total")
  peak=$(echo "$log" | awk '/^peak/ { printf "%.0f", $2 / 1024 }')
  taken=$(echo "$log" | sed -n 's/^thermal solve: \(.*\), relative residual.*/\1/p')
  balance=$(echo "$log" | sed -n 's/^energy balance: |sum Q + Q_env| \/ max |Q| = \([^;]*\);.*/\1/p')
  echo "| $2 | $ranks | $taken | $thermal | $total | $peak | $balance |"
done
/usr/bin/python3 - "$work/T2.csv" "$work/T1.csv" <<'PY'
import csv, sys
a, b = ([row for row in csv.reader(open(p))][1:] for p in sys.argv[1:3])
worst = 0.0
for c in (6, 8, 9, 11, 12):
    largest = max(abs(float(r[c])) for r in a)
    worst = max(worst, max(abs(float(x[c]) - float(y[c])) for x, y in zip(a, b)) / largest)
print(f"\n2 ranks against one process: largest difference {worst:.2g} of a column's largest value (T, J, H, q, Q)")
PY
rm -f "$work"/T1.csv "$work"/T2.csv
fi
