# SPDX-License-Identifier: MIT
"""@file pfm.py
@brief PFM reading and per-pixel relMSE (eps 0.01, as xrsc_metrics) for the issue-19 edge analysis."""
import array, sys
def read_pfm(p):
    """returns (w,h,list of (r,g,b)) with row 0 = top"""
    with open(p,'rb') as f:
        hd=f.readline().strip(); dims=f.readline().split(); w,h=int(dims[0]),int(dims[1])
        s=float(f.readline()); a=array.array('f'); a.frombytes(f.read())
    if s>0: a.byteswap()
    c=3 if hd==b'PF' else 1
    rows=[[tuple(a[(y*w+x)*c:(y*w+x)*c+c]) for x in range(w)] for y in range(h)]
    rows.reverse()
    return w,h,rows
def relmse_px(t,r,eps=1e-2):
    return sum((a-b)**2/(b*b+eps) for a,b in zip(t,r))/3
def relmse_map(T,R):
    return [[relmse_px(T[y][x],R[y][x]) for x in range(len(R[0]))] for y in range(len(R))]
def mean(m): return sum(map(sum,m))/(len(m)*len(m[0]))
