from _explore2 import *
import conftest as cf
zw=cf.load('double')
delta=0.5; cs=dict(delay=8,filter='average',average=16)
st,co=zw.coeffs(delta); st,lp=zw.loop(co,zw.loop_spec(**cs)); n=lp.degree
parts=lr.loop_parts(delta,**cs)
beta=zw.r(0.6*1)
import sys
cs=eval(sys.argv[1]); st,lp=zw.loop(co,zw.loop_spec(**cs)); n=lp.degree; parts=lr.loop_parts(delta,**cs)
for beta in eval(sys.argv[2]):
  a_lo=1e-6
  a_hi=a_lo
  while lr.schur_stable(lr.loop_poly(parts,a_hi,beta,n))[0]: a_hi*=2
  ab=boundary_alpha(parts,n,beta,a_lo,a_hi)
  print('beta',beta,'alpha_b',float(ab))
  p=lr.loop_poly(parts,ab,beta,n)
  rho,th=lr.spectral_radius(p)
  print(' rho',float(rho),'theta',float(th))
  for k in [1e2,1e4,1e6,1e8,1e10]:
    a=float(ab)*(1-k*2**-53)
    s,v=zw.loop_check(lp,a,beta)
    print('  k',k,v.stable,v.marginal,v.deciding, float(lr.spectral_radius(lr.loop_poly(parts,a,beta,n))[0])-1)
