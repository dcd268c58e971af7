#!/usr/bin/python3
"""Plots of `hemirad bench` results: error against time per scene and method, and time against
samples beside the reference system's published times (physics.md section 7, their hardware).

usage: /usr/bin/python3 bench/plot.py RESULTS.csv [RESULTS.csv ...] --out DIR
Needs Debian's python3-matplotlib (installed by scripts/install-deps.sh)."""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# The reference system (i7-8700K, 12 threads, GTX 1070 Ti), full-pipeline seconds by sample count.
REFERENCE = {
    "samples": [96, 384, 768, 1536, 3072],
    "Cornell (12,922 patches), hemicube/OpenGL": [7, 10, 31, 251, 992],
    "Cornell (12,922 patches), hemisphere/Embree": [3, 30, 116, 446, 1778],
    "Street (64,202 patches), OpenGL": [68, 128, 248, 1213, 4018],
    "Street (64,202 patches), Embree": [14, 174, 665, 2565, 7511],
}


def number(row, key):
    value = row.get(key, "")
    return float(value) if value not in ("", None) else None


def load(paths):
    rows = []
    for path in paths:
        with open(path, newline="") as f:
            rows.extend(csv.DictReader(f))
    return rows


def series_key(row):
    if row["method"] == "hemicube":
        return "hemicube (R sweep)"
    fixed = ", fixed directions" if row.get("directions") == "fixed" else ""
    post = ", " + row["postprocess"] if row.get("postprocess") else ""
    if row.get("estimator") == "analytic":
        return "hemisphere, analytic estimator (origins sweep)" + post
    return "hemisphere, %s origin%s%s%s" % (row["origins"], "" if row["origins"] == "1" else "s", fixed, post)


def scene_panels(rows, metric):
    """One axis per scene, each with that scene's series of rows that have `metric`, sorted by F time."""
    scenes = sorted({r["scene"] for r in rows})
    fig, axes = plt.subplots(1, len(scenes), figsize=(6 * len(scenes), 4.6), squeeze=False)
    panels = []
    for ax, scene in zip(axes[0], scenes):
        groups = {}
        for r in rows:
            if r["scene"] == scene and number(r, metric) is not None:
                groups.setdefault(series_key(r), []).append(r)
        for group in groups.values():
            group.sort(key=lambda r: number(r, "t_ff"))
        panels.append((ax, scene, sorted(groups.items())))
    return fig, panels


def finish_panel(ax, title, xlabel, ylabel):
    ax.set_title(title)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)


def error_vs_time(rows, out):
    fig, panels = scene_panels(rows, "err_mean")
    for ax, scene, series in panels:
        for key, group in series:
            t = [number(r, "t_bvh") + number(r, "t_ff") for r in group]
            e = [number(r, "err_mean") for r in group]
            ax.loglog(t, e, "o-", label=key)
            for r, x, y in zip(group, t, e):
                tag = r["resolution"] if r["method"] == "hemicube" else r["samples"]
                if r.get("estimator") == "analytic":
                    tag = "%s origin%s" % (r["origins"], "" if r["origins"] == "1" else "s")
                ax.annotate(tag, (x, y), textcoords="offset points", xytext=(4, 4), fontsize=7)
        patches = series[-1][1][0]["patches"] if series else "?"
        finish_panel(ax, "%s (%s patches)" % (scene, patches), "form-factor time [s] (this machine, 2 cores)",
                     "mean per-row |F - F_ref|")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "error_vs_time.png"), dpi=110)


def radiosity_vs_time(rows, out):
    fig, panels = scene_panels(rows, "b_rel_mean")
    for ax, scene, series in panels:
        for key, group in series:
            t = [number(r, "t_bvh") + number(r, "t_ff") + number(r, "t_solve") for r in group]
            ax.loglog(t, [number(r, "b_rel_mean") for r in group], "o-", label=key)
        finish_panel(ax, scene, "form factors + solve [s]", "mean |B - B_ref| / mean B_ref")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "radiosity_error_vs_time.png"), dpi=110)


def time_vs_samples(rows, out):
    fig, ax = plt.subplots(figsize=(7.5, 5))
    for label, times in REFERENCE.items():
        if label == "samples":
            continue
        ax.loglog(REFERENCE["samples"], times, "--", marker="s", alpha=0.6,
                  label="reference system, " + label + " [their i7-8700K + GTX 1070 Ti]")
    groups = {}
    for r in rows:
        if (r["method"] == "hemisphere" and r["origins"] == "1" and r.get("estimator", "rays") == "rays"
                and not r.get("postprocess")):
            groups.setdefault((r["scene"], r.get("directions") == "fixed"), []).append(r)
    for (scene, fixed), group in sorted(groups.items()):
        group.sort(key=lambda r: number(r, "samples"))
        ax.loglog([number(r, "samples") for r in group], [number(r, "t_total") for r in group], "o-", linewidth=2,
                  label="Hemirad hemisphere, %s%s (%s patches) [this 2-core VM]" % (
                      scene, ", fixed directions" if fixed else "", group[0]["patches"]))
    ax.set_xlabel("directions per patch (samples)")
    ax.set_ylabel("form factors + solve [s]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "time_vs_samples.png"), dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", nargs="+")
    parser.add_argument("--out", default="bench")
    args = parser.parse_args()
    rows = load(args.results)
    if not rows:
        sys.exit("plot.py: no results in " + ", ".join(args.results))
    os.makedirs(args.out, exist_ok=True)
    error_vs_time(rows, args.out)
    radiosity_vs_time(rows, args.out)
    time_vs_samples(rows, args.out)
    print("plot.py: wrote error_vs_time.png, radiosity_error_vs_time.png, time_vs_samples.png to " + args.out)


if __name__ == "__main__":
    main()
