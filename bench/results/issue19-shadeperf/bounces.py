#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""@file bounces.py
@brief Splits spp and the sample cache's shading launch into a per-ray and a fixed part from
       bounces-*.txt (bench output of bounces.settings with the sub-pass timers): per secondary
       ray = (1 bounce - 0 bounces) / secondary rays, fixed = the 0-bounce time per path.
usage: bounces.py FILE..."""
import re, sys

PX = 2 * 256 * 256
for path in sys.argv[1:]:
    frame, launch, cnt, rays = {}, {}, {}, {}
    mode = None
    for line in open(path):
        f = line.split()
        if line.startswith('per pass'):
            mode = 'pass'
        elif line.startswith('method'):
            mode = 'counters'
        elif line.startswith('setting') and mode == 'pass':
            cols = f[1:]
        elif mode == 'pass' and f and f[0] in ('default', 'default0', 'spp1', 'spp0'):
            row = dict(zip(cols, f[1:]))
            if f[0].startswith('spp'):
                frame[f[0]] = float(row['trace'])
            else:
                launch[f[0]] = float(row['sh_launch'])
        elif line.startswith(('default ', 'default0 ')) and 'sc_shaded=' in line:
            cnt[f[0]] = float(re.search(r'sc_shaded=([0-9.]+)', line).group(1))
            rays[f[0]] = float(re.search(r'sc_shade_rays=([0-9.]+)', line).group(1))
        elif mode is None and f and f[0] == 'spp1' and len(f) > 5:
            rays['spp1'] = float(f[5]) * PX
    spp_sec = rays['spp1'] - PX  # after the camera rays
    print(f"{path}: spp {(frame['spp1'] - frame['spp0']) / spp_sec * 1e3:.2f} us per secondary ray, "
          f"{frame['spp0'] / PX * 1e3:.2f} us fixed per pixel; launch "
          f"{(launch['default'] - launch['default0']) / rays['default'] * 1e3:.2f} us per ray, "
          f"{launch['default0'] / cnt['default0'] * 1e3:.2f} us fixed per invocation "
          f"({cnt['default']:.0f} paths, {rays['default'] / cnt['default']:.2f} rays each; spp "
          f"{spp_sec / PX:.2f} per path)")
