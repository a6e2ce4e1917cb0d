#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# @file errmap.py
# @brief Issue 19 (Cornell): where the relMSE of `xrsc bench --keep-frames` frames sits.
#
# Usage: errmap.py OUT SETTING [SETTING...] [--maps DIR]
# Reads OUT/ref/frame_K_EYE.pfm and OUT/frames/SETTING/frame_K_EYE.pfm of every scored frame
# and splits each setting's relMSE (the bench's: mean over pixels and rgb of
# (x - r)^2 / (r^2 + 0.01)) into regions of the reference: the light panel (luminance > 2),
# its ring (within 2 px of it), dark (< 0.05), edges (relative luminance gradient of the
# reference > 0.5 to a 4-neighbour) and the rest; also the share of the top 0.5 % pixels,
# the signed mean error (bias) per region, and the relMSE after a 5x5 box blur of both
# images (low-frequency error) against the rest (noise). --maps DIR: writes per-frame error
# maps as PFM (grey, the per-pixel relMSE term).
import sys, os, glob, re
import numpy as np

EPS = 0.01

def read_pfm(p):
    with open(p, 'rb') as f:
        hdr = f.readline().strip()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        a = np.frombuffer(f.read(), dtype='<f4' if scale < 0 else '>f4')
    c = 3 if hdr == b'PF' else 1
    return a.reshape(h, w, c)[::-1].astype(np.float64)

def write_pfm(p, img):
    h, w = img.shape[:2]
    with open(p, 'wb') as f:
        f.write(b'Pf\n%d %d\n-1.0\n' % (w, h))
        f.write(np.ascontiguousarray(img[::-1], dtype='<f4').tobytes())

def lum(a):
    return 0.2126 * a[..., 0] + 0.7152 * a[..., 1] + 0.0722 * a[..., 2]

def dilate(m, r):
    out = m.copy()
    for dy in range(-r, r + 1):
        for dx in range(-r, r + 1):
            out |= np.roll(np.roll(m, dy, 0), dx, 1)
    return out

def box(a, r=2):
    out = np.zeros_like(a)
    for dy in range(-r, r + 1):
        for dx in range(-r, r + 1):
            out += np.roll(np.roll(a, dy, 0), dx, 1)
    return out / (2 * r + 1) ** 2

def regions(ref):
    L = lum(ref)
    panel = L > 2.0
    ring = dilate(panel, 2) & ~panel
    dark = (L < 0.05) & ~panel & ~ring
    g = np.zeros_like(L, dtype=bool)
    for ax in (0, 1):
        d = np.abs(np.diff(L, axis=ax)) / (np.minimum(
            np.delete(L, -1, ax), np.delete(L, 0, ax)) + 0.05)
        e = d > 0.5
        pad = [(0, 0), (0, 0)]
        pad[ax] = (0, 1)
        g |= np.pad(e, pad)
        pad[ax] = (1, 0)
        g |= np.pad(e, pad)
    edge = g & ~panel & ~ring & ~dark
    rest = ~(panel | ring | dark | edge)
    return dict(panel=panel, ring=ring, dark=dark, edge=edge, rest=rest)

def main():
    args = sys.argv[1:]
    maps = None
    if '--maps' in args:
        i = args.index('--maps'); maps = args[i + 1]; del args[i:i + 2]
        os.makedirs(maps, exist_ok=True)
    out, settings = args[0], args[1:]
    names = ['panel', 'ring', 'dark', 'edge', 'rest']
    print('setting,relmse,' + ','.join(f'{n}_share' for n in names) + ',' +
          ','.join(f'{n}_bias' for n in names) + ',top0.5%_share,lowfreq_relmse,px_share_' +
          '_'.join(names))
    for s in settings:
        files = sorted(glob.glob(f'{out}/frames/{s}/frame_*_*.pfm'))
        tot = {n: 0.0 for n in names}; bias = {n: [0.0, 0] for n in names}
        npx = {n: 0 for n in names}
        allterm = []; lowf = 0.0; count = 0
        for fp in files:
            m = re.search(r'frame_(\d+)_(left|right)\.pfm', fp)
            rp = f'{out}/ref/frame_{m.group(1)}_{m.group(2)}.pfm'
            x = read_pfm(fp)[..., :3]; r = read_pfm(rp)[..., :3]
            term = ((x - r) ** 2 / (r ** 2 + EPS)).mean(axis=2)
            lt = ((box(x) - box(r)) ** 2 / (box(r) ** 2 + EPS)).mean(axis=2)
            rg = regions(r)
            for n in names:
                tot[n] += term[rg[n]].sum(); npx[n] += rg[n].sum()
                rel = (lum(x) - lum(r))[rg[n]].sum()
                bias[n][0] += rel; bias[n][1] += lum(r)[rg[n]].sum()
            allterm.append(term.ravel()); lowf += lt.sum(); count += term.size
            if maps:
                write_pfm(f'{maps}/{s}_{m.group(1)}_{m.group(2)}.pfm',
                          np.repeat(term[..., None], 3, 2))
        a = np.concatenate(allterm); total = a.sum()
        top = np.sort(a)[::-1][:max(1, len(a) // 200)].sum()
        print(f'{s},{total / count:.4g},' +
              ','.join(f'{tot[n] / total:.3f}' for n in names) + ',' +
              ','.join(f'{bias[n][0] / max(bias[n][1], 1e-9):+.3f}' for n in names) +
              f',{top / total:.3f},{lowf / count:.4g},' +
              '_'.join(f'{npx[n] / count:.3f}' for n in names))

main()
