"""The rigid block of the impact kinds (impact, fence): the generator's truncated cube or a
closed STL of the user, its mass properties, oriented and centred as released. Not a kind: the
kinds that throw a block share it."""

import math
import os

import numpy as np

from postprocess import bodyframes, solid, vtu
from postprocess.meta import read_json

from .generator import generate


class Block:
    """The block: the generator's truncated cube (analytic or mesh) or a closed STL of the user
    (mesh), with its mass properties, oriented by the unit quaternion ``quat``. Writes the
    oriented, centred STL the frames draw (and the mesh path moves) into ``workdir``."""

    def __init__(self, workdir, mass, side, quat=(1.0, 0.0, 0.0, 0.0), stl=None):
        self.mass, self.quat = float(mass), tuple(float(v) for v in quat)
        self.path = os.path.join(workdir, "block.stl")
        rotation = solid.quaternion_matrix(self.quat)
        if stl is None:
            generate("shape truncated-cube", self.path, "--side", side, "--mass", mass)
            meta = read_json(os.path.join(workdir, "block.json"))
            self.side = float(meta["parameters"]["side"])
            self.cut = float(meta["parameters"]["corner_cut"])
            inertia, centroid = np.asarray(meta["inertia"], float), np.zeros(3)
            points, triangles = vtu.read_stl(self.path)
        else:
            self.side = self.cut = None
            points, triangles = vtu.read_stl(stl)
            _, centroid, inertia = solid.mass_properties(points, triangles, self.mass)
        points = (points - centroid) @ rotation.T
        bodyframes.write_stl(self.path, points, triangles, name="block")
        self.inertia = rotation @ inertia @ rotation.T     # space axes as placed
        self.half = float(-points[:, 2].min())             # centroid to the lowest point
        self.points = points                               # the vertices as placed
        self.radius = float(np.linalg.norm(points[:, :2], axis=1).max())

    def extent(self, direction):
        """Distance from the centroid to the block's foremost vertex along ``direction``."""
        d = np.asarray(direction, float)
        return float(np.max(self.points @ (d / np.linalg.norm(d))))

    def inertia_variables(self):
        """The deck variables of the inertia tensor about the centroid (space axes)."""
        i = self.inertia
        return dict(ixx=repr(i[0, 0]), iyy=repr(i[1, 1]), izz=repr(i[2, 2]),
                    ixy=repr(i[0, 1]), ixz=repr(i[0, 2]), iyz=repr(i[1, 2]))


def compose(first, then):
    """The unit quaternion [w, x, y, z] of the rotation ``then`` followed by ``first`` (the
    Hamilton product first * then): ``then`` turns the block in its own frame, ``first`` places
    it."""
    w1, x1, y1, z1 = first
    w2, x2, y2, z2 = then
    return (w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2)


def floor_damping(restitution, kn, mass):
    """gamma_n [1/s] of fix wirenet/body's floor (F = kn d - gamma_n M v_n) that gives a body of
    this mass the coefficient of restitution: the damped linear oscillator's
    zeta = -ln e / sqrt(pi^2 + ln^2 e), gamma_n = 2 zeta sqrt(kn / M)."""
    log_e = math.log(restitution)
    zeta = -log_e / math.sqrt(math.pi ** 2 + log_e ** 2)
    return 2.0 * zeta * math.sqrt(kn / mass)


TOUCH_FRACTION = 0.005   # the block has touched once it is this part of its speed short of its
                         # free flight (0.5 %: 2.5 mm/s at 5 m/s, 0.13 m/s at 25 m/s)


def first_touch(time, travel, velocity, gravity):
    """(time, travel) at which the block touched the net: the first time its velocity differs
    from its free flight from the release (``gravity`` the acceleration vector) by
    TOUCH_FRACTION of its release speed, interpolated between the output rows. The momentum it
    has lost is an integral of the contact force, smooth where the force itself is not: the
    first row with a contact force can be one node's graze of a few microseconds (measured on
    the quick fence: 2 kN in one row, none in the next four; the block's first row with a force
    moved by 5 rows, 4.5 % of the braking distance, when contact.ks changed by 20 %). The first
    row's time and travel for a block that never lost that much."""
    time = np.asarray(time, float)
    velocity = np.asarray(velocity, float)
    speed0 = float(np.linalg.norm(velocity[0]))
    free = velocity[0] + np.outer(time - time[0], gravity)
    short = np.linalg.norm(free - velocity, axis=1) / max(speed0, np.finfo(float).tiny)
    past = np.nonzero(short >= TOUCH_FRACTION)[0]
    if not past.size or past[0] == 0:
        return float(time[0]), float(travel[0])
    k = int(past[0])
    # the lost speed grows as the square of the time since the touch (a contact force that
    # grows from zero): its root is linear in time between two rows on that curve; the row
    # before the touch is not on it (nothing lost yet), so from the two after it, backwards
    root, limit = np.sqrt(short), math.sqrt(TOUCH_FRACTION)
    a = k if root[k - 1] < 0.5 * limit and k + 1 < len(time) else k - 1
    when = time[a] + (limit - root[a]) / (root[a + 1] - root[a]) * (time[a + 1] - time[a])
    when = min(max(when, time[k - 1]), time[k])
    return float(when), float(np.interp(when, time[k - 1:k + 1], travel[k - 1:k + 1]))
