#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""@file make_character.py
@brief Writes scenes/character.gltf (stability case `character`, issue 21): the Khronos
CesiumMan walking along x in front of a textured wall. The figure is read in place: the
scene's buffer 0 is ../shared/scenes/khronos/CesiumMan/glTF-Binary/CesiumMan.glb, the whole
file, and CesiumMan's buffer views point past the GLB header into its BIN chunk; nothing of
its data is copied. Its JSON (nodes, skin, accessors, animation) is restated here with the
offsets moved. Buffer 1 (embedded) holds the wall, its checker texture (the PNG of
scenes/disocclusion.gltf) and the walk across: a `walker` node above CesiumMan's root, moved
from x = -1 to +1 m in the file's one clip (2 s, looping), so the figure is an animated
instance (the stability suite's `object` region) with or without skinning.

usage: scenes/tools/make_character.py [REPO_ROOT]   (run from anywhere; writes in place)
"""
import base64
import json
import os
import struct
import sys

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                       os.path.join(os.path.dirname(__file__), "..", ".."))
GLB_URI = "../../shared/scenes/khronos/CesiumMan/glTF-Binary/CesiumMan.glb"  # from scenes/
GLB = os.path.normpath(os.path.join(ROOT, "scenes", GLB_URI))
WALL_Z = -1.2           # the wall's plane (m); the figure walks at z = 0
WALL_X, WALL_Y = (-6.0, 6.0), (-3.0, 5.0)
WALL_UV_REPEAT = 6.0    # checker repeats across the wall
WALK_X = (-0.7, 1.3)    # metres, over the clip's 2 s: 1 m/s; the suite's 60 frames: -0.7 to 0
TURN_Y = [0.0, 0.70710678, 0.0, 0.70710678]  # +90 deg about +Y: CesiumMan faces +x


def read_glb(path):
    b = open(path, "rb").read()
    magic, _, total = struct.unpack("<4sII", b[:12])
    assert magic == b"glTF" and total == len(b)
    jlen, jtype = struct.unpack("<II", b[12:20])
    assert jtype == 0x4E4F534A
    doc = json.loads(b[20:20 + jlen])
    bin_offset = 20 + jlen + 8  # the BIN chunk's header follows the JSON chunk
    return doc, bin_offset, len(b)


def checker_png():
    d = json.load(open(os.path.join(ROOT, "scenes", "disocclusion.gltf")))
    data = base64.b64decode(d["buffers"][0]["uri"].split(",", 1)[1])
    v = d["bufferViews"][d["images"][0]["bufferView"]]
    return data[v.get("byteOffset", 0):v.get("byteOffset", 0) + v["byteLength"]]


def f32(*xs):
    return struct.pack("<%df" % len(xs), *xs)


def main():
    doc, bin_offset, glb_len = read_glb(GLB)
    for v in doc["bufferViews"]:
        v["byteOffset"] = v.get("byteOffset", 0) + bin_offset
    doc["buffers"] = [{"uri": GLB_URI, "byteLength": glb_len}]

    # Buffer 1: the wall (4 vertices), its indices, the PNG, the walker's keys.
    (x0, x1), (y0, y1), z, r = WALL_X, WALL_Y, WALL_Z, WALL_UV_REPEAT
    aspect = (y1 - y0) / (x1 - x0)
    parts = [f32(x0, y0, z, x1, y0, z, x1, y1, z, x0, y1, z), f32(*[0, 0, 1] * 4),
             f32(0, r * aspect, r, r * aspect, r, 0, 0, 0), struct.pack("<6H", 0, 1, 2, 0, 2, 3),
             checker_png()]
    duration = max(max(doc["accessors"][s["input"]]["max"]) for a in doc["animations"]
                   for s in a["samplers"])
    parts += [f32(0.0, duration), f32(WALK_X[0], 0, 0, WALK_X[1], 0, 0)]
    blob, offs = b"", []
    for p in parts:
        blob += b"\0" * (-len(blob) % 4)
        offs.append(len(blob))
        blob += p
    doc["buffers"].append({"byteLength": len(blob), "uri": "data:application/octet-stream;base64," +
                           base64.b64encode(blob).decode()})
    views = []
    for o, p in zip(offs, parts):
        views.append(len(doc["bufferViews"]))
        doc["bufferViews"].append({"buffer": 1, "byteOffset": o, "byteLength": len(p)})

    def acc(view, count, typ, comp=5126, **kw):
        doc["accessors"].append(dict(bufferView=views[view], componentType=comp, count=count,
                                     type=typ, **kw))
        return len(doc["accessors"]) - 1

    pos = acc(0, 4, "VEC3", min=[x0, y0, z], max=[x1, y1, z])
    nrm, uv, idx = acc(1, 4, "VEC3"), acc(2, 4, "VEC2"), acc(3, 6, "SCALAR", comp=5123)
    t_in = acc(5, 2, "SCALAR", min=[0.0], max=[duration])
    t_out = acc(6, 2, "VEC3")
    doc.setdefault("samplers", []).append({})
    doc.setdefault("images", []).append({"bufferView": views[4], "mimeType": "image/png"})
    doc.setdefault("textures", []).append({"sampler": len(doc["samplers"]) - 1,
                                           "source": len(doc["images"]) - 1})
    doc["materials"].append({"name": "checker-wall", "pbrMetallicRoughness": {
        "baseColorTexture": {"index": len(doc["textures"]) - 1}, "metallicFactor": 0,
        "roughnessFactor": 1}})
    doc["meshes"].append({"name": "wall", "primitives": [{"attributes": {
        "POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": uv}, "indices": idx,
        "material": len(doc["materials"]) - 1}]})

    roots = doc["scenes"][doc.get("scene", 0)]["nodes"]
    n = len(doc["nodes"])
    doc["nodes"] += [
        {"name": "walker", "children": roots, "translation": [WALK_X[0], 0, 0],
         "rotation": TURN_Y},
        {"name": "wall", "mesh": len(doc["meshes"]) - 1},
        {"name": "sun", "rotation": [-0.223714918, 0.134228945, 0, 0.965367377],
         "extensions": {"KHR_lights_punctual": {"light": 0}}},
        {"name": "camera", "camera": 0, "translation": [0, 0.8, 1.5]},
    ]
    doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.05}}]
    doc["extensionsUsed"] = sorted(set(doc.get("extensionsUsed", []) + ["KHR_lights_punctual"]))
    doc["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"name": "sun", "type": "directional", "color": [1, 0.95, 0.85], "intensity": 3}]}}
    # The walk across is a channel of the file's first (only) clip, so the default clip has it.
    a = doc["animations"][0]
    a["samplers"].append({"input": t_in, "output": t_out, "interpolation": "LINEAR"})
    a["channels"].append({"sampler": len(a["samplers"]) - 1,
                          "target": {"node": n, "path": "translation"}})
    a["name"] = "walk"
    doc["scene"] = 0
    doc["scenes"] = [{"name": "character", "nodes": [n, n + 1, n + 2, n + 3],
                      "extras": {"xrsc_environment": [0.2, 0.2, 0.24]}}]
    doc["asset"] = {"version": "2.0", "generator": "xrsc scenes/tools/make_character.py",
                    "copyright": "CesiumMan: CC-BY 4.0, Cesium (read in place from ../shared)"}
    with open(os.path.join(ROOT, "scenes", "character.gltf"), "w") as f:
        json.dump(doc, f, separators=(",", ":"))
        f.write("\n")


if __name__ == "__main__":
    main()
