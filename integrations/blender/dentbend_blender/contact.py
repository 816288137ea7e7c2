"""Where a projectile moving along a direction first touches a target (world coordinates)."""

import numpy as np
from mathutils import Vector
from mathutils.bvhtree import BVHTree


def first_contact(target_positions, target_triangles, projectile_positions, projectile_triangles, direction):
    """How far the projectile moves along the unit ``direction`` until it touches the target,
    m, and the contact point; ``None`` when it never does.

    Rays from every projectile vertex along the direction hit the target, and rays from every
    target vertex against the direction hit the projectile; the shortest travel wins. Rays
    start a hair (1e-6 of the scene's size) behind their vertex, so a projectile already
    touching the target is found at travel 0.
    """
    both = np.concatenate([target_positions, projectile_positions])
    size = float(np.linalg.norm(both.max(axis=0) - both.min(axis=0)))
    reach, back = 2.0 * size + 1.0, 1e-6 * size
    best = None
    d = Vector(direction)
    for sources, triangles, hit_positions, sign in (
        (projectile_positions, target_triangles, target_positions, 1.0),
        (target_positions, projectile_triangles, projectile_positions, -1.0),
    ):
        tree = BVHTree.FromPolygons(hit_positions.tolist(), triangles.tolist(), all_triangles=True)
        ray = d * sign
        for p in sources:
            start = Vector(p) - ray * back
            location, _normal, _index, distance = tree.ray_cast(start, ray, reach)
            if location is None:
                continue
            travel = max(distance - back, 0.0)
            if best is None or travel < best[0]:
                # The contact is on the target: the hit itself, or the target vertex the
                # projectile reaches.
                point = location if sign > 0 else Vector(p)
                best = (travel, np.array(point, dtype=np.float64))
    return best
