#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""@file summarize.py
@brief Medians over alternating runs (TAG-{before,after}-N.txt in DIR) of each setting's GPU ms,
       its ratio to spp1 in the same run, and each pass's GPU ms (issue19-speed3's summary, with
       the pass columns taken from the files: "trace_mask" is gone after the fusion).
usage: summarize.py DIR TAG"""
import csv, glob, os, re, statistics, sys


def parse(path):
    frame, passes, cols, mode, load = {}, {}, None, None, None
    for line in open(path):
        f = line.split()
        if not f:
            continue
        if 'load average' in line:
            load = float(re.search(r'load average: ([0-9.]+)', line).group(1))
            continue
        if line.startswith('setting') and 'GPU ms' in line:
            mode = 'frame'
            continue
        if line.startswith('per pass'):
            mode = 'pass'
            continue
        if line.startswith('setting') and mode == 'pass':
            cols = f[1:]
            continue
        if line.startswith(('method', 'CPBD', 'files')):
            mode = None if line.startswith('method') else mode
            continue
        if mode == 'frame':
            frame[f[0]] = float(f[1])
        elif mode == 'pass' and cols:
            passes[f[0]] = {c: float(v) for c, v in zip(cols, f[1:]) if v != '-'}
    return frame, passes, load


def main(folder, tag):
    order = ['reproject', 'trace_mask', 'density', 'trace', 'shade', 'reconstruct', 'taa', 'blend']
    for v in ('before', 'after'):
        files = sorted(glob.glob(os.path.join(folder, f'{tag}-{v}-*.txt')))
        runs = [r for r in (parse(p) for p in files) if 'spp1' in r[0]]  # complete runs
        if not runs:
            continue
        loads = [r[2] for r in runs if r[2] is not None]
        print(f'## {v} ({len(runs)} runs, medians; load average {min(loads):.1f}-{max(loads):.1f})')
        print('| setting | GPU ms | / median spp1 | median of x spp1 per run | ' +
              ' | '.join(order) + ' | reproject + trace_mask + density |')
        print('|---' * (5 + len(order)) + '|')
        spp = statistics.median(r[0]['spp1'] for r in runs)
        for s in runs[0][0]:
            ms = statistics.median(r[0][s] for r in runs)
            x = statistics.median(r[0][s] / r[0]['spp1'] for r in runs)
            pm, fixed = [], []
            for c in order:
                vals = [r[1][s][c] for r in runs if c in r[1].get(s, {})]
                pm.append(f'{statistics.median(vals):.1f}' if vals else '-')
            for r in runs:  # reproject + trace_mask + density per run (the fused passes)
                p = r[1].get(s, {})
                if 'reproject' in p:
                    fixed.append(sum(p.get(c, 0.0) for c in order[:3]))
            fx = f'{statistics.median(fixed):.1f}' if fixed else '-'
            print(f'| {s} | {ms:.1f} | {ms / spp:.2f} | {x:.2f} | ' + ' | '.join(pm) + f' | {fx} |')
        print('per run, GPU ms: ' + '; '.join(
            s + ' ' + ' '.join(f'{r[0][s]:.0f}' for r in runs) for s in runs[0][0]))
        print()


def frames(folder, tag, v):
    """Every measured frame's pass times (bench.csv of each run, warm-up left out)."""
    rows = []
    for p in sorted(glob.glob(os.path.join(folder, f'{tag}-{v}-*.csv'))):
        rows += [r for r in csv.DictReader(open(p)) if r['warmup'] == '0']
    return rows


def per_frame(folder, tag):
    """Per pass over all measured frames of all runs: the median and the 10th percentile (a
    frame the machine's other load preempted is slower, never faster)."""
    cols = ['gpu_ms', 'gpu_reproject_ms', 'gpu_trace_mask_ms', 'gpu_density_ms', 'gpu_trace_ms',
            'gpu_shade_ms', 'gpu_reconstruct_ms', 'gpu_taa_ms', 'gpu_blend_ms']
    print('## per frame, all runs: median / 10th percentile, GPU ms')
    print('| build | setting | frames | ' + ' | '.join(c[4:-3] or 'frame' for c in cols) + ' |')
    print('|---' * (3 + len(cols)) + '|')
    for v in ('before', 'after'):
        rows = frames(folder, tag, v)
        for s in dict.fromkeys(r['setting'] for r in rows):
            mine = [r for r in rows if r['setting'] == s]
            cells = []
            for c in cols:
                vals = sorted(float(r[c]) for r in mine if r.get(c) not in (None, ''))
                cells.append(f'{statistics.median(vals):.1f} / {vals[len(vals) // 10]:.1f}'
                             if vals else '-')
            print(f'| {v} | {s} | {len(mine)} | ' + ' | '.join(cells) + ' |')
    print()


def paired(folder, tag):
    """Run i of after against run i of before (adjacent in time, so under a similar load): per
    pass the median over the pairs of (after - before), each run's value being the median of
    its measured frames; and the default / spp1 ratio of each run's frame medians."""
    cols = ['gpu_ms', 'gpu_reproject_ms', 'gpu_trace_mask_ms', 'gpu_density_ms', 'gpu_trace_ms',
            'gpu_shade_ms', 'gpu_reconstruct_ms', 'gpu_taa_ms', 'gpu_blend_ms']

    def run_medians(path):
        rows = [r for r in csv.DictReader(open(path)) if r['warmup'] == '0']
        out = {}
        for s in dict.fromkeys(r['setting'] for r in rows):
            out[s] = {c: statistics.median(float(r[c]) for r in rows
                                           if r['setting'] == s and r.get(c) not in (None, ''))
                      for c in cols if any(r['setting'] == s and r.get(c) not in (None, '')
                                           for r in rows)}
        return out

    pairs = []
    for b in sorted(glob.glob(os.path.join(folder, f'{tag}-before-*.csv'))):
        a = b.replace('-before-', '-after-')
        if os.path.exists(a):
            pairs.append((run_medians(b), run_medians(a)))
    if not pairs:
        return
    print(f'## paired runs ({len(pairs)}): median over pairs of after - before, GPU ms '
          '(trace_mask: before\'s pass, gone after)')
    print('| setting | ' + ' | '.join(c[4:-3] or 'frame' for c in cols) +
          ' | default / spp1 before | after |')
    print('|---' * (3 + len(cols)) + '|')
    d = {}
    for c in cols:
        vals = [p[1]['default'].get(c, 0.0) - p[0]['default'].get(c, 0.0) for p in pairs
                if c in p[0]['default'] or c in p[1]['default']]
        d[c] = f'{statistics.median(vals):+.1f}' if vals else '-'
    rb = statistics.median(p[0]['default']['gpu_ms'] / p[0]['spp1']['gpu_ms'] for p in pairs)
    ra = statistics.median(p[1]['default']['gpu_ms'] / p[1]['spp1']['gpu_ms'] for p in pairs)
    print('| default | ' + ' | '.join(d[c] for c in cols) + f' | {rb:.2f} | {ra:.2f} |')
    print()


if __name__ == '__main__':
    main(sys.argv[1], sys.argv[2])
    per_frame(sys.argv[1], sys.argv[2])
    paired(sys.argv[1], sys.argv[2])
