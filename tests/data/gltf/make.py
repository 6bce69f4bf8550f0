#!/usr/bin/env python3
"""Writes the small glTF and PLY files of tests/data/gltf and tests/data/ply, each value
chosen by hand (tests/inputs.rs states what each file must give). Run from this folder:
python3 make.py. Deterministic: the same bytes every run."""
import base64, json, math, struct

def pack(fmt, values):
    return b"".join(struct.pack("<" + fmt, *v) if isinstance(v, tuple) else struct.pack("<" + fmt, v) for v in values)

class Doc:
    def __init__(self):
        self.bin = bytearray()
        self.j = {"asset": {"version": "2.0", "generator": "shadelab tests/data/gltf/make.py"},
                  "buffers": [], "bufferViews": [], "accessors": [], "meshes": [], "nodes": [], "scenes": []}
    def view(self, data, stride=None):
        while len(self.bin) % 4: self.bin.append(0)
        v = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if stride: v["byteStride"] = stride
        self.bin += data
        self.j["bufferViews"].append(v)
        return len(self.j["bufferViews"]) - 1
    def accessor(self, view, ctype, count, typ, normalized=False, extra=None):
        a = {"bufferView": view, "componentType": ctype, "count": count, "type": typ}
        if normalized: a["normalized"] = True
        if extra: a.update(extra)
        self.j["accessors"].append(a)
        return len(self.j["accessors"]) - 1
    def vec3(self, values):
        return self.accessor(self.view(pack("3f", values)), 5126, len(values), "VEC3",
                             extra={"min": [min(v[k] for v in values) for k in range(3)],
                                    "max": [max(v[k] for v in values) for k in range(3)]})
    def indices(self, values):
        return self.accessor(self.view(pack("H", values)), 5123, len(values), "SCALAR")
    def write_gltf(self, path, uri=None):
        j = json.loads(json.dumps(self.j))
        data = bytes(self.bin)
        j["buffers"] = [{"byteLength": len(data),
                         "uri": uri if uri else "data:application/octet-stream;base64," + base64.b64encode(data).decode()}]
        open(path, "w").write(json.dumps(j, indent=1) + "\n")
        if uri: open(uri, "wb").write(data)
    def write_glb(self, path):
        j = json.loads(json.dumps(self.j))
        data = bytes(self.bin) + b"\0" * (-len(self.bin) % 4)
        j["buffers"] = [{"byteLength": len(self.bin)}]
        js = json.dumps(j).encode()
        js += b" " * (-len(js) % 4)
        body = struct.pack("<I4s", len(js), b"JSON") + js + struct.pack("<I4s", len(data), b"BIN\0") + data
        open(path, "wb").write(struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body)

TRI = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]

def nodes_doc():
    """Seven nodes over four meshes: see tests/inputs.rs gltf_node_transforms_*."""
    d = Doc()
    p = d.vec3(TRI)
    n = d.vec3([(0, 0, 1)] * 3)
    i = d.indices([0, 1, 2])
    # mesh 0: one indexed triangle with its normals
    d.j["meshes"].append({"name": "tri", "primitives": [{"attributes": {"POSITION": p, "NORMAL": n}, "indices": i}]})
    # mesh 1: the same triangle, non-indexed, no normals (computed)
    d.j["meshes"].append({"name": "bare", "primitives": [{"attributes": {"POSITION": p}}]})
    # mesh 2: a tilted triangle and its face normal, for the non-uniform scale
    tilt = [(0, 0, 0), (1, 0, 0), (0, 1, 1)]
    s = 1 / math.sqrt(2)
    d.j["meshes"].append({"name": "tilted", "primitives": [{"attributes": {
        "POSITION": d.vec3(tilt), "NORMAL": d.vec3([(0, -s, s)] * 3)}}]})
    # mesh 3: a strip of 4 vertices (2 triangles) and a line primitive (left out)
    quad = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0)]
    qp = d.vec3(quad)
    d.j["meshes"].append({"name": "strip", "primitives": [
        {"attributes": {"POSITION": qp, "NORMAL": d.vec3([(0, 0, 1)] * 4)}, "mode": 5},
        {"attributes": {"POSITION": qp}, "mode": 1}]})
    q = math.sin(math.pi / 4)
    d.j["nodes"] = [
        {"name": "rotated_scaled", "mesh": 0, "rotation": [0, 0, q, q], "scale": [2, 2, 2], "translation": [3, 0, 0]},
        {"name": "parent", "translation": [0, 5, 0], "scale": [3, 3, 3], "children": [2]},
        {"name": "child", "mesh": 0, "translation": [1, 0, 0]},
        {"name": "nonuniform", "mesh": 2, "scale": [1, 1, 4], "translation": [0, 0, 6]},
        {"name": "bare", "mesh": 1, "translation": [-3, 0, 0]},
        {"name": "strip", "mesh": 3, "translation": [0, -5, 0]},
        {"name": "mirrored", "mesh": 0, "matrix": [-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -6, 1]},
    ]
    d.j["scenes"] = [{"name": "other", "nodes": [4]}, {"name": "main", "nodes": [0, 1, 3, 4, 5, 6]}]
    d.j["scene"] = 1
    return d

def quantized_doc():
    """KHR_mesh_quantization: SHORT positions (not normalized), BYTE normalized normals."""
    d = Doc()
    pos = d.accessor(d.view(pack("4h", [(0, 0, 0, 0), (100, 0, 0, 0), (0, 100, 0, 0)]), stride=8), 5122, 3, "VEC3")
    nrm = d.accessor(d.view(pack("4b", [(0, 0, 127, 0), (0, 0, 127, 0), (0, -128, 0, 0)]), stride=4), 5120, 3, "VEC3", normalized=True)
    d.j["meshes"] = [{"primitives": [{"attributes": {"POSITION": pos, "NORMAL": nrm}}]}]
    d.j["nodes"] = [{"mesh": 0}]
    d.j["scenes"] = [{"nodes": [0]}]
    d.j["extensionsUsed"] = ["KHR_mesh_quantization", "KHR_materials_unlit"]
    d.j["extensionsRequired"] = ["KHR_mesh_quantization"]
    return d

def morph_doc():
    """A triangle, a sparse morph target moving vertex 2 by (0, 0, 1), weight 0.5; a fan."""
    d = Doc()
    p = d.vec3(TRI)
    si = d.view(pack("H", [2]))
    sv = d.view(pack("3f", [(0, 0, 1)]))
    target = d.accessor(None, 5126, 3, "VEC3", extra={"sparse": {
        "count": 1, "indices": {"bufferView": si, "componentType": 5123}, "values": {"bufferView": sv}}})
    del d.j["accessors"][target]["bufferView"]
    fan = d.vec3([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)])
    d.j["meshes"] = [{"weights": [0.5], "primitives": [{"attributes": {"POSITION": p}, "targets": [{"POSITION": target}]}]},
                     {"primitives": [{"attributes": {"POSITION": fan}, "mode": 6}]}]
    d.j["nodes"] = [{"mesh": 0}, {"mesh": 1, "translation": [0, 0, -2]}]
    d.j["scenes"] = [{"nodes": [0, 1]}]
    return d

nodes_doc().write_gltf("nodes.gltf")
nodes_doc().write_glb("nodes.glb")
nodes_doc().write_gltf("external.gltf", uri="external%20buffer.bin")
import os
os.replace("external%20buffer.bin", "external buffer.bin")
quantized_doc().write_gltf("quantized.gltf")
morph_doc().write_gltf("morph.gltf")

# PLY: the cube of scenes/cube.obj (one vertex per corner, its normal), and the icosphere's
# shared vertices without normals; ASCII, binary little and big endian.
def read_obj(path):
    v, vn, f = [], [], []
    for line in open(path):
        w = line.split()
        if not w: continue
        if w[0] == "v": v.append(tuple(float(x) for x in w[1:4]))
        elif w[0] == "vn": vn.append(tuple(float(x) for x in w[1:4]))
        elif w[0] == "f": f.append([tuple(int(x) - 1 if x else None for x in (c.split("/") + ["", ""])[:3]) for c in w[1:]])
    return v, vn, f

def write_ply(path, fmt, verts, faces, normals, extra_edge=False, quad=False):
    props = "property float x\nproperty float y\nproperty float z\n"
    if normals: props += "property float nx\nproperty float ny\nproperty float nz\n"
    head = f"ply\nformat {fmt} 1.0\ncomment written by shadelab tests/data/gltf/make.py\nelement vertex {len(verts)}\n{props}"
    head += f"element face {len(faces)}\nproperty list uchar int vertex_indices\n"
    if extra_edge: head += "element edge 1\nproperty int vertex1\nproperty int vertex2\n"
    head += "end_header\n"
    if fmt == "ascii":
        body = "".join(" ".join(repr(float(c)) for c in v) + "\n" for v in verts)
        body += "".join(f"{len(f)} " + " ".join(map(str, f)) + "\n" for f in faces)
        if extra_edge: body += "0 1\n"
        open(path, "w").write(head + body)
    else:
        e = "<" if fmt == "binary_little_endian" else ">"
        body = b"".join(struct.pack(e + f"{len(v)}f", *v) for v in verts)
        body += b"".join(struct.pack(e + "B" + f"{len(f)}i", len(f), *f) for f in faces)
        if extra_edge: body += struct.pack(e + "ii", 0, 1)
        open(path, "wb").write(head.encode() + body)

v, vn, f = read_obj("../../../scenes/cube.obj")
verts, faces = [], []
for face in f:
    idx = []
    for (pi, _, ni) in face:
        verts.append(v[pi] + vn[ni]); idx.append(len(verts) - 1)
    faces.append(idx)
for fmt in ["ascii", "binary_little_endian", "binary_big_endian"]:
    write_ply(f"../ply/cube_{fmt}.ply", fmt, verts, faces, True, extra_edge=True)
v, _, f = read_obj("../../../scenes/icosphere.obj")
write_ply("../ply/icosphere_ascii.ply", "ascii", v, [[c[0] for c in face] for face in f], False)
write_ply("../ply/icosphere_binary_big_endian.ply", "binary_big_endian", v, [[c[0] for c in face] for face in f], False)
# A square as one 4-vertex face (a fan of 2 triangles).
write_ply("../ply/square_ascii.ply", "ascii", [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], [[0, 1, 2, 3]], False)
