"""A symmetric mesh for tests: a Netgen mesh of half a scene and its mirror image at x = 0."""

import numpy as np

import ngdgfric as ndf
from ngdgfric.meshes import mesh_arrays, mesh_from_arrays


def mirrored(half, full, names=None):
    """A Netgen mesh of ``half`` (symmetry side "axis" on x = 0) and its mirror image as a mesh of ``full``, the
    mirrored sides renamed by ``names``."""
    mesh = ndf.netgen_mesh(half, 0.3)
    points, triangles, segments, labels = mesh_arrays(mesh)
    n = len(points)
    on_axis = np.flatnonzero(np.abs(points[:, 0]) < 1e-14)
    remap = np.arange(2 * n)
    remap[on_axis + n] = on_axis
    keep = labels != "axis"
    triangles = remap[np.vstack([triangles, triangles[:, [0, 2, 1]] + n])]
    segments = remap[np.vstack([segments[keep], segments[keep][:, ::-1] + n])]
    used = np.unique(triangles)
    number = np.full(2 * n, -1)
    number[used] = np.arange(len(used))
    labels = np.concatenate([labels[keep], [(names or {}).get(label, label) for label in labels[keep]]])
    whole = mesh_from_arrays(full, np.vstack([points, points * [-1, 1]])[used], number[triangles], number[segments],
                             labels)
    return mesh, whole
