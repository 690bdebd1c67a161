"""Mass properties of a closed triangulated surface (a block given as an STL) and rotations.

Volume, centroid and inertia tensor of the uniform solid a closed, consistently oriented
triangle mesh bounds, from the signed tetrahedra each facet forms with the origin (the
divergence theorem; Tonon, J. Math. Stat. 1 (2004) 8-11, for the covariance of a tetrahedron).
"""

import numpy as np

from .errors import PostprocessError

# covariance of the canonical tetrahedron (0, e1, e2, e3), scaled by its volume 1/6
_CANONICAL = np.array([[2, 1, 1], [1, 2, 1], [1, 1, 2]], float) / 120.0


def mass_properties(points, triangles, mass):
    """(volume, centroid, inertia about the centroid) of the uniform solid of ``mass``."""
    tri = points[np.asarray(triangles, int)]
    a = tri.transpose(0, 2, 1)                       # columns: the three vertices
    det = np.linalg.det(a)                            # 6 x signed volume of each tetrahedron
    volume = float(det.sum() / 6.0)
    if not abs(volume) > 1e-15:
        raise PostprocessError("block STL: the surface encloses no volume (not closed?)")
    if volume < 0:                                    # inward-facing facets: flip the sign
        det, volume = -det, -volume
    centroid = (det[:, None] * tri.sum(axis=1)).sum(axis=0) / (24.0 * volume)
    cov = np.einsum("n,nij,jk,nlk->il", det, a, _CANONICAL, a)   # second moment about 0, x V
    cov = cov / volume - np.outer(centroid, centroid)            # about the centroid, per volume
    inertia = mass * (np.trace(cov) * np.eye(3) - cov)
    return volume, centroid, inertia


def quaternion_matrix(q):
    """Rotation matrix of the unit quaternion (w, x, y, z) (normalised here)."""
    w, x, y, z = np.asarray(q, float) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
