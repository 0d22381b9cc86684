#!/usr/bin/env python3
"""Compare two tab-separated tables with headers: same columns and rows, numbers to 1e-9 relative.

Usage: compare_tables.py OURS.tsv REFERENCE.tsv (exit 1 on a difference)."""
import sys, math
def load(p):
    lines=open(p).read().splitlines(); return lines[0].split('\t'), [l.split('\t') for l in lines[1:] if l]
h1,r1=load(sys.argv[1]); h2,r2=load(sys.argv[2])
assert h1==h2, (h1,h2)
print('rows', len(r1), len(r2))
worst=0; bad=0
for k,(a,b) in enumerate(zip(r1,r2)):
    for c,(x,y) in enumerate(zip(a,b)):
        try: u=float(x); v=float(y)
        except ValueError:
            if x!=y: bad+=1; print('text', k, h1[c], x, y) if bad<5 else None
            continue
        if u==v or (math.isnan(u) and math.isnan(v)): continue
        rel=abs(u-v)/max(abs(u),abs(v))
        worst=max(worst,rel)
        if rel>1e-9:
            bad+=1
            if bad<8: print('num', k, h1[c], x, y, rel)
print('worst rel', worst, 'bad', bad)
sys.exit(1 if bad or len(r1) != len(r2) else 0)
