#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# @file compare.py
# @brief Issue 19 (Cornell): relMSE / temporal / stereo per case and setting from
# bench/issue19_table.py's CSV, and each setting's ratios to `default`, as Markdown.
# Usage: compare.py TABLE.csv SETTING [SETTING...]
import csv, sys

rows = list(csv.DictReader(open(sys.argv[1])))
sets = sys.argv[2:]
cases = []
for r in rows:
    if r['case'] not in cases:
        cases.append(r['case'])
at = {(r['case'], r['setting']): r for r in rows}
f = lambda r: tuple(float(r[k]) for k in ('relmse', 'temporal_msd', 'stereo_msd'))
print('| case | ' + ' | '.join(f'`{s}`' for s in sets) + ' |')
print('|---' * (len(sets) + 1) + '|')
for c in cases:
    print(f'| {c} | ' + ' | '.join('%.3g / %.3g / %.3g' % f(at[c, s]) if (c, s) in at else '-'
                                   for s in sets) + ' |')
print('\nRatios to `default` (relMSE / temporal / stereo):\n')
others = [s for s in sets if s != 'default']
print('| case | ' + ' | '.join(f'`{s}`' for s in others) + ' |')
print('|---' * (len(others) + 1) + '|')
for c in cases:
    d = f(at[c, 'default'])
    print(f'| {c} | ' + ' | '.join(' / '.join('%.2f' % (v / b) for v, b in zip(f(at[c, s]), d))
                                   if (c, s) in at else '-' for s in others) + ' |')
