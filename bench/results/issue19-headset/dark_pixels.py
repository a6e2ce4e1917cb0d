#!/usr/bin/python3
# SPDX-License-Identifier: MIT
# @file dark_pixels.py
# @brief Issue 19 (stop 22): where a setting's relMSE sits against the reference, from
#        `xrsc bench --keep-frames` frames: black pixels, pixels under 0.75x / over 1.33x the
#        reference (reference luminance > 0.05), their shares of the relMSE, and the mean ratio.
# Usage: dark_pixels.py OUT FRAME SETTING... (FRAME as in the file names, e.g. 00008; left eye)
import sys
import numpy as np


def pfm(path):
    with open(path, 'rb') as f:
        kind = f.readline().strip()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        d = np.frombuffer(f.read(), dtype='<f4' if scale < 0 else '>f4')
    return d.reshape(h, w, 3 if kind == b'PF' else 1)[::-1]


out, frame = sys.argv[1], sys.argv[2]
ref = pfm(f'{out}/ref/frame_{frame}_left.pfm')
for name in sys.argv[3:]:
    img = pfm(f'{out}/frames/{name}/frame_{frame}_left.pfm')
    e = ((img - ref) ** 2 / (ref ** 2 + 0.01)).mean(axis=2)
    lit = ref.mean(axis=2) > 0.05
    groups = {'black': img.max(axis=2) <= 0,
              'dark<0.75x': (img.mean(axis=2) < 0.75 * ref.mean(axis=2)) & lit,
              'bright>1.33x': (img.mean(axis=2) > 1.33 * ref.mean(axis=2)) & lit}
    parts = ' '.join(f'{k} {m.mean():.4f} (share {e[m].sum() / e.sum():.3f})'
                     for k, m in groups.items())
    print(f'{name:14s} relmse {e.mean():.5f} {parts} mean ratio {img.mean() / ref.mean():.3f}')
