# YADE 2023.02a (Debian `yade`) deck of the issue-7 benchmark scene.
#   yade -n -j THREADS -x validation/peers/yade/bench.py particles.csv STEPS L final.csv
# (ci/bench-dem.sh runs it; validation/peers/make_bench.py writes particles.csv and L.)
# YADE parallelises with OpenMP threads (-j), not MPI ranks. Contact law as in
# validation/yade/yade_common.py: Hertz-Mindlin (Law2_ScGeom_MindlinPhys_Mindlin) with
# betan = alpha(0.5)/sqrt(6) = 0.233034 (the same Tsuji damping as ppohdem: measured e = 0.49997
# for two 1 mm spheres at 0.1 m/s), betas = 0 (no tangential dashpot), force clamped at >= 0,
# incremental tangential spring k_t = 8 G* sqrt(R* delta), mu = 0.5; plane walls with a
# Hertzian curvature radius 1e8 R; no numerical damping. Verlet distance 1e-4 m (0.1 d, the
# skin of the other codes). Prints "loop_seconds S" (the O.run time) and writes the final
# state as a ppohdem particle CSV.
import math, sys, time
from yade import O, utils
from yade import *  # noqa: F401,F403

csv, steps, L, out = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
BETAN = 0.5708146467804909 / math.sqrt(6.0)   # yade_common.tsuji_alpha(0.5) / sqrt(6)
mat = O.materials.append(FrictMat(young=1.0e7, poisson=0.3, density=2500.0, frictionAngle=math.atan(0.5)))
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Wall_Aabb()], verletDist=1.0e-4),
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
O.dt = 8.65e-6   # 0.2 Rayleigh time
t0 = time.time()
O.run(steps, True)
print('loop_seconds %.6f' % (time.time() - t0))
with open(out, 'w') as f:
    f.write('id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n')
    for pid, b in zip(ids, bids):
        s = O.bodies[b].state
        f.write('%d,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%g\n' % (
            pid, s.pos[0], s.pos[1], s.pos[2], s.vel[0], s.vel[1], s.vel[2],
            s.angVel[0], s.angVel[1], s.angVel[2], O.bodies[b].shape.radius))
