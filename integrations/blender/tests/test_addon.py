"""The Blender add-on, headless (the bpy module): register it, dent a UV-mapped cube with a
sphere, check the dent, the attributes and undo."""

import os
import pathlib
import sys

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

import dentbend_blender  # noqa: E402

DEPTH = 0.2


def read(collection, key, width, dtype=np.float32):
    values = np.empty(len(collection) * width, dtype=dtype)
    collection.foreach_get(key, values)
    return values.reshape(len(collection), width)


@pytest.fixture
def scene():
    """The default startup file (one window, for undo), emptied; a 2 m UV-mapped cube with a
    corner colour and a point weight (its rest height), and a 0.5 m sphere above it, active."""
    bpy.ops.wm.read_homefile()
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    dentbend_blender.register()
    bpy.ops.mesh.primitive_cube_add(size=2.0)
    cube = bpy.context.active_object
    colour = cube.data.color_attributes.new("Paint", "BYTE_COLOR", "CORNER")
    corners = len(cube.data.loops)
    colour.data.foreach_set("color", np.tile([0.25, 0.5, 0.75, 1.0], corners).astype(np.float32))
    weight = cube.data.attributes.new("rest_height", "FLOAT", "POINT")
    weight.data.foreach_set("value", read(cube.data.vertices, "co", 3)[:, 2].copy())
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, location=(0.0, 0.0, 2.0))
    sphere = bpy.context.active_object
    cube.select_set(True)
    sphere.select_set(True)
    bpy.context.view_layer.objects.active = sphere
    yield cube, sphere
    dentbend_blender.unregister()


def in_window(operator, **arguments):
    window = bpy.context.window_manager.windows[0]
    with bpy.context.temp_override(window=window):
        return operator(**arguments)


def test_the_operator_dents_the_cube_and_keeps_its_attributes(scene):
    cube, _ = scene
    result = in_window(bpy.ops.object.dentbend_dent, depth=DEPTH)
    assert result == {"FINISHED"}
    mesh = cube.data
    positions = read(mesh.vertices, "co", 3)
    # The top face's vertices: inside its square (the sides' have |x| or |y| = 1; refinement
    # adds some there too, the cube's triangles being large).
    top = (np.abs(positions[:, 0]) < 0.999) & (np.abs(positions[:, 1]) < 0.999) & (positions[:, 2] > 0.5)
    # The sphere fell along its local -Z onto the top face (z = 1): the deepest point went down
    # by the depth (the library's peak displacement is exact to float32 rounding, 1e-5 m).
    assert positions[top, 2].min() == pytest.approx(1.0 - DEPTH, abs=1e-4)
    # The dent is round and centred: the deepest vertex is under the sphere's centre, within
    # the refined grid's spacing (about 0.1 m here).
    deepest = positions[top][np.argmin(positions[top, 2])]
    assert np.hypot(deepest[0], deepest[1]) < 0.1
    # The bottom never moves.
    assert np.allclose(positions[positions[:, 2] < -0.5, 2], -1.0)
    # The 8-vertex cube was refined to carry the dent.
    assert len(mesh.vertices) > 8

    # The UV layer survived, one UV per corner, within the cube's UV layout.
    assert "UVMap" in mesh.uv_layers and mesh.uv_layers.active.name == "UVMap"
    uvs = read(mesh.uv_layers["UVMap"].data, "uv", 2)
    assert len(uvs) == len(mesh.loops)
    assert np.all((uvs >= -1e-6) & (uvs <= 1.0 + 1e-6))
    # New corners on the top face interpolate the top face's UVs: they lie in its UV square.
    corner_vertex = read(mesh.loops, "vertex_index", 1, np.int32)[:, 0]
    polygon_normals = read(mesh.polygons, "normal", 3)
    loop_start = read(mesh.polygons, "loop_start", 1, np.int32)[:, 0]
    loop_total = read(mesh.polygons, "loop_total", 1, np.int32)[:, 0]
    face_of_corner = np.repeat(np.arange(len(mesh.polygons)), loop_total)
    assert np.array_equal(np.repeat(loop_start, loop_total) + np.concatenate([np.arange(n) for n in loop_total]),
                          np.arange(len(mesh.loops)))
    rest = read(mesh.attributes["rest_height"].data, "value", 1)[:, 0]
    top_corners = rest[corner_vertex] > 0.999
    top_uvs = uvs[top_corners & (polygon_normals[face_of_corner][:, 2] > 0.0)]
    original_top = np.array([[0.625, 0.5], [0.875, 0.75]])
    assert np.all(top_uvs >= original_top[0] - 1e-5) and np.all(top_uvs <= original_top[1] + 1e-5)
    # The point weight (the rest height) interpolates: every new vertex on the top face has
    # rest height 1 exactly, wherever the dent moved it.
    assert np.allclose(rest[top], 1.0, atol=1e-6)
    sides = np.abs(np.abs(positions[:, :2]).max(axis=1) - 1.0) < 1e-6
    assert np.allclose(rest[sides], positions[sides, 2], atol=1e-6)
    # The corner colour is constant, so every corner keeps it (byte rounding: 1/255).
    paint = read(mesh.color_attributes["Paint"].data, "color", 4)
    assert np.allclose(paint, [0.25, 0.5, 0.75, 1.0], atol=1 / 255)
    # Polygons the dent did not touch keep their quads: the bottom is one quad still.
    bottom = polygon_normals[:, 2] < -0.99
    assert bottom.sum() == 1 and loop_total[bottom][0] == 4
    assert mesh.validate(verbose=False) is False


def test_undo_restores_the_cube(scene):
    cube, _ = scene
    before = read(cube.data.vertices, "co", 3)
    # Blender pushes an undo step after an operator with UNDO in its options; headless, the
    # test pushes the steps around it as the interface would (undo starts off in background
    # mode until the first push).
    assert "UNDO" in bpy.types.OBJECT_OT_dentbend_dent.bl_options
    in_window(bpy.ops.ed.undo_push, message="before the dent")
    assert in_window(bpy.ops.object.dentbend_dent, depth=DEPTH) == {"FINISHED"}
    in_window(bpy.ops.ed.undo_push, message="Dent (dentbend)")
    dented = len(bpy.data.objects["Cube"].data.vertices)
    assert dented > 8
    in_window(bpy.ops.ed.undo)
    cube = bpy.data.objects["Cube"]
    assert len(cube.data.vertices) == 8 and len(cube.data.polygons) == 6
    assert np.array_equal(read(cube.data.vertices, "co", 3), before)
    assert "UVMap" in cube.data.uv_layers
    in_window(bpy.ops.ed.redo)
    assert len(bpy.data.objects["Cube"].data.vertices) == dented


def test_a_direction_that_misses_changes_nothing(scene):
    cube, _ = scene
    before = read(cube.data.vertices, "co", 3)
    result = in_window(bpy.ops.object.dentbend_dent, depth=DEPTH, direction="CUSTOM", custom_direction=(0, 0, 1))
    assert result == {"CANCELLED"}
    assert np.array_equal(read(cube.data.vertices, "co", 3), before)


def test_refine_off_moves_the_vertices_it_has(scene):
    cube, sphere = scene
    # A 16 x 16 grid on top, so the vertices alone can carry the dent.
    bpy.context.view_layer.objects.active = cube
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.subdivide(number_cuts=15)
    bpy.ops.object.mode_set(mode="OBJECT")
    bpy.context.view_layer.objects.active = sphere
    count = len(cube.data.vertices)
    polygons = len(cube.data.polygons)
    assert in_window(bpy.ops.object.dentbend_dent, depth=0.1, refine=False, preserve_volume=True) == {"FINISHED"}
    assert (len(cube.data.vertices), len(cube.data.polygons)) == (count, polygons)
    positions = read(cube.data.vertices, "co", 3)
    assert positions[:, 2].max() > 1.0  # the rim the kept volume raises
    top = (np.abs(positions[:, 0]) < 0.999) & (np.abs(positions[:, 1]) < 0.999) & (positions[:, 2] > 0.5)
    assert positions[top, 2].min() == pytest.approx(0.9, abs=1e-4)


INSTALL = """
import sys, bpy, numpy as np
bpy.ops.wm.read_homefile()
window = bpy.context.window_manager.windows[0]
with bpy.context.temp_override(window=window):
    assert bpy.ops.extensions.package_install_files(
        filepath=sys.argv[1], repo="user_default", enable_on_install=True) == {"FINISHED"}
assert "bl_ext.user_default.dentbend" in bpy.context.preferences.addons
site = bpy.utils.user_resource("EXTENSIONS", path=".local")
for obj in list(bpy.data.objects):
    bpy.data.objects.remove(obj)
bpy.ops.mesh.primitive_cube_add(size=2.0)
cube = bpy.context.active_object
bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, location=(0.0, 0.0, 2.0))
cube.select_set(True)
with bpy.context.temp_override(window=window):
    assert bpy.ops.object.dentbend_dent(depth=0.2) == {"FINISHED"}
co = np.empty(3 * len(cube.data.vertices), np.float32)
cube.data.vertices.foreach_get("co", co)
co = co.reshape(-1, 3)
top = (np.abs(co[:, 0]) < 0.999) & (np.abs(co[:, 1]) < 0.999) & (co[:, 2] > 0.5)
print("installed", site, co[top, 2].min())
"""


@pytest.mark.skipif(not os.environ.get("DENTBEND_BLENDER_ZIP"), reason="DENTBEND_BLENDER_ZIP names no packed extension")
def test_the_packed_extension_installs_with_its_wheel_and_dents(tmp_path):
    """The zip build_extension.py packs installs as Blender installs extensions (in a fresh
    user configuration), its dentbend wheel with it, and its operator dents."""
    import subprocess

    archive = os.path.abspath(os.environ["DENTBEND_BLENDER_ZIP"])
    env = dict(os.environ, XDG_CONFIG_HOME=str(tmp_path), HOME=str(tmp_path))
    run = subprocess.run([sys.executable, "-c", INSTALL, archive], env=env, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stdout + run.stderr
    line = next(l for l in run.stdout.splitlines() if l.startswith("installed"))
    _, site, lowest = line.split()
    assert list(pathlib.Path(site).glob("lib/python3*/site-packages/dentbend/__init__.py"))
    assert float(lowest) == pytest.approx(0.8, abs=1e-4)


def test_edges_wires_loose_vertices_and_custom_normals_survive_a_refining_dent(scene):
    cube, _ = scene
    mesh = cube.data
    for edge in mesh.edges:
        edge.use_seam = True
    mesh.normals_split_custom_set([(0.0, 0.0, 1.0)] * len(mesh.loops))
    # A wire edge and a loose vertex, far from the dent.
    mesh.vertices.add(3)
    mesh.vertices.foreach_set("co", np.concatenate([read(mesh.vertices, "co", 3)[:8].ravel(), [3, 0, 0, 3, 1, 0, 4, 4, 4]]))
    mesh.edges.add(1)
    mesh.edges[-1].vertices = (8, 9)
    mesh.update()
    assert in_window(bpy.ops.object.dentbend_dent, depth=DEPTH) == {"FINISHED"}
    positions = read(mesh.vertices, "co", 3)
    edges = read(mesh.edges, "vertices", 2, np.int32)
    seams = np.array([edge.use_seam for edge in mesh.edges])
    # The cube's 12 edges were split by the refinement; every piece is still a seam, and no
    # new edge across a face is: a seam's two ends lie on one cube edge (two coordinates at +-1).
    on_cube_edge = (np.abs(np.abs(positions) - 1.0) < 1e-6).sum(axis=1) >= 2
    assert seams.sum() > 12
    assert np.all(on_cube_edge[edges[seams]])
    # The wire edge and the loose vertex are still there, unchanged.
    wire = [i for i, (a, b) in enumerate(edges.tolist()) if {a, b} == {8, 9}]
    assert len(wire) == 1 and np.allclose(positions[8:11], [[3, 0, 0], [3, 1, 0], [4, 4, 4]])
    # The custom normals are interpolated: every corner's is still +z, to Blender's storage
    # (two 16-bit angles in each corner's normal space, which the dent tilts: 2.5e-3 at worst
    # here, 0.15 degrees; a normal left out or taken from the wrong corner is off by 0.1 or more).
    assert mesh.has_custom_normals
    normals = read(mesh.corner_normals, "vector", 3)
    assert np.allclose(normals, [0.0, 0.0, 1.0], atol=5e-3)


def test_a_mirrored_object_is_dented_inwards(scene):
    cube, _ = scene
    # Mirrored in x: its triangles are inside out in world coordinates until turned back.
    cube.scale = (-1.0, 1.0, 1.0)
    bpy.context.view_layer.update()
    assert in_window(bpy.ops.object.dentbend_dent, depth=DEPTH) == {"FINISHED"}
    positions = read(cube.data.vertices, "co", 3)
    top = (np.abs(positions[:, 0]) < 0.999) & (np.abs(positions[:, 1]) < 0.999) & (positions[:, 2] > 0.5)
    assert positions[top, 2].min() == pytest.approx(1.0 - DEPTH, abs=1e-4)
    assert positions[:, 2].max() == pytest.approx(1.0, abs=1e-6)
    # The mesh's own winding is kept: its polygons still face out in its own coordinates.
    normals = read(cube.data.polygons, "normal", 3)
    centres = read(cube.data.polygons, "center", 3)
    assert np.all(np.einsum("ij,ij->i", normals, centres) > 0.0)


def test_vertex_group_weights_survive_a_refining_dent(scene):
    cube, _ = scene
    group = cube.vertex_groups.new(name="Weights")
    # Weight = (rest height + 1) / 2: 1 on top, 0 at the bottom, so new vertices' weights
    # follow their rest height.
    for vertex in cube.data.vertices:
        group.add([vertex.index], (vertex.co.z + 1.0) / 2.0, "REPLACE")
    assert in_window(bpy.ops.object.dentbend_dent, depth=DEPTH) == {"FINISHED"}
    mesh = cube.data
    assert len(mesh.vertices) > 8
    rest = read(mesh.attributes["rest_height"].data, "value", 1)[:, 0]
    # The group is made again by the rebuild: found by name, at its old index.
    index = cube.vertex_groups["Weights"].index
    assert index == 0 and cube.vertex_groups.active_index == 0
    weights = np.array([next(g.weight for g in v.groups if g.group == index) for v in mesh.vertices])
    assert np.allclose(weights, (rest + 1.0) / 2.0, atol=1e-6)


def test_a_far_away_object_keeps_its_untouched_vertices_exactly(scene):
    cube, sphere = scene
    # 20 km from the origin, turned: float32 world coordinates there are 2 mm apart.
    for obj in (cube, sphere):
        obj.location.x += 20000.0
    cube.rotation_euler = (0.0, 0.0, 0.5)
    bpy.context.view_layer.update()
    before = read(cube.data.vertices, "co", 3)
    assert in_window(bpy.ops.object.dentbend_dent, depth=DEPTH, refine=False) == {"FINISHED"}
    after = read(cube.data.vertices, "co", 3)
    # The 8-vertex cube has only corners: the dent moves the top four; the bottom four are
    # untouched and keep their coordinates bit for bit.
    bottom = before[:, 2] < 0.0
    assert np.array_equal(after[bottom], before[bottom])
    # The dent is made near the target, so it is as exact there as at the origin: the corners
    # it moves went down, by at most the depth.
    drop = before[~bottom, 2] - after[~bottom, 2]
    assert np.all(drop >= 0.0) and drop.max() <= DEPTH + 1e-5


def test_zero_scale_and_a_mesh_shared_with_the_active_object_are_refused(scene):
    cube, sphere = scene
    cube.scale = (1.0, 1.0, 0.0)
    bpy.context.view_layer.update()
    assert in_window(bpy.ops.object.dentbend_dent, depth=DEPTH) == {"CANCELLED"}
    cube.scale = (1.0, 1.0, 1.0)
    twin = sphere.copy()  # shares the sphere's mesh
    bpy.context.collection.objects.link(twin)
    twin.location = (0.0, 0.0, 0.8)
    cube.select_set(False)
    twin.select_set(True)
    bpy.context.view_layer.update()
    vertices = len(sphere.data.vertices)
    assert in_window(bpy.ops.object.dentbend_dent, depth=DEPTH) == {"CANCELLED"}
    assert len(sphere.data.vertices) == vertices
