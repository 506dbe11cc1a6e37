import conftest as cf, numpy as np, loop_reference as lr, time
from mpmath import mpf
zw=cf.load('double')
cases=[dict(delay=0),dict(delay=3),dict(differentiator='tustin'),dict(delay=2,differentiator='tustin'),
       dict(delay=1,filter='lowpass',pole=0.8),dict(delay=2,differentiator='tustin',filter='lowpass',pole=0.3),
       dict(delay=2,filter='average',average=5),dict(delay=8,differentiator='tustin',filter='average',average=16)]
for delta in [1e-6, 0.5, 1e3]:
  st,co=zw.coeffs(delta)
  for cs in cases:
    t=time.time()
    parts=lr.loop_parts(delta,**cs)
    spec=zw.loop_spec(**cs)
    st,lp=zw.loop(co,spec)
    n=lp.degree
    worst=0
    for (al,be) in [(0,0),(1.0,0.3),(0.2,-0.7)]:
        ref=lr.loop_poly(parts,al,be,n)
        st,p=zw.loop_poly(lp,al,be)
        p0=p[0]
        scale=sum(abs(float(r)) for r in ref)
        err=max(abs(p[i]/p0-float(ref[i])) for i in range(n+1))/scale
        worst=max(worst,err)
    print(delta, cs, n, len(parts[0])-1, '%.2e'%worst, '%.2fs'%(time.time()-t))
