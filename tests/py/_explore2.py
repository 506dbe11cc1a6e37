import conftest as cf, numpy as np, loop_reference as lr, time, math, sys
from mpmath import mp, mpf
import reference as ref
def boundary_alpha(parts, n, beta, lo, hi, iters=200):
    # lo stable, hi unstable; bisection in mp
    lo, hi = mpf(lo), mpf(hi)
    for _ in range(iters):
        mid=(lo+hi)/2
        if lr.schur_stable(lr.loop_poly(parts, mid, beta, n))[0]: lo=mid
        else: hi=mid
        if hi-lo < mpf(10)**-40*abs(hi): break
    return lo
def band(zw, delta, cs, betas_frac=(0.0,0.3,0.7), ks=(1,3,10,30,100,300,1000,3000,10000)):
    st,co=zw.coeffs(delta); st,lp=zw.loop(co,zw.loop_spec(**cs)); n=lp.degree
    parts=lr.loop_parts(delta,**cs)
    out=[]
    # find beta range: scan
    fs=0; fu=[]; unmarked=0
    for fb in betas_frac:
        # heuristic beta scale
        d=cs.get('delay',0)
        bscale = max(delta,1e-3)
        beta = zw.r(fb*2*bscale + (0.5*bscale if cs.get('differentiator')=='tustin' else 0))
        a_lo = None
        # find stable tiny alpha
        for a in [1e-3*bscale/(1+d), 1e-5*bscale, 1e-8*bscale]:
            a=zw.r(a)
            if lr.schur_stable(lr.loop_poly(parts,a,beta,n))[0]: a_lo=a;break
        if a_lo is None: continue
        a_hi=a_lo
        while lr.schur_stable(lr.loop_poly(parts,a_hi,beta,n))[0]: a_hi*=2
        ab=boundary_alpha(parts,n,beta,a_lo,a_hi)
        ab_f=zw.r(float(ab))
        for k in ks:
            for sgn in (+1,-1):
                a=ab_f
                a = float(zw.np(a)) ; 
                ulp=np.spacing(zw.np(ab_f))
                a=zw.r(ab_f+sgn*k*float(ulp))
                lab=lr.schur_stable(lr.loop_poly(parts,a,beta,n))[0]
                s,v=zw.loop_check(lp,a,beta)
                if v.stable and not lab: fs+=1; print('FALSE STABLE',delta,cs,a,beta)
                if lab and not v.stable:
                    fu.append(k)
                    if not v.marginal: unmarked+=1
    return fs, (max(fu) if fu else 0), unmarked
if __name__ == "__main__":
 for prec in ["double","float"]:
   zw=cf.load(prec)
   for delta in [1e-6,1e-3,0.5,5.0,1e3]:
     for cs in [dict(delay=0),dict(delay=1),dict(delay=8),dict(differentiator='tustin'),dict(delay=1,filter='lowpass',pole=0.8),dict(delay=1,filter='lowpass',pole=0.999),dict(delay=2,filter='average',average=8),dict(delay=3,differentiator='tustin',filter='lowpass',pole=0.3)]:
         t=time.time()
         print(prec, delta, cs, band(zw,delta,cs), '%.1fs'%(time.time()-t), flush=True)
 