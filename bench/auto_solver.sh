#!/usr/bin/env bash
# What `--solver auto` should pick above 2000 patches: SOR or Gauss-Seidel (ordered sweeps, one
# core) or Jacobi (parallel sweeps), on cornell13k with F reused, for 1 thread up to the cores this machine has.
# Usage: bench/auto_solver.sh BUILD_DIR; writes bench/results/auto_solver.md.
source "$(dirname "$0")/setup.sh" "${1:-build}"
/usr/bin/python3 "$root/scenes/generators/cornell13k.py" "$work" >/dev/null
"$hemirad" formfactors "$work/cornell13k.obj" -o "$work/F.hff" --quiet
cores=$(nproc)
{
  echo "# --solver auto above 2000 patches: SOR, Gauss-Seidel or Jacobi by thread count"
  echo
  echo "cornell13k (12,922 patches), F reused from a file, tolerance 1e-6; the solve stage of the"
  echo "timing table, measured by bench/auto_solver.sh on $cores cores, $(date -u +%Y-%m-%d)."
  echo
  echo "| threads | sor s (sweeps) | gauss-seidel s (sweeps) | jacobi s (sweeps) | auto picks |"
  echo "|---|---|---|---|---|"
  for t in $(seq 1 "$cores"); do
    row="| $t |"
    for s in sor gauss-seidel jacobi; do
      log=$("$hemirad" solve "$work/cornell13k.obj" --ff "$work/F.hff" --solver "$s" --threads "$t" -o "$work/B.csv")
      seconds=$(echo "$log" | awk '/^solve \(/{print $NF}')
      sweeps=$(echo "$log" | awk '/converged in/{for (k = 1; k <= NF; ++k) if ($k == "in") {print $(k + 1); exit}}')
      row="$row $seconds ($sweeps) |"
    done
    picked=$("$hemirad" solve "$work/cornell13k.obj" --ff "$work/F.hff" --threads "$t" -o "$work/B.csv" |
             awk '/^solve \(/{print $2}' | tr -d '()')
    echo "$row $picked |"
  done
} | tee "$root/bench/results/auto_solver.md"
