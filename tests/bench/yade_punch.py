# YADE side of the punch benchmark of `./wirenet bench` (tests/bench/run_bench.py): YADE WirePM's
# punch test of a 3 m double-twist net, the case docs/examples/yade_punch.toml runs in WireNet.
# Written from YADE's documented WirePM example examples/WireMatPM/wirecontacttest.py (Debian
# package yade, /usr/share/doc/yade/examples): the same WireMat materials, hexaNet packing and link
# creation (an enlarged interaction range for the first step, then the normal one). Here: all four
# edges pinned, no gravity, local damping 0.2, a rigid sphere of radius 0.5 m that starts touching
# the net at its centre and moves at 0.5 m/s into it (a non-dynamic body moves with its velocity).
#
#   yade -n -x -j1 tests/bench/yade_punch.py STEPS DT OUT.json
#
# Writes OUT.json: nodes, links, steps, wall time of the timed steps (after a warm-up), the
# sphere's travel and its force at the end.
import json
import sys
import time
from math import pi, radians

from yade import O
from yade.config import version
from yade.pack import hexaNet
from yade.utils import sphere, uniaxialTestFeatures  # noqa: F401 (uniaxialTestFeatures: see below)
from yade.wrapper import (Bo1_Sphere_Aabb, ForceResetter, FrictMat, Ig2_Sphere_Sphere_ScGeom,
                          InsertionSortCollider, InteractionLoop, Ip2_FrictMat_FrictMat_FrictPhys,
                          Ip2_WireMat_WireMat_WirePhys, Law2_ScGeom_FrictPhys_CundallStrack,
                          Law2_ScGeom_WirePhys_WirePM, NewtonIntegrator, WireMat)

steps, dt, out = int(sys.argv[1]), float(sys.argv[2]), sys.argv[3]
WARMUP = max(steps // 10, 100)

d = 2.7e-3                       # wire diameter [m]
radius = 4 * d                   # hexaNet's node radius (WireNet: --node-radius 0.0108)
curve = [(0.0019230769, 2.5e8), (0.0192, 3.2195e8), (0.05, 3.8292e8), (0.15, 5.1219e8),
         (0.25, 5.5854e8), (0.3, 5.6585e8), (0.35, 5.6585e8)]
node_mass = 3.9e-3
density = node_mass / (4.0 / 3.0 * pi * radius ** 3)
net = O.materials.append(WireMat(young=curve[0][1] / curve[0][0], poisson=0.3,
                                 frictionAngle=radians(11.31),        # mu 0.2 as WireNet
                                 density=density, isDoubleTwist=True, diameter=d,
                                 strainStressValues=curve, lambdaEps=0.4, lambdak=0.66))
body = O.materials.append(FrictMat(young=1e12, poisson=0.3, frictionAngle=radians(11.31),
                                   density=1000.0))

half = 1.5
nodes, lx, ly = hexaNet(radius=radius, cornerCoord=[-half, -half, 0], xLength=2 * half,
                        yLength=2 * half, mos=0.08, a=0.04, b=0.04, startAtCorner=True,
                        isSymmetric=False, wire=True, fixed=False, material=net)
O.bodies.append(nodes)

# links: one step with the enlarged range of the example (2.8 x the sum of the radii reaches the
# single-wire length, 56.6 mm, not the next twist), then the normal range
factor = 2.8
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(aabbEnlargeFactor=factor, label="aabb")]),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom(interactionDetectionFactor=factor, label="ig2")],
                    [Ip2_WireMat_WireMat_WirePhys(linkThresholdIteration=1),
                     Ip2_FrictMat_FrictMat_FrictPhys()],
                    [Law2_ScGeom_WirePhys_WirePM(linkThresholdIteration=1),
                     Law2_ScGeom_FrictPhys_CundallStrack()]),
    NewtonIntegrator(damping=0.2, gravity=(0, 0, 0)),
]
O.dt = dt
O.step()
aabb.aabbEnlargeFactor = -1.0      # noqa: F821 (labels are globals in YADE)
ig2.interactionDetectionFactor = -1.0   # noqa: F821
links = sum(1 for i in O.interactions if i.isReal)

# all four edges pinned
xs = [b.state.pos[0] for b in O.bodies]
ys = [b.state.pos[1] for b in O.bodies]
x0, x1, y0, y1 = min(xs), max(xs), min(ys), max(ys)
for b in O.bodies:
    p = b.state.pos
    if min(abs(p[0] - x0), abs(p[0] - x1), abs(p[1] - y0), abs(p[1] - y1)) < 1e-9:
        b.state.blockedDOFs = "xyzXYZ"

# the sphere: touching the top of the node nearest to the centre, moving down at 0.5 m/s
R = 0.5
cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
s = O.bodies.append(sphere((cx, cy, R + radius), R, fixed=True, material=body))
O.bodies[s].state.vel = (0, 0, -0.5)

O.run(WARMUP, True)
start = time.time()
O.run(steps, True)
wall = time.time() - start
force = O.forces.f(s, sync=True)
with open(out, "w") as handle:
    json.dump(dict(nodes=len(nodes), links=links, steps=steps, warmup=WARMUP, dt=dt,
                   wall=wall, ms_per_step=1e3 * wall / steps,
                   travel=-(O.bodies[s].state.pos[2] - (R + radius)), force_z=force[2],
                   yade=version),
              handle, indent=1)
