"""The loading body's frames for the ParaView series when the body is an analytic one (fix
wirenet/body, inputs/include/frames_body_analytic.in): the deck writes the body's pose
(frames/body_pose.txt: step, centre x y z, unit quaternion w x y z of the rotation since the fix
was defined) and this module moves the generator's STL of the same shape to each pose, writing
frames/body_STEP.stl, the files `dump mesh/stl` writes on the mesh path. The STL is only drawn:
the simulation does not use it.

The generator's STL must have the fix's reference point at its origin and the body's starting
orientation: the platters' base centre (spheroid centre, cone base centre; the STL dome or cone
points to -z, as the deck's body does) and the block's centroid.
"""

import os

import numpy as np

from .errors import PostprocessError
from .vtu import read_stl

POSE_FILE = "body_pose.txt"


def read_poses(path):
    """{step: (centre[3], quaternion[4])}, the last row of a step winning (comment lines and the
    title line skipped)."""
    poses = {}
    with open(path, encoding="utf-8") as handle:
        for number, line in enumerate(handle, 1):
            fields = line.split()
            if not fields or fields[0].startswith("#") or fields[0] == "step":
                continue
            if len(fields) != 8:
                raise PostprocessError(f"{path}:{number}: expected 8 numbers (step x y z qw qx qy "
                                       f"qz), got '{line.strip()}'")
            values = [float(v) for v in fields]
            poses[int(round(values[0]))] = (np.array(values[1:4]), np.array(values[4:8]))
    return poses


def rotation(q):
    """Rotation matrix of the unit quaternion (w, x, y, z)."""
    w, x, y, z = np.asarray(q, float) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def write_stl(path, points, triangles, name="body"):
    """ASCII STL of the triangles (facet normals from the vertex order)."""
    tri = points[triangles]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    length = np.linalg.norm(normals, axis=1)
    normals = normals / np.where(length > 0, length, 1.0)[:, None]
    lines = [f"solid {name}"]
    for n, t in zip(normals, tri):
        lines.append(f"facet normal {n[0]:.9g} {n[1]:.9g} {n[2]:.9g}\nouter loop")
        lines.extend(f"vertex {v[0]:.9g} {v[1]:.9g} {v[2]:.9g}" for v in t)
        lines.append("endloop\nendfacet")
    lines.append(f"endsolid {name}\n")
    with open(path, "w", encoding="utf-8") as handle:
        handle.write("\n".join(lines))


def write_body_frames(workdir, stl):
    """frames/body_STEP.stl from frames/body_pose.txt of a run folder and the body's STL.
    Returns the number of frames written (0 when the run wrote no poses: the mesh path)."""
    frames = os.path.join(workdir, "frames")
    pose_path = os.path.join(frames, POSE_FILE)
    if not os.path.isfile(pose_path):
        return 0
    poses = read_poses(pose_path)
    points, triangles = read_stl(stl)
    for step, (centre, quat) in sorted(poses.items()):
        moved = centre + points @ rotation(quat).T
        write_stl(os.path.join(frames, f"body_{step}.stl"), moved, triangles)
    return len(poses)
