from _explore2 import *
import conftest as cf
ks=[10**i for i in range(0,12)]
for prec in ['double','float']:
  zw=cf.load(prec)
  for delta in [1e-6,0.5,1e3]:
    for cs in [dict(delay=2),dict(delay=4),dict(delay=8),dict(delay=2,filter='average',average=8),dict(delay=8,filter='average',average=16),dict(differentiator='tustin',delay=8,filter='average',average=16)]:
        print(prec, delta, cs, band(zw,delta,cs,ks=ks), flush=True)
