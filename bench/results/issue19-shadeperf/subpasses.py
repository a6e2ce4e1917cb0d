#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""@file subpasses.py
@brief Sub-pass medians of the `subpass` runs (builds with debug-subpass-timers.patch): per
       frame over all runs (median / 10th percentile) and paired (run i after - run i before)
       medians of each run's mean, for every gpu_*_ms column of the default setting.
usage: subpasses.py DIR TAG"""
import csv, glob, statistics, sys

d, tag = sys.argv[1], sys.argv[2]


def runs(build):
    out = []
    for i in range(1, 100):
        try:
            rows = [r for r in csv.DictReader(open(f"{d}/{tag}-{build}-{i}.csv"))
                    if r['setting'] == 'default' and r['warmup'] == '0']
        except FileNotFoundError:
            break
        out.append(rows)
    return out


b, a = runs('before'), runs('after')
cols = [c for c in b[0][0] if c.startswith('gpu_') and c.endswith('_ms') and c != 'gpu_ms']
print('| pass | before: median / p10 | after: median / p10 | paired median of after - before |')
print('|---|---|---|---|')
for c in cols:
    def stats(rs):
        v = sorted(float(r[c]) for run in rs for r in run if r[c])
        return statistics.median(v), v[len(v) // 10]
    mean = lambda run: statistics.mean(float(r[c]) for r in run)
    pd = statistics.median(mean(y) - mean(x) for x, y in zip(b, a))
    (mb, pb), (ma, pa) = stats(b), stats(a)
    print(f'| {c[4:-3]} | {mb:.1f} / {pb:.1f} | {ma:.1f} / {pa:.1f} | {pd:+.1f} |')
