#!/usr/bin/env python3
"""Sensor points (issue 37): a grid of about 10^5 sensors against street64k by rays, and the rays
against the exact factors on a subset of the same grid and on district25k.

    python3 bench/sensors.py BUILD_DIR [WORK_DIR]

Cases, each a whole `hemirad sensors` process (wall seconds, its own peak RSS by GNU time, 2 threads
unless --threads says otherwise):
- street64k less its sky dome (61,823 patches, 469 mirror panes): a grid over its ground at 0.19 m
  spacing, 1.1 m up (115,431 sensors), --sensor-estimator auto (rays);
- every 500th sensor of that grid (231), exact and by rays: the sky view factors' error, and what
  the sensors see reflected from radiosity 1 on every patch and from random radiosity in 0..1;
- district25k (scenes/generators/district.py --preset 25k): a grid over its ground at 20 m, 1.5 m up
  (683 sensors), exact and by rays at 1024 .. 65536 rays.
Prints Markdown.
"""
import csv
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
import scipy.io

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(hemirad, args):
    """One sensors process: (wall seconds, peak RSS MiB, report)."""
    with tempfile.NamedTemporaryFile("r") as peak, tempfile.TemporaryFile("w+") as log:
        started = time.perf_counter()
        status = subprocess.run(["/usr/bin/time", "-f", "%M", "-o", peak.name, hemirad, "sensors"] + args,
                                stdout=log, stderr=subprocess.STDOUT).returncode
        seconds = time.perf_counter() - started
        log.seek(0)
        text = log.read()
        if status != 0:
            sys.exit("hemirad sensors %s failed:\n%s" % (" ".join(args), text))
        return seconds, int(open(peak.name).read().split()[-1]) / 1024, text


def stage(report, name):
    for line in report.splitlines():
        if line.startswith(name + " "):
            return float(line.split()[-1])
    return float("nan")


def sky_view(path):
    rows = list(csv.reader(open(path)))
    column = rows[0].index("sky_view_factor")
    return np.array([float(r[column]) for r in rows[1:]])


def errors(exact_csv, rays_csv, exact_mtx=None, rays_mtx=None):
    d = sky_view(rays_csv) - sky_view(exact_csv)
    out = {"svf_rms": np.sqrt((d * d).mean()), "svf_max": abs(d).max(), "svf_mean": d.mean()}
    if exact_mtx:
        A, B = scipy.io.mmread(exact_mtx).tocsr(), scipy.io.mmread(rays_mtx).tocsr()
        J = np.random.default_rng(1).random(A.shape[1])
        a, b = A @ J, B @ J
        out["random_rel_rms"] = np.sqrt(((b - a) ** 2).mean()) / a.mean()
        out["nnz_exact"], out["nnz_rays"] = A.nnz / A.shape[0], B.nnz / B.shape[0]
    return out


def main():
    build = sys.argv[1]
    work = sys.argv[2] if len(sys.argv) > 2 else tempfile.mkdtemp(prefix="hemirad-sensors-")
    hemirad = os.path.join(build, "hemirad")
    py = "/usr/bin/python3"
    subprocess.run([py, os.path.join(ROOT, "scenes/generators/street64k.py"), work], check=True, stdout=subprocess.DEVNULL)
    street = os.path.join(work, "street_nosky.obj")
    with open(os.path.join(work, "street64k.obj")) as src, open(street, "w") as dst:
        sky = False
        for line in src:
            if line.startswith("o "):
                sky = line.split()[1] == "sky"
            if not (sky and line.startswith("f ")):
                dst.write(line)
    subprocess.run([py, os.path.join(ROOT, "scenes/generators/district.py"), work, "--preset", "25k"], check=True,
                   stdout=subprocess.DEVNULL)
    district = os.path.join(work, "district25k.obj")
    threads = ["--threads", "2"]

    print("# Sensor points: 10^5 against street64k, rays against the exact factors (issue 37)")
    print()
    print("Whole `hemirad sensors` processes on 2 threads (wall seconds, the sensor-factors stage, peak RSS by GNU"
          " time). The sky view errors are the rays' against the exact factors of the same sensors.")
    print()
    print("| case | sensors | estimator | wall s | sensor factors s | peak MiB | nonzeros / sensor | sky view error rms / max |")
    print("|---|---|---|---|---|---|---|---|")
    grid = os.path.join(work, "grid.csv")
    seconds, peak, report = run(hemirad, [street, "--up", "y", "--grid", "ground", "--spacing", "0.19", "--height", "1.1",
                                          "-o", grid] + threads)
    count = len(sky_view(grid))
    nonzeros = int(report.split(" nonzeros")[0].split()[-1])
    print("| street64k ground grid, 0.19 m, 1.1 m up | %d | auto (rays, 4096) | %.1f | %.1f | %.0f | %.0f | (below) |" % (
        count, seconds, stage(report, "sensor factors"), peak, nonzeros / count))

    rows = list(csv.reader(open(grid)))
    subset = os.path.join(work, "subset.csv")
    with open(subset, "w") as f:
        f.write("x,y,z,nx,ny,nz,name\n")
        for r in rows[1::500]:
            f.write(",".join(r[2:8] + [r[1]]) + "\n")
    runs = {}
    for estimator in ("exact", "rays"):
        out = os.path.join(work, "subset_%s" % estimator)
        runs[estimator] = run(hemirad, [street, "--up", "y", "--sensors", subset, "--sensor-estimator", estimator,
                                        "-o", out + ".csv", "--factors", out + ".mtx"] + threads)
    e = errors(os.path.join(work, "subset_exact.csv"), os.path.join(work, "subset_rays.csv"),
               os.path.join(work, "subset_exact.mtx"), os.path.join(work, "subset_rays.mtx"))
    for estimator in ("exact", "rays"):
        seconds, peak, report = runs[estimator]
        print("| street64k, every 500th of the grid | %d | %s | %.1f | %.2f | %.0f | %.0f | %s |" % (
            len(rows[1::500]), estimator, seconds, stage(report, "sensor factors"), peak,
            e["nnz_" + estimator], "-" if estimator == "exact" else "%.1e / %.1e" % (e["svf_rms"], e["svf_max"])))
    street_random = e["random_rel_rms"]

    district_rows = []
    exact_csv = os.path.join(work, "district_exact.csv")
    seconds, peak, report = run(hemirad, [district, "--grid", "ground", "--spacing", "20", "--height", "1.5",
                                          "--sensor-estimator", "exact", "-o", exact_csv] + threads)
    print("| district25k ground grid, 20 m, 1.5 m up | %d | exact | %.1f | %.2f | %.0f | | - |" % (
        len(sky_view(exact_csv)), seconds, stage(report, "sensor factors"), peak))
    for rays in (1024, 4096, 16384, 65536):
        out = os.path.join(work, "district_rays%d.csv" % rays)
        seconds, peak, report = run(hemirad, [district, "--grid", "ground", "--spacing", "20", "--height", "1.5",
                                              "--sensor-estimator", "rays", "--sensor-rays", str(rays), "-o", out] + threads)
        e = errors(exact_csv, out)
        print("| district25k ground grid | %d | rays, %d | %.1f | %.2f | %.0f | | %.1e / %.1e (mean %.0e) |" % (
            len(sky_view(out)), rays, seconds, stage(report, "sensor factors"), peak, e["svf_rms"], e["svf_max"],
            e["svf_mean"]))
    print()
    print("What street64k's subset sees reflected from a random radiosity (0..1 per patch, no correlation"
          " between neighbours: the hardest case for rays), rays against exact: %.1e of the mean, rms." % street_random)


if __name__ == "__main__":
    main()
