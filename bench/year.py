#!/usr/bin/env python3
"""A year of hours against one F (issue 37): `hemirad year` on a scene with the isotropic sky and with
Perez's sky (daylight coefficients), from a synthetic 8,760-hour EPW for Munich written here.

    python3 bench/year.py BINARY SCENE.obj [--sky perez] [--label NAME] [--threads N] [--ff F.hff] [--svf SVF.csv]
                          [--extra "--up y"]

--ff and --svf store F and the sky view factors on the first run and reuse them on the next (the
year "after F"); the report then leaves their stages out.

The weather is made up, not measured: each hour's clear-sky DNI and DHI from the sun's elevation, and
a day's cloudiness from a fixed random sequence that moves irradiance from the beam to the sky. It
has the shape of a real year (4,400 hours of daylight, overcast and clear days), which is what the
timing needs. Prints the stages' seconds from the command's report, the hours solved, the peak
memory (GNU time's maximum resident set) and the output sizes.
"""
import argparse
import math
import os
import random
import re
import subprocess
import sys
import tempfile

LATITUDE, LONGITUDE, ZONE = 48.13, 11.70, 1.0


def elevation(day, hour_middle):
    """Degrees, a textbook approximation (Cooper's declination, the equation of time left out)."""
    declination = 23.45 * math.sin(math.radians(360.0 * (284 + day) / 365.0))
    solar_time = hour_middle + (LONGITUDE - 15.0 * ZONE) / 15.0
    hour_angle = 15.0 * (solar_time - 12.0)
    lat, dec, h = map(math.radians, (LATITUDE, declination, hour_angle))
    return math.degrees(math.asin(math.sin(lat) * math.sin(dec) + math.cos(lat) * math.cos(dec) * math.cos(h)))


def write_epw(path):
    rng = random.Random(37)
    days = [31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31]
    lines = ["LOCATION,Munich synthetic,BY,DEU,hemirad bench/year.py,108660,%.2f,%.2f,%.1f,520.0" % (LATITUDE, LONGITUDE, ZONE),
             "DESIGN CONDITIONS,0", "TYPICAL/EXTREME PERIODS,0", "GROUND TEMPERATURES,0", "HOLIDAYS/DAYLIGHT SAVINGS,No,0,0,0",
             "COMMENTS 1,Synthetic: clear-sky irradiance and a random cloudiness per day (not measured data)",
             "COMMENTS 2,Irradiance in Wh/m2 per hour ending at the hour (local standard time, UTC+1)",
             "DATA PERIODS,1,1,Data,Sunday, 1/1,12/31"]
    day = 0
    for month, count in enumerate(days, start=1):
        for d in range(1, count + 1):
            day += 1
            cloud = rng.random() ** 0.7
            for hour in range(1, 25):
                s = math.sin(math.radians(max(0.0, elevation(day, hour - 0.5))))
                clear_dni = 1000.0 * math.exp(-0.17 / s) if s > 0.02 else 0.0
                clear_dhi = 90.0 * s ** 0.6 if s > 0 else 0.0
                dni = (1.0 - cloud) * clear_dni
                dhi = clear_dhi + cloud * 280.0 * s
                lines.append("2001,%d,%d,%d,60,?9?9?9?9E0?9?9?9?9?9?9?9?9?9?9?9?9?9?9?9*9*9?9?9?9,10.0,5.0,70,95000,0,0,300,%d,%d,%d,"
                             "0,0,0,0,180,2.0,5,3,20.0,77777,9,999999999,15,0.1,0,88,0.2,0.0,0.0"
                             % (month, d, hour, round(dni * s + dhi), round(dni), round(dhi)))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("binary")
    ap.add_argument("scene")
    ap.add_argument("--sky", default="isotropic")
    ap.add_argument("--label", default=None)
    ap.add_argument("--threads", default="0")
    ap.add_argument("--ff", default=None, help="F stored here (reused when present)")
    ap.add_argument("--svf", default=None, help="sky view factors stored here (reused when present)")
    ap.add_argument("--extra", default="", help="more options for hemirad year, e.g. '--up y' for street64k")
    a = ap.parse_args()
    work = tempfile.mkdtemp(prefix="hemirad-year-")
    epw = os.path.join(work, "munich_synthetic.epw")
    write_epw(epw)
    annual, hourly = os.path.join(work, "annual.csv"), os.path.join(work, "total.npy")
    timed = ["/usr/bin/time", "-v"] if os.path.exists("/usr/bin/time") else []  # Debian's package "time"
    cmd = timed + [a.binary, "year", a.scene, "--weather", epw, "--sky", a.sky, "--threads", a.threads,
           "-o", annual, "--hourly", hourly]
    cmd += ["--ff", a.ff] if a.ff else []
    cmd += ["--svf", a.svf] if a.svf else []
    cmd += a.extra.split()
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(r.stdout + r.stderr)
    text = r.stdout + r.stderr
    label = a.label or os.path.basename(a.scene)
    year = re.search(r"year: (\d+) hours with sun or sky solved in ([\d.e+-]+) s \(([\d.e+-]+) ms per hour\)", text)
    parts = re.search(r"per hour: (sun [^;\n]*)", text)
    peak = re.search(r"Maximum resident set size \(kbytes\): (\d+)", text)
    stages = {m.group(1).strip(): float(m.group(2)) for m in re.finditer(r"^(\S[\w ,()-]*?)\s{2,}([\d.]+)$", text, re.M)}
    print("%s, sky %s: %s hours in %.1f s (%.1f ms per hour); daylight coefficients %.1f s, sky view factors %.1f s, "
          "form factors %.1f s, total %.1f s; peak memory %.0f MiB; annual.csv %.1f MiB, total.npy %.1f MiB"
          % (label, a.sky, year.group(1), float(year.group(2)), float(year.group(3)), stages.get("daylight coefficients", 0.0),
             stages.get("sky view factors", 0.0), stages.get("form factors", 0.0), stages.get("total", 0.0),
             int(peak.group(1)) / 1024.0 if peak else float("nan"), os.path.getsize(annual) / 2**20, os.path.getsize(hourly) / 2**20))
    if parts:
        print("  per hour: " + parts.group(1))


if __name__ == "__main__":
    main()
