"""Rigid-body helpers of the body and block tests: rows of thermo vectors, quaternions."""

import math

import numpy as np


def vec(row, *names):
    return np.array([row[n] for n in names])


def quat_rotate(q, v):
    w, x, y, z = q
    u = np.array([x, y, z])
    return v + 2 * np.cross(u, np.cross(u, v) + w * v)


def axis_angle(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    return np.concatenate([[math.cos(angle / 2)], math.sin(angle / 2) * axis])
