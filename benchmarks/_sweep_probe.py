import time, sys, numpy as np
from structure.model import Material, hemisphere_model
from structure.statics import RelaxationSettings, solve_equilibrium, strain_error
from structure.model import MembraneState
from structure.volume import FillScale
from fluid.hydrostatic import HydrostaticLiquid
# usage: python benchmarks/_sweep_probe.py [DT STRAIN_PASSES LEVEL_GAIN RAMP_RATE MAX_STEPS] [drain]
R=0.20955
mat=Material(0.001778,1070.,8.6e6)
m=hemisphere_model(26,R,mat)
fs=FillScale(m)
liq=HydrostaticLiquid(1000.,(0,0,-9.81))
d=RelaxationSettings()
a=[x for x in sys.argv[1:] if x!='drain']
s=RelaxationSettings(dt=float(a[0]) if a else d.dt, strain_passes=int(a[1]) if len(a)>1 else d.strain_passes,
                     level_gain=float(a[2]) if len(a)>2 else d.level_gain, ramp_rate=float(a[3]) if len(a)>3 else d.ramp_rate,
                     max_steps=int(a[4]) if len(a)>4 else d.max_steps)
st=MembraneState(m.node_rest_position)
pf=lambda x: liq.pressure(x)
fills=list(np.round(np.linspace(0,1,11),2))
legs=[('fill',fills)]+([('drain',fills[::-1])] if 'drain' in sys.argv else [])
for leg,ff in legs:
    T=time.time()
    for phi in ff:
        t0=time.time()
        st,info=solve_equilibrium(m,st,pf,(0,0,-9.81),s,volume_target=float(fs.volume(phi)))
        V=info.liquid_volume; tv=fs.volume(phi)
        print(f"{leg} {phi:.1f} steps {info.steps:5d} conv {info.converged!s:5} h {liq.equivalent_height(info.pressure_level):+9.4f} m "
              f"dV/Vtarget {abs(V-tv)/tv:.1e} strain mean {info.strain_error:.4f} max {info.strain_max:.3f} "
              f"fixed moved {np.abs(st.node_position[m.node_fixed]-m.node_rest_position[m.node_fixed]).max():.0e} t {time.time()-t0:.2f} s",flush=True)
    print(leg, "total", round(time.time()-T,2), "s")
np.save('/tmp/sweep.npy', st.node_position)
