"""One `hemirad formfactors` process timed as a whole, for the bench scripts (exact_factors.py,
real_meshes.py)."""

import subprocess
import sys
import tempfile
import time


def timed(hemirad, scene, out, extra, threads=1):
    """One formfactors process: (wall seconds, its own peak RSS in MiB, its report)."""
    command = [hemirad, "formfactors", scene, "-o", out, "--threads", str(threads)] + extra
    # GNU time forks from its own small process: ru_maxrss survives exec, so a child forked from
    # the calling Python process (which may hold the last F) would report that process's peak.
    peak_file = out + ".peak"
    with tempfile.TemporaryFile("w+") as log:
        started = time.perf_counter()
        status = subprocess.run(["/usr/bin/time", "-f", "%M", "-o", peak_file] + command, stdout=log,
                                stderr=subprocess.STDOUT).returncode
        seconds = time.perf_counter() - started
        log.seek(0)
        text = log.read()
    if status != 0:
        sys.exit("%s failed:\n%s" % (" ".join(command), text))
    return seconds, int(open(peak_file).read().split()[-1]) / 1024, text
