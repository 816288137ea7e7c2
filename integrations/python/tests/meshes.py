"""Closed test meshes built with numpy: a UV sphere and a box whose faces are grids."""

import numpy as np


def sphere(radius=0.5, rings=12, segments=24, center=(0.0, 0.0, 0.0)):
    """A closed UV sphere: (positions float32 (N, 3), faces uint32 (M, 3)), outward winding."""
    positions = [(0.0, 0.0, radius)]
    for i in range(1, rings):
        theta = np.pi * i / rings
        for j in range(segments):
            phi = 2.0 * np.pi * j / segments
            positions.append((radius * np.sin(theta) * np.cos(phi), radius * np.sin(theta) * np.sin(phi),
                              radius * np.cos(theta)))
    positions.append((0.0, 0.0, -radius))
    bottom = len(positions) - 1
    ring = lambda i, j: 1 + (i - 1) * segments + j % segments
    faces = []
    for j in range(segments):
        faces.append((0, ring(1, j), ring(1, j + 1)))
        faces.append((bottom, ring(rings - 1, j + 1), ring(rings - 1, j)))
    for i in range(1, rings - 1):
        for j in range(segments):
            a, b, c, d = ring(i, j), ring(i, j + 1), ring(i + 1, j), ring(i + 1, j + 1)
            faces.append((a, c, b))
            faces.append((b, c, d))
    points = np.asarray(positions, dtype=np.float32) + np.asarray(center, dtype=np.float32)
    return points, np.asarray(faces, dtype=np.uint32)


def box(size=(2.0, 2.0, 0.5), cells=(8, 8, 2)):
    """A closed box centred on the origin, each side a grid of cells (welded at the edges)."""
    half = np.asarray(size, dtype=np.float64) / 2.0
    index = {}
    positions, faces = [], []

    def vertex(p):
        key = tuple(np.round(p, 9))
        if key not in index:
            index[key] = len(positions)
            positions.append(p)
        return index[key]

    for axis in range(3):
        u, v = (axis + 1) % 3, (axis + 2) % 3
        for sign in (-1.0, 1.0):
            nu, nv = cells[u], cells[v]
            grid = np.empty((nu + 1, nv + 1), dtype=np.int64)
            for i in range(nu + 1):
                for j in range(nv + 1):
                    p = np.zeros(3)
                    p[axis] = sign * half[axis]
                    p[u] = -half[u] + 2.0 * half[u] * i / nu
                    p[v] = -half[v] + 2.0 * half[v] * j / nv
                    grid[i, j] = vertex(p)
            for i in range(nu):
                for j in range(nv):
                    a, b, c, d = grid[i, j], grid[i + 1, j], grid[i, j + 1], grid[i + 1, j + 1]
                    # (u, v, axis) is right-handed: u x v = +axis, so (a, b, d) faces +axis.
                    if sign > 0:
                        faces += [(a, b, d), (a, d, c)]
                    else:
                        faces += [(a, d, b), (a, c, d)]
    return np.asarray(positions, dtype=np.float32), np.asarray(faces, dtype=np.uint32)


def box_asset(size=(4.0, 4.0, 0.5), cells=(4, 4, 1)):
    """``box`` as a game asset: one vertex per side at its hard edges, each side's normal
    authored, UVs projected per side at 2 UV units a metre (the side's other two coordinates).
    (positions, faces, normals, uvs)."""
    welded, faces = box(size, cells)
    positions, normals, uvs, out, index = [], [], [], [], {}
    for face in faces:
        a, b, c = welded[face].astype(np.float64)
        n = np.cross(b - a, c - a)
        axis = int(np.argmax(np.abs(n)))
        sign = 1.0 if n[axis] > 0 else -1.0
        corners = []
        for v in face:
            key = (int(v), axis, sign)
            if key not in index:
                index[key] = len(positions)
                p = welded[v]
                positions.append(p)
                normal = np.zeros(3)
                normal[axis] = sign
                normals.append(normal)
                others = [k for k in range(3) if k != axis]
                uvs.append(2.0 * p[others])
            corners.append(index[key])
        out.append(corners)
    return (np.asarray(positions, dtype=np.float32), np.asarray(out, dtype=np.uint32),
            np.asarray(normals, dtype=np.float32), np.asarray(uvs, dtype=np.float32))
