import time, sys, numpy as np
from structure.model import Material, hemisphere_model
from structure.statics import RelaxationSettings, solve_equilibrium, strain_error
from structure.thesis import ConstraintSettings
from structure.model import MembraneState
from structure.volume import FillScale, liquid_volume
from fluid.hydrostatic import HydrostaticLiquid
R=0.20955
mat=Material(0.001778,1070.,8.6e6)
m=hemisphere_model(26,R,mat)
fs=FillScale(m)
liq=HydrostaticLiquid(1000.,(0,0,-9.81))
dt=float(sys.argv[1]); damp=float(sys.argv[2]); bend=int(sys.argv[3]); ramp=int(sys.argv[4])
s=RelaxationSettings(dt=dt,damping=damp,ramp_steps=ramp,max_steps=int(sys.argv[5]),tolerance=1e-5,constraints=ConstraintSettings(bend_limit_iterations=bend,wall_slack=1.0,gauss_seidel=True))
st=MembraneState(m.node_rest_position)
pf=lambda x: liq.pressure(x)
T=time.time()
for phi in np.linspace(0,1,11):
    t0=time.time()
    st,info=solve_equilibrium(m,st,pf,(0,0,-9.81),s,volume_target=float(fs.volume(phi)))
    V=info.liquid_volume
    print(f"{phi:.1f} steps {info.steps} conv {info.converged} move {info.move_ratio:.2e} h {liq.equivalent_height(info.pressure_level):.4f} fill {fs.fill(V):.5f} strain {strain_error(m,st.node_position)} t {time.time()-t0:.2f}",flush=True)
print("total",time.time()-T)
np.save('/tmp/sweep.npy', st.node_position)
