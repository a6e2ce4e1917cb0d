#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""@file summarize.py
@brief Medians over the alternating runs (lavapipe-{before,after}-N.txt) of each setting's GPU ms,
       its ratio to spp1 in the same run, and each pass's GPU ms."""
import glob, re, statistics, sys, os

here = os.path.dirname(os.path.abspath(__file__))

def parse(path):
    frame, passes, cols, mode = {}, {}, None, None
    for line in open(path):
        f = line.split()
        if not f:
            continue
        if line.startswith('setting') and 'GPU ms' in line:
            mode = 'frame'; continue
        if line.startswith('per pass'):
            mode = 'pass'; continue
        if line.startswith('setting') and mode == 'pass':
            cols = f[1:]; continue
        if line.startswith(('method', 'CPBD', 'files')):
            mode = None if line.startswith('method') else mode
            continue
        if mode == 'frame':
            frame[f[0]] = float(f[1])
        elif mode == 'pass' and cols:
            passes[f[0]] = {c: float(v) for c, v in zip(cols, f[1:]) if v != '-'}
    return frame, passes

for v in ('before', 'after'):
    runs = [parse(p) for p in sorted(glob.glob(os.path.join(here, f'lavapipe-{v}-*.txt')))]
    print(f'## {v} ({len(runs)} runs, medians)')
    settings = list(runs[0][0].keys())
    cols = ['reproject', 'trace_mask', 'density', 'trace', 'shade', 'reconstruct', 'blend', 'taa']
    print('| setting | GPU ms | / median spp1 | median of x spp1 per run | ' + ' | '.join(cols) + ' |')
    print('|---' * (4 + len(cols)) + '|')
    spp = statistics.median(r[0]['spp1'] for r in runs)
    for s in settings:
        ms = statistics.median(r[0][s] for r in runs)
        x = statistics.median(r[0][s] / r[0]['spp1'] for r in runs)
        pm = []
        for c in cols:
            vals = [r[1][s][c] for r in runs if c in r[1].get(s, {})]
            pm.append(f'{statistics.median(vals):.1f}' if vals else '-')
        print(f'| {s} | {ms:.1f} | {ms / spp:.2f} | {x:.2f} | ' + ' | '.join(pm) + ' |')
    print('per run, GPU ms: ' + '; '.join(
        s + ' ' + ' '.join(f'{r[0][s]:.0f}' for r in runs) for s in settings))
    print()
