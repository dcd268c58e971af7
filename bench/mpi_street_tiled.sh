#!/usr/bin/env bash
# The scale-out job end to end: street64k repeated 4 times along the street (~250k patches) on 2 MPI
# ranks, F computed on the ranks and stored sharded (each rank writes its own shard), solved with
# PETSc where the rows are; then `hemirad info` on the shards (one process, one shard in memory at a
# time) and a second solve that reads the shards. Wall time and peak RSS per rank from /usr/bin/time.
# Usage: bench/mpi_street_tiled.sh BUILD_DIR [SAMPLES]; writes bench/results/mpi_street_tiled.md.
source "$(dirname "$0")/setup.sh" "${1:-build}"
samples=${2:-3072}
generated=$(/usr/bin/python3 "$root/scenes/generators/street64k.py" "$work" --tiles 4)
scene="$work/street64k_x4.obj"
mpirun=(mpirun --allow-run-as-root --oversubscribe)

run() {  # LABEL RANKS COMMAND...: one table row; the log is kept as $work/LABEL.log
  local label=$1 ranks=$2; shift 2
  local times="$work/$label.time" start end
  : >"$times"
  start=$(date +%s.%N)
  if [ "$ranks" -gt 0 ]; then
    "${mpirun[@]}" -np "$ranks" /usr/bin/env time -f "%e %M" -a -o "$times" "$hemirad" "$@" >"$work/$label.log" 2>&1
  else
    /usr/bin/env time -f "%e %M" -a -o "$times" "$hemirad" "$@" >"$work/$label.log" 2>&1
  fi
  end=$(date +%s.%N)
  printf '| %s | %s | %.1f | %s |\n' "$label" "$([ "$ranks" -gt 0 ] && echo "$ranks" || echo 1)" \
    "$(python3 -c "print($end - $start)")" "$(awk '{printf "%s%.0f", (NR>1?" / ":""), $2/1024}' "$times")"
}

{
  echo "# A tiled street (~250k patches) end to end on 2 MPI ranks, F sharded"
  echo
  echo "\`scenes/generators/street64k.py --tiles 4\`: $generated. Hemisphere rays, $samples"
  echo "directions, 1 origin, 1 thread per rank; measured by bench/mpi_street_tiled.sh on $(nproc) cores,"
  echo "$(date -u +%Y-%m-%d). \"job\" is the whole command (scene, BVH, F, shards written, solve, CSV);"
  echo "peak RSS per rank in MiB."
  echo
  echo "| run | ranks | job s | peak RSS MiB |"
  echo "|---|---|---|---|"
  run "solve from scratch, F stored sharded" 2 solve "$scene" --samples "$samples" --threads 1 --ff "$work/F.hff" \
    --shards --solver bicgstab -o "$work/B.csv"
  run "info on the shards (one process)" 0 info "$work/F.hff"
  run "solve again, each rank reading its shard" 2 solve "$scene" --samples "$samples" --threads 1 \
    --ff "$work/F.hff" --solver bicgstab -o "$work/B2.csv"
  echo
  cmp -s "$work/B.csv" "$work/B2.csv" && echo "Both solves wrote the same B.csv." && echo
  echo "The first job's report (rank 0):"
  echo '```'
  grep -E "^scene|^form factors:|^  ranks|^  row sums|^wrote|^solve:" "$work/solve from scratch, F stored sharded.log" || true
  sed -n '/^stage/,/^total/p' "$work/solve from scratch, F stored sharded.log"
  echo '```'
  echo
  echo "\`hemirad info\` on the manifest:"
  echo '```'
  grep -E "valid|patches|nonzeros|row sums|shard [0-9]" "$work/info on the shards (one process).log" || true
  echo '```'
  echo
  echo "The second job's F lines:"
  echo '```'
  grep -E "^form factors|^solve \(|^load F|^total" "$work/solve again, each rank reading its shard.log" || true
  echo '```'
} | tee "$root/bench/results/mpi_street_tiled.md"
