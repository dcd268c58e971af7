#!/usr/bin/env bash
# Runs every libFuzzer harness of tests/fuzz for SECONDS each (default 600), growing a corpus in
# BUILD/corpus-<harness> from the committed seeds; prints executions per harness and fails on a
# finding (the crashing input is kept in BUILD/findings-<harness>/).
set -euo pipefail
build=${1:-build-fuzz}
seconds=${2:-600}
cd "$(dirname "$0")/../.."
status=0
report="$build/fuzz-report.txt"
: > "$report"
for harness in fuzz_obj fuzz_form_factors; do
    case $harness in
        fuzz_obj) seeds=tests/fuzz/corpus/obj ;;
        fuzz_form_factors) seeds=tests/fuzz/corpus/ff ;;
    esac
    corpus="$build/corpus-$harness"
    findings="$build/findings-$harness"
    mkdir -p "$corpus" "$findings"
    cp -n "$seeds"/* "$corpus"/ 2>/dev/null || true
    echo "== $harness: $seconds s"
    log="$build/$harness.log"
    if ! (cd "$findings" && "../$harness" "../corpus-$harness" -max_total_time="$seconds" -rss_limit_mb=2048 \
            -max_len=16384 -timeout=10 -print_final_stats=1 > "../$harness.log" 2>&1); then
        status=1
        echo "$harness: FINDING (see $log and $findings)"
        grep -E "ERROR|SUMMARY" "$log" | head -5
    fi
    runs=$(grep -oE "Done [0-9]+ runs in [0-9]+ second" "$log" | tail -1 || true)
    rate=$(grep -oE "average_exec_per_sec: *[0-9]+" "$log" | grep -oE "[0-9]+$" || true)
    units=$(ls "$corpus" | wc -l)
    echo "$harness: ${runs:-no summary}, ${rate:-?} exec/s, corpus $units inputs" | tee -a "$report"
done
exit $status
