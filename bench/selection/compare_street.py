#!/usr/bin/env python3
"""Compare .hdr renders of a street against a reference render (bench/results/selection/README.md).

    python3 bench/selection/compare_street.py REF.hdr A.hdr [B.hdr ...]

Luminance Y = 0.265 R + 0.670 G + 0.065 B; per picture: mean / reference, rel. MSE =
sum (Y - Y_ref)^2 / sum Y_ref^2 (the reference's own noise included), fireflies = pixels above 5x
the reference and above 0.1, the 3 x 3 blocks' mean ratios, and 8 x 8-pixel tiles' mean ratios
(tiles where the reference is above 2 % of its mean): the smallest, the largest and how many are
at 2x or 0.5x. Needs numpy (the project's venv).
"""
import sys

import numpy as np


def read_hdr(path):
    d=open(path,'rb').read()
    i=0
    while True:
        j=d.index(b'\n',i); line=d[i:j]; i=j+1
        if line.startswith(b'-Y') or line.startswith(b'+Y'): break
    parts=line.split(); H=int(parts[1]); W=int(parts[3])
    img=np.zeros((H,W,4),np.uint8); p=i
    for y in range(H):
        if d[p]==2 and d[p+1]==2:
            p+=4
            for c in range(4):
                x=0
                while x<W:
                    n=d[p]; p+=1
                    if n>128:
                        n-=128; img[y,x:x+n,c]=d[p]; p+=1
                    else:
                        img[y,x:x+n,c]=np.frombuffer(d[p:p+n],np.uint8); p+=n
                    x+=n
        else:
            img[y]=np.frombuffer(d[p:p+4*W],np.uint8).reshape(W,4); p+=4*W
    e=img[...,3].astype(np.int32)
    f=np.where(e>0, np.ldexp(1.0, e-136), 0.0)
    rgb=img[...,:3].astype(np.float64)*f[...,None]
    if parts[0]==b'+Y': rgb=rgb[::-1]
    return rgb
def Y(r): return 0.265*r[...,0]+0.670*r[...,1]+0.065*r[...,2]
ref=Y(read_hdr(sys.argv[1]))
for path in sys.argv[2:]:
    y=Y(read_hdr(path))
    H,W=y.shape
    rel=((y-ref)**2).sum()/(ref**2).sum()
    ff=((y>5*ref)&(y>0.1)).sum()
    blocks=[]
    for by in range(3):
        for bx in range(3):
            a=y[by*H//3:(by+1)*H//3, bx*W//3:(bx+1)*W//3].mean(); b=ref[by*H//3:(by+1)*H//3, bx*W//3:(bx+1)*W//3].mean()
            blocks.append(a/b if b>0 else float('nan'))
    # finer: 8x8-pixel tiles, ratio of means where the reference is not dark
    t=8; rs=[]
    for yy in range(0,H-t+1,t):
        for xx in range(0,W-t+1,t):
            b=ref[yy:yy+t,xx:xx+t].mean()
            if b>0.02*ref.mean(): rs.append(y[yy:yy+t,xx:xx+t].mean()/b)
    rs=np.array(rs)
    print(f"{path}: mean/all {y.mean()/ref.mean():.4f}  rel.MSE {rel:.4f}  fireflies {ff}  3x3 blocks/all "+" ".join(f"{v:.2f}" for v in blocks)+f"  8px tiles: min {rs.min():.2f} max {rs.max():.2f} (>=2x: {(rs>=2).sum()}, <=0.5x: {(rs<=0.5).sum()} of {len(rs)})")
