#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""@file issue19_table.py
@brief Issue 19 item 1: one table (CSV on stdout, markdown with --md) of the runs that
bench/issue19_defaults.sh wrote, one row per case and completed setting, from the per-frame
files (frames/NAME.csv), with the summary's definitions: relMSE over the scored frames,
temporal and stereo difference and GPU ms over the frames after the warm-up; `beats` marks a
setting below `default` on all three quality figures.

Usage: python3 bench/issue19_table.py OUT [--md]
"""
import csv
import os
import sys

CASES = ("cornell", "glossy", "candle", "hololens", "strands", "headturn", "edges", "specular",
         "moving", "disocclusion")
FIGURES = ("relmse", "temporal_msd", "stereo_msd")


def mean(values):
    values = [float(v) for v in values if v not in ("", None)]
    return sum(values) / len(values) if values else float("nan")


def setting_means(path):
    with open(path, newline="") as f:
        lines = [l for l in f if not l.startswith("#")]
    rows = list(csv.DictReader(lines))
    measured = [r for r in rows if r["warmup"] == "0"]
    scored = [r for r in measured if r["scored"] == "1"]
    return {"relmse": mean(r["relmse"] for r in scored),
            "temporal_msd": mean(r["temporal_msd"] for r in measured),
            "stereo_msd": mean(r["stereo_msd"] for r in measured),
            "gpu_ms": mean(r["gpu_ms"] for r in measured),
            "rays_per_px": mean(r["rays_per_px"] for r in measured),
            "frames": len(measured), "scored": len(scored)}


def table(out, order):
    for case in CASES:
        d = os.path.join(out, case, "frames")
        if not os.path.isdir(d):
            continue
        done = {n[:-4]: setting_means(os.path.join(d, n)) for n in os.listdir(d)
                if n.endswith(".csv")}
        base = done.get("default")
        for name in sorted(done, key=lambda n: order.index(n) if n in order else 99):
            m = done[name]
            beats = base is not None and name != "default" and all(m[k] < base[k] for k in FIGURES)
            yield case, name, m, beats


def main():
    out, md = sys.argv[1], "--md" in sys.argv[2:]
    here = os.path.dirname(os.path.abspath(__file__))
    order = []
    with open(os.path.join(here, "issue19_defaults.settings")) as f:
        for line in f:
            if "name=" in line and not line.startswith("#"):
                order.append(line.split("name=")[1].split(",")[0].strip())
    if md:
        print("| case | setting | relMSE | temporal | stereo | GPU ms | below default on all 3 |")
        print("|---|---|---|---|---|---|---|")
    else:
        print("case,setting,relmse,temporal_msd,stereo_msd,gpu_ms,rays_per_px,frames,scored,"
              "beats_default")
    for case, name, m, beats in table(out, order):
        if md:
            print("| %s | %s | %.4g | %.3g | %.3g | %.0f | %s |" % (
                case, name, m["relmse"], m["temporal_msd"], m["stereo_msd"], m["gpu_ms"],
                "yes" if beats else ""))
        else:
            print("%s,%s,%.6g,%.6g,%.6g,%.6g,%.6g,%d,%d,%d" % (
                case, name, m["relmse"], m["temporal_msd"], m["stereo_msd"], m["gpu_ms"],
                m["rays_per_px"], m["frames"], m["scored"], beats))


if __name__ == "__main__":
    main()
