# SPDX-License-Identifier: MIT
"""@file ana.py
@brief Splits a frame's relMSE by pixel class: usage ana.py REFDIR TESTDIR FRAME (dark: reference
luminance < 0.3, mid: < 1.5; "-edge": the 3 x 3 neighbourhood spans more than 3:1)."""
from pfm import *  # noqa: F403 (read_pfm, relmse_px)
import sys
ref=sys.argv[1]; tst=sys.argv[2]; fr=int(sys.argv[3]) if len(sys.argv)>3 else 36
tot=0; cats={}
for e in ['left','right']:
    w,h,R=read_pfm('%s/frame_%05d_%s.pfm'%(ref,fr,e)); _,_,T=read_pfm('%s/frame_%05d_%s.pfm'%(tst,fr,e))
    for y in range(h):
        for x in range(w):
            r=R[y][x]; t=T[y][x]; L=sum(r)/3; Lt=sum(t)/3
            # neighbourhood contrast in ref
            nb=[sum(R[yy][xx])/3 for yy in range(max(0,y-1),min(h,y+2)) for xx in range(max(0,x-1),min(w,x+2))]
            edge=max(nb)/(min(nb)+1e-3)>3
            c=('dark' if L<0.3 else 'mid' if L<1.5 else 'bright')+('-edge' if edge else '')
            v=relmse_px(t,r)
            s=cats.setdefault(c,[0,0,0.0,0.0]); s[0]+=1; s[1]+=v; s[2]+=L; s[3]+=Lt
            tot+=v
n=2*w*h
print('total relMSE', tot/n)
for c,s in sorted(cats.items()):
    print('%-12s n=%5d share_of_relMSE=%.4f meanerr=%.3f meanRef=%.3f meanTest=%.3f'%(c,s[0],s[1]/n,s[1]/s[0],s[2]/s[0],s[3]/s[0]))
