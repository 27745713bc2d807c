# YADE 2023.02a (Debian `yade`) deck of the port check's settling_bed
# (`ppohdem validate --export-scenes DIR`, DIR/settling_bed/scene.toml; docs/port-validation.md,
# "Other codes"):
#   yade -n -j 1 -x validation/peers/port/settling_bed_yade.py particles.csv OUT_DIR "COMMENT"
# (validation/peers/port/run_peers.sh runs it; make_inputs.py writes particles.csv.)
# The scene as in in.settling_bed.lammps; the contact law of validation/peers/yade/bench.py
# (docs/performance.md, "DEM peers"): Hertz-Mindlin with betan = alpha(0.5)/sqrt(6) (ppohdem's
# Tsuji damping), betas = 0, incremental tangential spring, mu = 0.5, Hertzian plane walls.
# Writes OUT_DIR/frame_NNNNNN.csv (ppohdem's particle CSV) every 2,000 steps. YADE integrates
# with leapfrog: its velocities are those of the half step before the frame's positions.
import math, os, sys
from yade import O, utils
from yade import *  # noqa: F401,F403

csv, out, comment = sys.argv[1], sys.argv[2], sys.argv[3]
L, DT, STEPS, EVERY = 0.02, 1.0e-5, 14000, 2000
BETAN = 0.5708146467804909 / math.sqrt(6.0)   # yade_common.tsuji_alpha(0.5) / sqrt(6)
mat = O.materials.append(FrictMat(young=1.0e7, poisson=0.3, density=2500.0, frictionAngle=math.atan(0.5)))
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Wall_Aabb()], verletDist=2.0e-4),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom(avoidGranularRatcheting=False), Ig2_Wall_Sphere_ScGeom(hertzian=True, noRatch=False)],
                    [Ip2_FrictMat_FrictMat_MindlinPhys(betan=BETAN, betas=0.0)],
                    [Law2_ScGeom_MindlinPhys_Mindlin()]),
    NewtonIntegrator(damping=0.0, gravity=(0, 0, -9.81)),
]
for axis, pos, sense in ((2, 0.0, 1), (0, 0.0, 1), (0, L, -1), (1, 0.0, 1), (1, L, -1)):
    O.bodies.append(utils.wall(pos, axis=axis, sense=sense, material=mat))
ids, spheres = [], []
with open(csv) as f:
    for line in f:
        if line[0] == '#' or line.startswith('id'):
            continue
        v = line.split(',')
        ids.append(int(v[0]))
        spheres.append(utils.sphere((float(v[1]), float(v[2]), float(v[3])), float(v[10]), material=mat))
bids = O.bodies.append(spheres)
O.dt = DT
os.makedirs(out, exist_ok=True)


def write_frame(step):
    path = os.path.join(out, 'frame_%06d.csv' % step)
    with open(path + '.tmp', 'w') as f:
        f.write('# %s; step %d\n' % (comment, step))
        f.write('id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n')
        for pid, b in zip(ids, bids):
            s = O.bodies[b].state
            f.write('%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n' % (
                pid, s.pos[0], s.pos[1], s.pos[2], s.vel[0], s.vel[1], s.vel[2],
                s.angVel[0], s.angVel[1], s.angVel[2], O.bodies[b].shape.radius))
    os.replace(path + '.tmp', path)


write_frame(0)
for step in range(EVERY, STEPS + 1, EVERY):
    O.run(EVERY, True)
    write_frame(step)
print('wrote %d frames into %s' % (STEPS // EVERY + 1, out))
