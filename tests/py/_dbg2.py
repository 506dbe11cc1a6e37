import conftest as cf, loop_reference as lr, numpy as np
from mpmath import mpf, mp
zw=cf.load('double')
spec=dict(delay=2, differentiator="tustin", filter="average", average=5)
st,co=zw.coeffs(1000.0); st,lp=zw.loop(co,zw.loop_spec(**spec)); n=lp.degree
parts=lr.loop_parts(1000.0,**spec)
for b in [-1.5356292461148047e-38, -1e-20, -1e-10, 0.0, 1e-10,1e-3]:
    a=177.82794100389228
    p=lr.loop_poly(parts,a,b,n)
    print(b, zw.loop_check(lp,a,b)[1].stable, lr.schur_stable(p)[0], float(lr.schur_stable(p)[1]), [float(x) for x in lr.spectral_radius(p)], zw.loop_spectral_radius(lp,a,b))
print(list(lp.Ds)[:n+1]); print(list(lp.Ds_err)[:n+1]); print(list(lp.Nbs)[:n+1])
