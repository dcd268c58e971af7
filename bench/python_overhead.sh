#!/usr/bin/env bash
# The Python module's overhead over the hemirad command (issue 11): cornell13k, load + F + solve and
# load + F alone, each as a whole process (wall time, peak RSS), alternating, median of REPEATS.
# Usage: bench/python_overhead.sh BUILD_DIR [REPEATS]; writes bench/results/python_overhead.md.
source "$(dirname "$0")/setup.sh" "${1:-build}"
repeats=${2:-3}
build="$(cd "${1:-build}" && pwd)"
/usr/bin/python3 "$root/scenes/generators/cornell13k.py" "$work" >/dev/null
cat > "$work/f.py" <<'PY'
import sys, hemirad
scene = hemirad.load(sys.argv[1])
F, report = hemirad.form_factors(scene)
if sys.argv[2] == "solve":
    B, _ = hemirad.solve(scene, F)
PY
/usr/bin/python3 - "$hemirad" "$work" "$build/python" "$repeats" <<'PY' | tee "$root/bench/results/python_overhead.md"
import os, statistics, subprocess, sys, time
hemirad, work, pythonpath, repeats = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
scene = os.path.join(work, "cornell13k.obj")
env = dict(os.environ, PYTHONPATH=pythonpath)
runs = {
    ("F + solve", "CLI"): [hemirad, "solve", scene, "-o", "/dev/null", "--format", "csv", "--quiet"],
    ("F + solve", "Python"): [sys.executable, os.path.join(work, "f.py"), scene, "solve"],
    ("F", "CLI"): [hemirad, "formfactors", scene, "-o", "/dev/null", "--quiet"],
    ("F", "Python"): [sys.executable, os.path.join(work, "f.py"), scene, "f"],
    ("import", "Python"): [sys.executable, "-c", "import hemirad"],
}
times = {key: [] for key in runs}
rss = {key: 0 for key in runs}
for _ in range(repeats):
    for key, command in runs.items():
        started = time.perf_counter()
        child = subprocess.Popen(command, env=env, stdout=subprocess.DEVNULL)
        _, status, usage = os.wait4(child.pid, 0)  # this child's own peak RSS
        times[key].append(time.perf_counter() - started)
        assert os.waitstatus_to_exitcode(status) == 0, command
        rss[key] = max(rss[key], usage.ru_maxrss)
median = {key: statistics.median(t) for key, t in times.items()}
print("# Python module overhead over the CLI (issue 11)\n")
print(f"cornell13k (12,922 patches, default hemisphere settings: 3072 samples, analytic estimator), whole")
print(f"processes, median of {repeats} alternating runs, {os.cpu_count()} cores, {time.strftime('%Y-%m-%d', time.gmtime())};")
print("bench/python_overhead.sh. The CLI writes its output to /dev/null; Python keeps F and B in memory.")
print("Peak RSS: the process's own (wait4), the largest of its runs.\n")
print("| job | CLI s | Python s | Python / CLI | CLI peak MiB | Python peak MiB |")
print("|---|---|---|---|---|---|")
for job in ("F + solve", "F"):
    cli, py = median[(job, "CLI")], median[(job, "Python")]
    print(f"| {job} | {cli:.2f} | {py:.2f} | {py / cli:.3f} | {rss[(job, 'CLI')] / 1024:.0f} | {rss[(job, 'Python')] / 1024:.0f} |")
print(f"\n`import hemirad` alone (numpy, scipy, the module): {median[('import', 'Python')]:.2f} s.")
PY
