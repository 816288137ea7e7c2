"""A Blender mesh as dentbend's arrays, and the dented arrays written back with every attribute.

A dent that only moves vertices writes their positions and nothing else. A dent that refines
rebuilds the mesh: polygons none of whose triangles changed are kept as they were (quads and
n-gons included); the pieces of the others become triangles. Every attribute but strings is
carried over: point and corner values of new vertices and corners interpolate their parents'
(floats, vectors and colours linearly; integers, booleans, quaternions and matrices from the
nearer parent), faces keep their polygon's values, and edges that lie along an old edge keep
its values. Vertex-group weights are interpolated like point floats.

dentbend works in float32, so positions go to it relative to an origin near the target
(computed in float64), and the vertices a dent did not move keep their own coordinates
exactly.
"""

import numpy as np

# Attributes that are the mesh's topology, rebuilt rather than copied.
TOPOLOGY = {"position", ".edge_verts", ".corner_vert", ".corner_edge"}
# Per data type: the value's property name, its components, its numpy dtype, interpolated?
TYPES = {
    "FLOAT": ("value", 1, np.float32, True),
    "FLOAT2": ("vector", 2, np.float32, True),
    "FLOAT_VECTOR": ("vector", 3, np.float32, True),
    "FLOAT_COLOR": ("color", 4, np.float32, True),
    "BYTE_COLOR": ("color", 4, np.float32, True),
    "QUATERNION": ("value", 4, np.float32, False),
    "FLOAT4X4": ("value", 16, np.float32, False),
    "INT": ("value", 1, np.int32, False),
    "INT8": ("value", 1, np.int32, False),
    "INT32_2D": ("value", 2, np.int32, False),
    "BOOLEAN": ("value", 1, bool, False),
}


def read(collection, key, width, dtype):
    """A foreach_get of ``key`` as an (n, width) array."""
    values = np.empty(len(collection) * width, dtype=dtype)
    collection.foreach_get(key, values)
    return values.reshape(len(collection), width)


def world_winding(triangles, world):
    """Triangles wound counter-clockwise seen from outside in world coordinates: a mirroring
    placement (negative determinant) turns them inside out, so they are flipped back."""
    return triangles[:, [0, 2, 1]] if np.linalg.det(world[:3, :3]) < 0.0 else triangles


class Triangulated:
    """A mesh's vertices and loop triangles as dentbend sees them (world coordinates relative
    to ``origin``, float32), with what ties them back to the mesh."""

    def __init__(self, obj, world):
        mesh = obj.data
        mesh.calc_loop_triangles()
        self.world_matrix = world
        self.local = read(mesh.vertices, "co", 3, np.float32).astype(np.float64)
        world_positions = self.local @ world[:3, :3].T + world[:3, 3]
        # The centre of the target's box: float32 keeps about 1e-7 of the distance from it.
        self.origin = (world_positions.min(axis=0) + world_positions.max(axis=0)) / 2.0
        self.relative = (world_positions - self.origin).astype(np.float32)
        self.triangles = read(mesh.loop_triangles, "vertices", 3, np.int32).astype(np.uint32)
        self.loops = read(mesh.loop_triangles, "loops", 3, np.int32)
        self.polygons = read(mesh.loop_triangles, "polygon_index", 1, np.int32)[:, 0]
        self.mirrored = np.linalg.det(world[:3, :3]) < 0.0
        # As dentbend sees them (world winding); `own_winding` turns its output faces back.
        self.world_triangles = world_winding(self.triangles, world)

    def own_winding(self, faces):
        """Faces in world winding back in the mesh's own."""
        return faces[:, [0, 2, 1]] if self.mirrored else faces

    def to_local(self, relative, moved):
        """dentbend's output positions (relative to the origin) in the object's coordinates;
        input vertices not in ``moved`` keep their own coordinates exactly."""
        inverse = np.linalg.inv(self.world_matrix)
        world_positions = relative.astype(np.float64) + self.origin
        local = world_positions @ inverse[:3, :3].T + inverse[:3, 3]
        still = np.ones(len(self.local), bool)
        still[moved[moved < len(self.local)]] = False
        local[: len(self.local)][still] = self.local[still]
        return local


def evaluated_world_mesh(obj, depsgraph):
    """The object as seen (modifiers applied): world positions (float64) and triangles."""
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        mesh.calc_loop_triangles()
        local = read(mesh.vertices, "co", 3, np.float32).astype(np.float64)
        world = np.array(evaluated.matrix_world, dtype=np.float64)
        positions = local @ world[:3, :3].T + world[:3, 3]
        triangles = world_winding(read(mesh.loop_triangles, "vertices", 3, np.int32).astype(np.uint32), world)
    finally:
        evaluated.to_mesh_clear()
    return positions, triangles


def write_positions(mesh, local):
    """Moves the vertices (same count); every attribute stays as it is."""
    mesh.vertices.foreach_set("co", local.astype(np.float32).ravel())
    mesh.update()


class Weights:
    """Each vertex of the dented mesh as a weighted sum of input vertices (new vertices from
    their parents, recursively)."""

    def __init__(self, base_count, parents, fractions):
        self.base_count = base_count
        self.sums = []
        for (a, b), t in zip(parents.tolist(), fractions.tolist()):
            total = {}
            for parent, weight in ((a, 1.0 - t), (b, t)):
                for vertex, w in self.of(parent).items():
                    total[vertex] = total.get(vertex, 0.0) + weight * w
            self.sums.append(total)

    def of(self, vertex):
        """``{input vertex: weight}`` for a vertex of the dented mesh."""
        return {vertex: 1.0} if vertex < self.base_count else self.sums[vertex - self.base_count]


class Blend:
    """New elements as weighted sums of old ones: rows, columns (old element), weights."""

    def __init__(self, count):
        self.count = count
        self.rows, self.columns, self.weights = [], [], []
        self.chunks = []

    def add(self, row, column, weight):
        self.rows.append(row)
        self.columns.append(column)
        self.weights.append(weight)

    def copy(self, rows, columns):
        """Rows that copy old elements whole (arrays of equal length)."""
        self.chunks.append((np.asarray(rows, np.int64), np.asarray(columns, np.int64), np.ones(len(rows))))

    def entries(self):
        """All (rows, columns, weights) as arrays."""
        parts = self.chunks + [
            (np.asarray(self.rows, np.int64), np.asarray(self.columns, np.int64), np.asarray(self.weights, np.float64))
        ]
        return tuple(np.concatenate([part[k] for part in parts]) for k in range(3))

    def apply(self, old, interpolate):
        """The new elements' values from the old ones: weighted sums, or the heaviest source."""
        rows, columns, weights = self.entries()
        if interpolate:
            out = np.zeros((self.count, old.shape[1]), np.float64)
            np.add.at(out, rows, weights[:, None] * old[columns].astype(np.float64))
            return out.astype(old.dtype)
        # Heaviest source per row: sort by (row, weight) and keep each row's last.
        order = np.lexsort((weights, rows))
        last = np.ones(len(order), bool)
        last[:-1] = rows[order][1:] != rows[order][:-1]
        out = np.zeros((self.count, old.shape[1]), old.dtype)
        out[rows[order][last]] = old[columns[order][last]]
        return out


def read_attributes(mesh):
    """Every attribute but the topology: (name, domain, type, values)."""
    out = []
    for attribute in mesh.attributes:
        if attribute.name in TOPOLOGY or attribute.data_type not in TYPES:
            continue
        key, width, dtype, _ = TYPES[attribute.data_type]
        out.append((attribute.name, attribute.domain, attribute.data_type, read(attribute.data, key, width, dtype)))
    return out


def rebuild(obj, source, result, local):
    """Rebuilds ``obj``'s mesh (read as ``source``) as the refined, dented ``result`` (local
    positions ``local``), keeping untouched polygons and carrying every attribute and the
    vertex-group weights."""
    mesh = obj.data
    base_vertices, base_triangles = len(source.local), len(source.triangles)
    faces, face_parents = source.own_winding(result.faces), result.face_parents.astype(np.int64)
    split = np.zeros(base_triangles, bool)
    split[face_parents[base_triangles:]] = True
    split |= np.any(faces[:base_triangles] != source.triangles, axis=1)
    broken = np.zeros(len(mesh.polygons), bool)
    broken[source.polygons[split]] = True

    loop_start = read(mesh.polygons, "loop_start", 1, np.int32)[:, 0]
    loop_total = read(mesh.polygons, "loop_total", 1, np.int32)[:, 0]
    corner_vertex = read(mesh.loops, "vertex_index", 1, np.int32)[:, 0]
    old_edges = read(mesh.edges, "vertices", 2, np.int32)
    kept = np.flatnonzero(~broken)
    pieces = np.flatnonzero(broken[source.polygons[face_parents]])

    # Corners: a kept polygon's are its old loops; a piece's interpolate its triangle's loops.
    weights = Weights(base_vertices, result.parents, result.fractions)
    kept_loops = np.concatenate([np.arange(s, s + n) for s, n in zip(loop_start[kept], loop_total[kept])] or [[]])
    kept_loops = kept_loops.astype(np.int64)
    corner_count = len(kept_loops) + 3 * len(pieces)
    corners = Blend(corner_count)
    corners.copy(np.arange(len(kept_loops)), kept_loops)
    row = len(kept_loops)
    for piece in pieces.tolist():
        parent = face_parents[piece]
        loop_of = dict(zip(source.triangles[parent].tolist(), source.loops[parent].tolist()))
        for vertex in faces[piece].tolist():
            for base, w in weights.of(vertex).items():
                # A piece's corners lie on its triangle, so their sources are its corners.
                corners.add(row, loop_of.get(base, source.loops[parent][0]), w)
            row += 1
    new_corner_vertex = np.concatenate([corner_vertex[kept_loops], faces[pieces].ravel().astype(np.int32)])
    starts = np.concatenate([[0], np.cumsum(np.concatenate([loop_total[kept], np.full(len(pieces), 3)]))[:-1]])
    face_sources = np.concatenate([kept, source.polygons[face_parents[pieces]]]).astype(np.int64)

    # Points: new vertices blend their input vertices.
    points = Blend(len(local))
    points.copy(np.arange(base_vertices), np.arange(base_vertices))
    for vertex in range(base_vertices, len(local)):
        for base, w in weights.of(vertex).items():
            points.add(vertex, base, w)

    attributes = read_attributes(mesh)
    uv_active = mesh.uv_layers.active.name if mesh.uv_layers.active else None
    uv_render = next((uv.name for uv in mesh.uv_layers if uv.active_render), None)
    color_active, color_default = mesh.attributes.active_color_name, mesh.attributes.default_color_name
    groups = read_groups(mesh, len(obj.vertex_groups))
    # Clearing the geometry clears the groups too: their names, locks and the active one.
    group_names = [(g.name, g.lock_weight) for g in obj.vertex_groups]
    active_group = obj.vertex_groups.active_index
    custom_normals = None
    if mesh.has_custom_normals:
        custom_normals = corners.apply(read(mesh.corner_normals, "vector", 3, np.float32), True)

    mesh.clear_geometry()
    mesh.vertices.add(len(local))
    mesh.vertices.foreach_set("co", local.astype(np.float32).ravel())
    mesh.loops.add(corner_count)
    mesh.loops.foreach_set("vertex_index", new_corner_vertex)
    mesh.polygons.add(len(starts))
    mesh.polygons.foreach_set("loop_start", starts.astype(np.int32))
    mesh.update(calc_edges=True)
    loose = loose_edges(old_edges, corner_vertex, loop_start, loop_total)
    if len(loose):
        # Edges of no polygon (wires) are never split: they come back as they were.
        made = read(mesh.edges, "vertices", 2, np.int32)
        mesh.edges.add(len(loose))
        mesh.edges.foreach_set("vertices", np.concatenate([made, loose]).ravel())
        mesh.update()

    edges = edge_blend(old_edges, read(mesh.edges, "vertices", 2, np.int32), weights, base_vertices)
    blends = {"POINT": points, "CORNER": corners, "EDGE": edges}
    for name, domain, data_type, values in attributes:
        key, _, _, interpolate = TYPES[data_type]
        if domain == "FACE":
            new = values[face_sources]
        elif domain in blends:
            new = blends[domain].apply(values, interpolate)
        else:
            continue
        attribute = mesh.attributes.get(name) or mesh.attributes.new(name, data_type, domain)
        attribute.data.foreach_set(key, new.ravel())
    if uv_active in mesh.uv_layers:
        mesh.uv_layers.active = mesh.uv_layers[uv_active]
    if uv_render in mesh.uv_layers:
        mesh.uv_layers[uv_render].active_render = True
    if color_active:
        mesh.attributes.active_color_name = color_active
    if color_default:
        mesh.attributes.default_color_name = color_default
    if groups is not None:
        for name, lock in group_names:
            group = obj.vertex_groups.get(name) or obj.vertex_groups.new(name=name)
            group.lock_weight = lock
        obj.vertex_groups.active_index = active_group
        write_groups(obj, points.apply(groups[0], True), points.apply(groups[1], True) > 0.0)
    if custom_normals is not None:
        lengths = np.linalg.norm(custom_normals, axis=1, keepdims=True)
        mesh.normals_split_custom_set((custom_normals / np.maximum(lengths, 1e-12)).tolist())
    mesh.update()


def read_groups(mesh, count):
    """Vertex-group weights and membership, (vertices, groups) each; None without groups."""
    if count == 0:
        return None
    weights = np.zeros((len(mesh.vertices), count), np.float32)
    member = np.zeros((len(mesh.vertices), count), np.float32)
    for vertex in mesh.vertices:
        for element in vertex.groups:
            if element.group < count:
                weights[vertex.index, element.group] = element.weight
                member[vertex.index, element.group] = 1.0
    return weights, member


def write_groups(obj, weights, member):
    """Puts vertex-group weights back after a rebuild: a vertex is in a group when any of its
    parents was."""
    for group in obj.vertex_groups:
        column = group.index
        for vertex in np.flatnonzero(member[:, column]).tolist():
            group.add([vertex], float(weights[vertex, column]), "REPLACE")


def loose_edges(edges, corner_vertex, loop_start, loop_total):
    """The edges no polygon uses, (k, 2)."""
    following = np.arange(len(corner_vertex)) + 1
    ends = np.repeat(loop_start + loop_total, loop_total)
    following[following == ends] = np.repeat(loop_start, loop_total)[following == ends]
    a, b = corner_vertex, corner_vertex[following]
    used = set(zip(np.minimum(a, b).tolist(), np.maximum(a, b).tolist()))
    keys = zip(edges.min(axis=1).tolist(), edges.max(axis=1).tolist())
    return edges[[key not in used for key in keys]].reshape(-1, 2)


def edge_blend(old_edges, new_edges, weights, base_vertices):
    """New edges from old ones: an edge whose two ends lie on one old edge (its ends, or
    vertices a split put on it) takes that edge's values; others take the type's zero."""
    old_index = {(min(a, b), max(a, b)): e for e, (a, b) in enumerate(old_edges.tolist())}
    blend = Blend(len(new_edges))

    def on_edges(vertex):
        """The old edges a vertex lies on: every edge at an input vertex, the edge(s) a new
        vertex's input vertices all lie on."""
        sources = [v for v, w in weights.of(vertex).items() if w > 0.0]
        if len(sources) == 1:
            return None  # an input vertex: any edge at it
        if len(sources) == 2:
            key = (min(sources), max(sources))
            return {old_index[key]} if key in old_index else set()
        return set()

    for e, (a, b) in enumerate(new_edges.tolist()):
        key = (min(a, b), max(a, b))
        if key in old_index:
            blend.add(e, old_index[key], 1.0)
            continue
        ends = [on_edges(a), on_edges(b)]
        known = [s for s in ends if s is not None]
        if not known:
            continue
        common = set.intersection(*known)
        # The old edge must also contain any input-vertex end.
        for vertex, s in zip((a, b), ends):
            if s is None:
                common = {c for c in common if vertex in old_edges[c]}
        if common:
            blend.add(e, min(common), 1.0)
    return blend
