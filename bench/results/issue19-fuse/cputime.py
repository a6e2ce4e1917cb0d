#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""@file cputime.py
@brief Per-frame CPU time of lavapipe's work, which the machine's other load barely changes
       (unlike the GPU timestamps, which on lavapipe are wall-clock spans): the CPU time (user +
       sys, all threads) of `xrsc replay --direct` at F2 frames minus that at F1 frames, over
       F2 - F1, so the setup (scene, BVH, pipelines) cancels. Builds alternate, REPS times.
usage: cputime.py REPS XRSC_BEFORE XRSC_AFTER [F1 F2]"""
import os, statistics, subprocess, sys

SETTINGS = {  # bench/issue10.settings' default and spp1, as xrsc replay renders them
    'default': ['--bounces', '1'],
    'spp1': ['--method', 'spp', '--spp', '1', '--bounces', '1'],
}


def cpu_seconds(exe, frames, opts):
    args = [exe, 'replay', '--direct', '--resolution', '256x256', '--frames', str(frames),
            '--write', 'none', '--out', '/tmp/fuse-cputime', '--overwrite'] + opts
    p = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, ru = os.wait4(p.pid, 0)
    if status != 0:
        sys.exit(f'{" ".join(args)}: exit status {status}')
    return ru.ru_utime + ru.ru_stime


def main():
    reps, exes = int(sys.argv[1]), {'before': sys.argv[2], 'after': sys.argv[3]}
    f1, f2 = (int(sys.argv[4]), int(sys.argv[5])) if len(sys.argv) > 5 else (8, 40)
    per = {(b, s): [] for b in exes for s in SETTINGS}
    for r in range(reps):
        for b, exe in exes.items():
            for s, opts in SETTINGS.items():
                ms = (cpu_seconds(exe, f2, opts) - cpu_seconds(exe, f1, opts)) / (f2 - f1) * 1e3
                per[(b, s)].append(ms)
                print(f'run {r + 1} {b} {s}: {ms:.1f} CPU ms per frame', flush=True)
    print(f'\nmedians of {reps} runs, CPU ms per frame (frames {f1}..{f2}):')
    for b in exes:
        d, p = statistics.median(per[(b, 'default')]), statistics.median(per[(b, 'spp1')])
        x = statistics.median(a / c for a, c in zip(per[(b, 'default')], per[(b, 'spp1')]))
        print(f'{b}: default {d:.1f}, spp1 {p:.1f}, default / spp1 {d / p:.3f} '
              f'(median of per-run ratios {x:.3f})')


if __name__ == '__main__':
    main()
