#!/usr/bin/env python3
"""Writes the hand-made seed corpus of the fuzz targets into fuzz/corpus/<target>/.

Run from anywhere: `python3 fuzz/seeds/make_seeds.py`. The scene seeds are copied from scenes/.
Every file is small; valid inputs and near-valid ones (one thing wrong) are mixed.
"""
import base64
import json
import os
import random
import shutil
import struct
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CORPUS = os.path.join(ROOT, "fuzz", "corpus")


def put(target, name, data):
    folder = os.path.join(CORPUS, target)
    os.makedirs(folder, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data)


# ---------------------------------------------------------------- OBJ
CUBE_V = [(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
CUBE_QUADS = [(1, 3, 4, 2), (5, 6, 8, 7), (1, 2, 6, 5), (3, 7, 8, 4), (1, 5, 7, 3), (2, 4, 8, 6)]


def obj_seeds():
    put("obj", "triangle.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    cube = "# cube\no cube\n" + "".join(f"v {x} {y} {z}\n" for x, y, z in CUBE_V)
    cube += "vt 0 0\nvt 1 0\nvn 0 0 1\ng sides\nusemtl grey\ns off\n"
    cube += "".join("f " + " ".join(f"{i}/1/1" for i in q) + "\n" for q in CUBE_QUADS)
    put("obj", "cube_quads.obj", cube)
    put("obj", "relative.obj", "v 0 0 0 1\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf -4//1 -3//1 -2//1 -1//1\nfo 1 2 3\n")
    put("obj", "exponents.obj", "v 1e-3 -2.5E+2 .5\nv inf 0 0\nv 0 0 1\nf 1 2 3 # comment\n")
    put("obj", "index_zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n")
    put("obj", "index_huge.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4294967297\nf -9223372036854775808 1 2\n")
    put("obj", "short_vertex.obj", "v 0 0\nf 1 1 1\n")
    put("obj", "crlf.obj", "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n")


# ---------------------------------------------------------------- PLY
def ply_header(fmt, nv, nf, extra=""):
    return (f"ply\nformat {fmt} 1.0\ncomment seed\nelement vertex {nv}\nproperty float x\nproperty float y\n"
            f"property float z\n{extra}element face {nf}\nproperty list uchar int vertex_indices\nend_header\n")


def ply_seeds():
    tet_v = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
    tet_f = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
    text = ply_header("ascii", 4, 4) + "".join(f"{x} {y} {z}\n" for x, y, z in tet_v)
    text += "".join(f"3 {a} {b} {c}\n" for a, b, c in tet_f)
    put("ply", "tetra_ascii.ply", text)
    for name, fmt, end in (("le", "binary_little_endian", "<"), ("be", "binary_big_endian", ">")):
        data = ply_header(fmt, 4, 4).encode()
        for v in tet_v:
            data += struct.pack(end + "3f", *v)
        for f in tet_f:
            data += struct.pack(end + "B3i", 3, *f)
        put("ply", f"tetra_{name}.ply", data)
    # Extra vertex properties, a skipped element with a list, a quad, double coordinates.
    data = ("ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
            "property double z\nproperty uchar red\nelement face 1\nproperty list uint ushort vertex_index\n"
            "element edge 1\nproperty list uchar short pair\nproperty int8 weight\nend_header\n").encode()
    for v in [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]:
        data += struct.pack("<3dB", *v, 200)
    data += struct.pack("<I4H", 4, 0, 1, 2, 3)
    data += struct.pack("<B2hb", 2, 0, 1, -1)
    put("ply", "quad_mixed.ply", data)
    put("ply", "huge_count.ply", ply_header("binary_little_endian", 10**12, 1) + "\0" * 16)
    put("ply", "huge_list.ply", ply_header("ascii", 3, 1) + "0 0 0\n1 0 0\n0 1 0\n255 0 1 2\n")
    put("ply", "negative_index.ply", ply_header("ascii", 3, 1) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 -2\n")
    put("ply", "truncated.ply", ply_header("binary_big_endian", 3, 1) + "\0" * 7)


# ---------------------------------------------------------------- glTF
def gltf_doc(buffer_uri, positions, indices, extra_nodes=False):
    pos = b"".join(struct.pack("<3f", *p) for p in positions)
    idx = b"".join(struct.pack("<H", i) for i in indices)
    pad = (4 - len(idx) % 4) % 4
    data = idx + b"\0" * pad + pos
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "translation": [0, 1, 0], "children": [1] if extra_nodes else []}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 1}, "indices": 0, "mode": 4}]}],
        "buffers": [{"byteLength": len(data)}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(idx), "target": 34963},
            {"buffer": 0, "byteOffset": len(idx) + pad, "byteLength": len(pos), "target": 34962},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5123, "count": len(indices), "type": "SCALAR"},
            {"bufferView": 1, "componentType": 5126, "count": len(positions), "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 1]},
        ],
    }
    if extra_nodes:
        doc["nodes"].append({"mesh": 0, "matrix": [-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 2, 0, 0, 1]})
    if buffer_uri == "data":
        doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(data).decode()
    elif buffer_uri is not None:
        doc["buffers"][0]["uri"] = buffer_uri
    return doc, data


def glb(doc, binary):
    js = json.dumps(doc, separators=(",", ":")).encode()
    js += b" " * ((4 - len(js) % 4) % 4)
    binary += b"\0" * ((4 - len(binary) % 4) % 4)
    total = 12 + 8 + len(js) + 8 + len(binary)
    out = struct.pack("<III", 0x46546C67, 2, total) + struct.pack("<II", len(js), 0x4E4F534A) + js
    return out + struct.pack("<II", len(binary), 0x004E4942) + binary


def gltf_seeds():
    tet_v = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
    tet_i = [0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3]
    doc, _ = gltf_doc("data", tet_v, tet_i)
    put("gltf", "tetra_data_uri.gltf", json.dumps(doc, indent=1))
    doc, _ = gltf_doc("data", tet_v, tet_i, extra_nodes=True)
    put("gltf", "tetra_two_nodes.gltf", json.dumps(doc))
    doc, data = gltf_doc(None, tet_v, tet_i)
    put("gltf", "tetra.glb", glb(doc, data))
    doc, data = gltf_doc(None, tet_v, tet_i, extra_nodes=True)
    doc["meshes"][0]["primitives"][0]["mode"] = 5  # triangle strip
    put("gltf", "tetra_strip.glb", glb(doc, data))
    doc, _ = gltf_doc("../../../../etc/passwd", tet_v, tet_i)
    put("gltf", "outside_uri.gltf", json.dumps(doc))
    doc, _ = gltf_doc("data", tet_v, tet_i)
    doc["accessors"][1]["count"] = 4294967295
    put("gltf", "huge_count.gltf", json.dumps(doc))
    doc, _ = gltf_doc("data", tet_v, tet_i)
    doc["nodes"][0]["children"] = [0]
    put("gltf", "cycle.gltf", json.dumps(doc))


# ---------------------------------------------------------------- scene TOML
SCENE_SEEDS = {
    "drop.toml": """frames = 90
[[body]]
name = "ball"
mesh = "sphere"
scale = 0.5
position = [0, 2, 0]
velocity = [0, -5, 0]
collider = "ball"
[[body]]
name = "ground"
mesh = "box"
kind = "static"
scale = [2, 0.25, 2]
[body.dent]
cap = 0.2
sigma = 0.1
resolution = 32
attenuation = "linear"
attenuation_scale = 2.0
""",
    "bend_auto.toml": """name = "bend"
[world]
gravity = [0, 0, 0]
[camera]
eye = [0, 1, 5]
target = [0, 0, 0]
fov_deg = 40
[[body]]
name = "rod"
mesh = "cylinder"
density = 500
[body.bend]
skeleton = "auto"
bones = 3
resolution = 16
influences = 2
falloff = 2.0
joint = { kind = "elastic", stiffness = 100.0, damping = 1.0 }
[body.bend.dynamic]
speed_threshold = 2.0
min_bone_length = 0.3
max_joints = 2
joint = { kind = "ball" }
""",
    "bad_values.toml": """frames = 0
[world]
dt = nan
[[body]]
name = "b"
mesh = "missing.obj"
mass = -1
density = inf
rotation = [1e39, 0, 0]
restitution = 2
""",
    "hardness.toml": """[[body]]
name = "plate"
mesh = "box"
kind = "kinematic"
angular_velocity = [0, 1, 0]
[body.dent]
hardness = 1e6
progressive = true
move_projectile = true
heat_iters = 2
clamp_iters = 3
heat_rate = 0.25
min_cos = 0.5
widen = 1.0
[[body]]
name = "plate"
mesh = "box"
""",
}


def scene_seeds():
    for name in sorted(os.listdir(os.path.join(ROOT, "scenes"))):
        if name.endswith(".toml"):
            shutil.copy(os.path.join(ROOT, "scenes", name), os.path.join(CORPUS, "scene_toml", name))
    for name, text in SCENE_SEEDS.items():
        put("scene_toml", name, text)


# ---------------------------------------------------------------- PNG
def png(width, height, color_type, depth, pixels_row):
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    raw = b"".join(b"\0" + pixels_row(r) for r in range(height))
    ihdr = struct.pack(">IIBBBBB", width, height, depth, color_type, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


def png_seeds():
    # Two leading bytes pick the extent and the glancing angle (see the target).
    def blob(w, r, c):
        return int(255 * max(0.0, 1 - ((r - w / 2) ** 2 + (c - w / 2) ** 2) / (w / 2) ** 2))
    put("dentmap_png", "gray8_16.png", b"\x20\x00" + png(16, 16, 0, 8, lambda r: bytes(blob(16, r, c) for c in range(16))))
    put("dentmap_png", "gray16_8.png", b"\x40\x80" + png(8, 8, 0, 16, lambda r: b"".join(
        struct.pack(">H", blob(8, r, c) * 257) for c in range(8))))
    put("dentmap_png", "rgb8_5.png", b"\x10\xff" + png(5, 5, 2, 8, lambda r: bytes(
        v for c in range(5) for v in (blob(5, r, c), 0, 255 - blob(5, r, c)))))
    put("dentmap_png", "graya8_4.png", b"\x08\x40" + png(4, 4, 4, 8, lambda r: bytes(
        v for c in range(4) for v in (blob(4, r, c), 128))))
    put("dentmap_png", "rgba16_3.png", b"\x08\x40" + png(3, 3, 6, 16, lambda r: b"".join(
        struct.pack(">4H", blob(3, r, c) * 257, 0, 0, 65535) for c in range(3))))
    put("dentmap_png", "gray1_8.png", b"\x01\x01" + png(8, 8, 0, 1, lambda r: bytes([0x5A])))
    put("dentmap_png", "black_4.png", b"\x01\x01" + png(4, 4, 0, 8, lambda r: bytes(4)))
    put("dentmap_png", "not_square.png", b"\x01\x01" + png(4, 2, 0, 8, lambda r: bytes([9] * 4)))
    put("dentmap_png", "huge_header.png", b"\x01\x01" + png(1, 1, 0, 8, lambda r: b"\xff")[:16]
        + struct.pack(">II", 100000, 100000) + png(1, 1, 0, 8, lambda r: b"\xff")[24:])


# ---------------------------------------------------------------- dent API
def dent_seeds():
    rng = random.Random(17)
    for i in range(12):
        put("dent_api", f"random_{i:02}", bytes(rng.randrange(256) for _ in range(rng.choice((32, 64, 128, 256)))))


if __name__ == "__main__":
    shutil.rmtree(CORPUS, ignore_errors=True)
    obj_seeds()
    ply_seeds()
    gltf_seeds()
    os.makedirs(os.path.join(CORPUS, "scene_toml"), exist_ok=True)
    scene_seeds()
    png_seeds()
    dent_seeds()
