# Shared helpers of the YADE reference scripts (validation/yade/*.py), run inside YADE:
#     yade -n -x validation/yade/<scene>.py [OUT_DIR]
# Imported by the scene scripts after they put this folder on sys.path.
#
# The contact law is chosen so that YADE solves the SAME equations as ppohdem's Hertz-Mindlin
# law (core/include/ppohdem/dem/contact_law.hpp); every remaining difference is listed in
# docs/yade.md. YADE 2023.02a, Ip2_FrictMat_FrictMat_MindlinPhys + Law2_ScGeom_MindlinPhys_Mindlin:
#   F_n  = kno uN^{3/2} - c_n v_n, clamped at >= 0,   kno = 4/3 E* sqrt(R*)
#   c_n  = 2 betan sqrt(m* k_n),  k_n = 3/2 kno uN^{1/2} (the tangent stiffness)
#        = 2 sqrt(3/2) betan sqrt(m* kno) uN^{1/4}
# ppohdem: eta delta^{1/4} delta_dot with eta = alpha sqrt(m* K), K = kno. So the laws are
# identical when betan = alpha / (2 sqrt(3/2)) = alpha / sqrt(6), with alpha(e) the Tsuji
# damping ratio whose MEASURED binary restitution is e. alpha(e) is computed here
# independently of ppohdem's C++ (hertz_damping.hpp) by RK4 + bisection of the same scaled
# equation x'' = -x^{3/2} - alpha x^{1/4} x' (force clamped >= 0), x(0) = 0, x'(0) = 1.
# betas = 0: ppohdem has no tangential dashpot (YADE's default would be betas = betan).
import math
import os
import sys
import time

# Before the star import: `from yade import *` rebinds __file__ to YADE's own package path.
HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))

from yade import *  # noqa: E402,F401,F403  (O, FrictMat, engines, utils inside YADE)
from yade import utils  # noqa: E402


def out_dir():
    """Output folder: argv[1] if given, else fixtures/yade of this checkout."""
    d = sys.argv[1] if len(sys.argv) > 1 else os.path.join(REPO, 'fixtures', 'yade')
    os.makedirs(d, exist_ok=True)
    return d


def yade_version():
    import yade.config
    return 'Yade ' + yade.config.version


def header_lines(script, extra=''):
    """'#' comment lines written at the top of every output CSV (provenance)."""
    cmd = 'yade -n -x validation/yade/' + os.path.basename(script) + ' [OUT_DIR]'
    lines = ['# produced by %s (%s), %s' % (yade_version(), cmd,
                                             time.strftime('%Y-%m-%d %H:%M:%S UTC', time.gmtime()))]
    if extra:
        lines.append('# ' + extra)
    return '\n'.join(lines) + '\n'


def write_csv(path, script, columns, rows, extra=''):
    """Atomic write (temp + rename) of a CSV with provenance comments."""
    tmp = path + '.tmp'
    with open(tmp, 'w') as f:
        f.write(header_lines(script, extra))
        f.write(','.join(columns) + '\n')
        for r in rows:
            f.write(','.join(('%.12g' % v) if isinstance(v, float) else str(v) for v in r) + '\n')
    os.replace(tmp, path)


def _scaled_impact(alpha, h=2.0e-4):
    """Restitution of x'' = -x^1.5 - alpha x^0.25 x' (force >= 0), x(0)=0, x'(0)=1 (RK4)."""
    def acc(x, v):
        if x <= 0.0:
            return 0.0
        f = x ** 1.5 + alpha * x ** 0.25 * v
        return -f if f > 0.0 else 0.0
    x, v = 0.0, 1.0
    while True:
        k1x, k1v = v, acc(x, v)
        k2x, k2v = v + 0.5 * h * k1v, acc(x + 0.5 * h * k1x, v + 0.5 * h * k1v)
        k3x, k3v = v + 0.5 * h * k2v, acc(x + 0.5 * h * k2x, v + 0.5 * h * k2v)
        k4x, k4v = v + h * k3v, acc(x + h * k3x, v + h * k3v)
        xn = x + h / 6.0 * (k1x + 2 * k2x + 2 * k3x + k4x)
        vn = v + h / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v)
        if xn <= 0.0 and vn < 0.0:
            return -vn
        x, v = xn, vn


def tsuji_alpha(e):
    """alpha whose measured restitution is e (bisection, 1e-7)."""
    if e >= 1.0:
        return 0.0
    lo, hi = 0.0, 10.0
    while hi - lo > 1.0e-7:
        mid = 0.5 * (lo + hi)
        if _scaled_impact(mid) > e:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def setup_engines(restitution, gravity=(0.0, 0.0, 0.0), walls=False):
    """Engines of every scene: Hertz-Mindlin with the ppohdem-equivalent damping, no
    numerical (non-viscous) damping of the integrator. Returns betan."""
    betan = tsuji_alpha(restitution) / math.sqrt(6.0)
    geoms = [Ig2_Sphere_Sphere_ScGeom(avoidGranularRatcheting=False)]
    bounds = [Bo1_Sphere_Aabb()]
    if walls:
        # hertzian=True: the wall's curvature radius is 1e8 R (a plane; ppohdem uses R* = R).
        # noRatch=False: the slip velocity uses the lever arm to the contact point (R - delta),
        # as ppohdem, not R (YADE's default "no ratcheting" kinematics).
        geoms.append(Ig2_Wall_Sphere_ScGeom(hertzian=True, noRatch=False))
        bounds.append(Bo1_Wall_Aabb())
    O.engines = [
        ForceResetter(),
        InsertionSortCollider(bounds),
        InteractionLoop(geoms,
                        [Ip2_FrictMat_FrictMat_MindlinPhys(betan=betan, betas=0.0)],
                        [Law2_ScGeom_MindlinPhys_Mindlin()]),
        NewtonIntegrator(damping=0.0, gravity=gravity),
    ]
    return betan


def material(density, young, poisson, friction):
    return O.materials.append(FrictMat(young=young, poisson=poisson, density=density,
                                       frictionAngle=math.atan(friction)))
