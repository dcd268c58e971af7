#!/usr/bin/env bash
# street64k F (hemisphere, 3072 directions) on 1 rank x 1 thread, 2 ranks x 1 thread and 1 process x
# 2 threads, then the distributed solve on 1 vs 2 ranks; wall time and peak RSS per rank from
# /usr/bin/time. Usage: bench/mpi_scaling.sh BUILD_DIR [SAMPLES]; writes bench/results/mpi_scaling.md.
source "$(dirname "$0")/setup.sh" "${1:-build}"
samples=${2:-3072}
/usr/bin/python3 "$root/scenes/generators/street64k.py" "$work" >/dev/null
scene="$work/street64k.obj"
mpirun=(mpirun --allow-run-as-root --oversubscribe)
# GNU time's %e (wall s) and %M (peak RSS KiB) per process, one line each.
timed() { local out=$1; shift; /usr/bin/env time -f "%e %M" -a -o "$out" "$@"; }

measure() {  # LABEL RANKS THREADS COMMAND...
  local label=$1 ranks=$2 threads=$3; shift 3
  local times="$work/$label.time"
  : >"$times"
  local start end
  start=$(date +%s.%N)
  if [ "$ranks" -gt 0 ]; then
    "${mpirun[@]}" -np "$ranks" /usr/bin/env time -f "%e %M" -a -o "$times" "$hemirad" "$@" --threads "$threads" \
      >"$work/$label.log" 2>&1
  else
    OMP_NUM_THREADS=$threads timed "$times" "$hemirad" "$@" --threads "$threads" >"$work/$label.log" 2>&1
  fi
  end=$(date +%s.%N)
  local ff rss
  ff=$(awk '/^form factors /{print $3}' "$work/$label.log" | tail -1)
  rss=$(awk '{printf "%s%.0f", (NR>1?" / ":""), $2/1024}' "$times")
  printf '| %s | %s | %s | %s | %.2f | %s |\n' "$label" "$([ "$ranks" -gt 0 ] && echo "$ranks" || echo 1)" \
    "$threads" "$ff" "$(python3 -c "print($end - $start)")" "$rss"
}

{
  echo "# street64k: form factors and solve across MPI ranks"
  echo
  echo "Hemisphere rays, $samples directions, 1 origin; \`hemirad formfactors\` (F written by rank 0) and"
  echo "\`hemirad solve --solver bicgstab\` (PETSc; F reused from the file). Measured by bench/mpi_scaling.sh"
  echo "on $(nproc) cores, $(date -u +%Y-%m-%d). \"form factors\" is the rows' wall time from the timing table;"
  echo "\"job\" is the whole command; peak RSS per rank in MiB."
  echo
  echo "| run | ranks | threads per rank | form factors s | job s | peak RSS MiB |"
  echo "|---|---|---|---|---|---|"
  measure "F, 1 process x 1 thread" 0 1 formfactors "$scene" -o "$work/F1.hff" --samples "$samples"
  measure "F, 2 ranks x 1 thread" 2 1 formfactors "$scene" -o "$work/F2.hff" --samples "$samples"
  measure "F, 1 process x 2 threads" 0 2 formfactors "$scene" -o "$work/F3.hff" --samples "$samples"
  cmp -s "$work/F1.hff" "$work/F2.hff" && echo && echo "F from 2 ranks is byte-identical to F from 1 process."
  echo
  echo "| run | ranks | threads per rank | form factors s | job s | peak RSS MiB |"
  echo "|---|---|---|---|---|---|"
  measure "solve, 1 rank" 1 1 solve "$scene" --ff "$work/F1.hff" --solver bicgstab -o "$work/B1.csv"
  measure "solve, 2 ranks" 2 1 solve "$scene" --ff "$work/F1.hff" --solver bicgstab -o "$work/B2.csv"
  echo
  echo "Solve lines of the 2-rank run:"
  echo '```'
  grep -E "^solve|^  ranks|^solve \(" "$work/solve, 2 ranks.log" || true
  echo '```'
} | tee "$root/bench/results/mpi_scaling.md"
