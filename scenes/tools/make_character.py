#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""@file make_character.py
@brief Writes the skinned figure of the stability case `character` (issue 21): a humanoid of
vertical capsules (torso, head, two legs with knees, two arms with elbows) skinned to 10
joints, weights blended across each joint, walking along +x in front of a checkered wall
under a sun. Everything is made here (the wall's texture is the PNG of
scenes/disocclusion.gltf, itself made by make_scenes.c); the binary data is one base64 data
URI, so the output is one .gltf file.

Clips (2 s each, LINEAR, 8 keys a second): `walk` (the first, so the default) moves the
figure's root from x = -0.7 to +1.3 m (1 m/s, looping), the legs swing +-20 deg with the knee
bending in the swing, the arms swing against them; `wave` stands at x = 0 and waves the right
forearm above the raised upper arm, the legs still.

--triangles N sets the tessellation: the segments around each capsule are chosen so that the
figure has about N triangles (the suite's scenes/character.gltf: 5000; the ~60k figure of
issue 21 item 4 is written at build time into the build folder, see scenes/CMakeLists.txt).

usage: make_character.py [--triangles N] [--out FILE]  (default scenes/character.gltf, 5000)
"""
import argparse
import base64
import json
import math
import os
import struct

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
WALL_Z = -1.2           # the wall's plane (m); the figure walks at z = 0
WALL_X, WALL_Y = (-6.0, 6.0), (-3.0, 5.0)
WALL_UV_REPEAT = 3.0    # checker repeats across the wall: 25 cm cells
WALK_X = (-0.7, 1.3)    # metres, over the clip's 2 s: 1 m/s; the suite's 60 frames: -0.7 to 0
CLIP_S, KEYS_PER_S = 2.0, 8
STEP_S = 1.0            # one stride of each leg per second
BLEND_M = 0.06          # half-width of the zone where a vertex blends two joints

# Joints: name, parent, bind position in the figure's frame (it faces +x, +z is its right).
JOINTS = [
    ("hips", None, (0, 0.92, 0)),
    ("spine", "hips", (0, 1.10, 0)),
    ("thigh_L", "hips", (0, 0.90, -0.10)),
    ("shin_L", "thigh_L", (0, 0.50, -0.10)),
    ("thigh_R", "hips", (0, 0.90, 0.10)),
    ("shin_R", "thigh_R", (0, 0.50, 0.10)),
    ("upper_arm_L", "spine", (0, 1.42, -0.22)),
    ("forearm_L", "upper_arm_L", (0, 1.12, -0.22)),
    ("upper_arm_R", "spine", (0, 1.42, 0.22)),
    ("forearm_R", "upper_arm_R", (0, 1.12, 0.22)),
]
JI = {name: i for i, (name, _, _) in enumerate(JOINTS)}

# Parts: vertical capsules (x, z, bottom y, top y, radius) skinned along y: `bands` lists, top
# down, the joint above each boundary y, the boundary, ..., the joint below the last one.
PARTS = [
    ((0, 0, 0.84, 1.50, 0.15), ["hips", 1.10, "spine"]),                  # torso
    ((0, 0, 1.54, 1.76, 0.11), ["spine"]),                                # head
    ((0, -0.10, 0.03, 0.96, 0.065), ["hips", 0.90, "thigh_L", 0.50, "shin_L"]),
    ((0, 0.10, 0.03, 0.96, 0.065), ["hips", 0.90, "thigh_R", 0.50, "shin_R"]),
    ((0, -0.22, 0.82, 1.46, 0.045), ["spine", 1.40, "upper_arm_L", 1.12, "forearm_L"]),
    ((0, 0.22, 0.82, 1.46, 0.045), ["spine", 1.40, "upper_arm_R", 1.12, "forearm_R"]),
]


def smooth(t):
    t = min(1.0, max(0.0, t))
    return t * t * (3 - 2 * t)


def weights_at(bands, y):
    """(joint, weight) pairs of a vertex at height y: one joint, or two across a boundary."""
    for k in range(1, len(bands), 2):
        upper, b, lower = bands[k - 1], bands[k], bands[k + 1]
        if y > b + BLEND_M:
            return [(JI[upper], 1.0)]
        if y >= b - BLEND_M:
            t = smooth((b + BLEND_M - y) / (2 * BLEND_M))  # 0 at the top of the zone
            return [(JI[upper], 1.0 - t), (JI[lower], t)]
    return [(JI[bands[-1]], 1.0)]


def capsule_profile(y0, y1, r, seg):
    """(radius, y, normal radial, normal y) rings from the bottom to the top, poles excluded:
    hemispherical caps of seg/4 bands and a cylinder with rings about as far apart as the
    segments around."""
    cap = max(2, seg // 4)
    cyl = max(1, round((y1 - y0 - 2 * r) / (2 * math.pi * r / seg)))
    rings = []
    for i in range(1, cap + 1):  # bottom cap, pole excluded
        a = -math.pi / 2 + (math.pi / 2) * i / cap
        rings.append((r * math.cos(a), y0 + r + r * math.sin(a), math.cos(a), math.sin(a)))
    for i in range(1, cyl):
        rings.append((r, y0 + r + (y1 - y0 - 2 * r) * i / cyl, 1.0, 0.0))
    for i in range(0, cap):  # top cap
        a = (math.pi / 2) * i / cap
        rings.append((r * math.cos(a), y1 - r + r * math.sin(a), math.cos(a), math.sin(a)))
    return rings


def build_figure(seg):
    """Positions, normals, joints, weights and indices of the figure at seg segments around."""
    pos, nrm, jnt, wgt, idx = [], [], [], [], []

    def vertex(p, n, bands):
        pos.append(p)
        nrm.append(n)
        jw = weights_at(bands, p[1])
        jw += [(0, 0.0)] * (4 - len(jw))
        jnt.append([j for j, _ in jw])
        wgt.append([w for _, w in jw])
        return len(pos) - 1

    for (cx, cz, y0, y1, r), bands in PARTS:
        rings = capsule_profile(y0, y1, r, seg)
        bottom = vertex((cx, y0, cz), (0, -1, 0), bands)
        first = len(pos)
        for rho, y, nr, ny in rings:
            for s in range(seg):
                a = 2 * math.pi * s / seg
                c, sn = math.cos(a), math.sin(a)
                vertex((cx + rho * c, y, cz + rho * sn), (nr * c, ny, nr * sn), bands)
        top = vertex((cx, y1, cz), (0, 1, 0), bands)
        ring = lambda i, s: first + i * seg + s % seg  # noqa: E731
        for s in range(seg):  # counter-clockwise seen from outside
            idx += [bottom, ring(0, s), ring(0, s + 1)]
            last = len(rings) - 1
            idx += [top, ring(last, s + 1), ring(last, s)]
            for i in range(last):
                a, b = ring(i, s), ring(i, s + 1)
                c, d = ring(i + 1, s), ring(i + 1, s + 1)
                idx += [a, c, b, b, c, d]
    return pos, nrm, jnt, wgt, idx


def segments_for(triangles):
    """The even number of segments around whose figure has the nearest triangle count."""
    best = None
    for seg in range(8, 400, 2):
        n = sum(2 * seg * (len(capsule_profile(y0, y1, r, seg)))
                for (_, _, y0, y1, r), _ in PARTS)
        if best is None or abs(n - triangles) < abs(best[1] - triangles):
            best = (seg, n)
    return best[0]


def quat(axis, deg):
    h = math.radians(deg) / 2
    s = math.sin(h)
    return [axis[0] * s, axis[1] * s, axis[2] * s, math.cos(h)]


Z, X = (0, 0, 1), (1, 0, 0)


def walk_keys(t):
    """Channel values of `walk` at t: (node, path) -> value."""
    ph = 2 * math.pi * t / STEP_S
    k = {("figure", "translation"): [WALK_X[0] + (WALK_X[1] - WALK_X[0]) * t / CLIP_S, 0, 0]}
    for side, sign in (("L", 1), ("R", -1)):
        swing = sign * math.sin(ph)  # +: the leg forward (+x)
        lift = max(0.0, sign * math.cos(ph))  # the knee bends while the leg swings forward
        k[("thigh_" + side, "rotation")] = quat(Z, 20 * swing)
        k[("shin_" + side, "rotation")] = quat(Z, -35 * lift)
        k[("upper_arm_" + side, "rotation")] = quat(Z, -15 * swing)
        k[("forearm_" + side, "rotation")] = quat(Z, 15)
    return k


def wave_keys(t):
    ph = 2 * math.pi * t / 1.0
    return {("figure", "translation"): [0, 0, 0],
            ("spine", "rotation"): quat(Z, 3 * math.sin(ph / 2)),
            ("upper_arm_R", "rotation"): quat(Z, 150),
            ("forearm_R", "rotation"): quat(Z, 25 * math.sin(ph))}


class Doc:
    def __init__(self):
        self.blob = b""
        self.g = {k: [] for k in ("bufferViews", "accessors", "meshes", "materials", "nodes",
                                  "images", "textures", "samplers", "skins", "animations")}

    def view(self, data, target=None):
        self.blob += b"\0" * (-len(self.blob) % 4)
        v = {"buffer": 0, "byteOffset": len(self.blob), "byteLength": len(data)}
        if target:
            v["target"] = target
        self.blob += data
        self.g["bufferViews"].append(v)
        return len(self.g["bufferViews"]) - 1

    def acc(self, rows, typ, comp=5126, target=None, minmax=False):
        n = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}[typ]
        fmt = {5126: "f", 5123: "H", 5125: "I", 5121: "B"}[comp]
        flat = [x for r in rows for x in (r if isinstance(r, (list, tuple)) else [r])]
        a = {"bufferView": self.view(struct.pack("<%d%s" % (len(flat), fmt), *flat), target),
             "componentType": comp, "count": len(rows), "type": typ}
        if minmax:
            cols = [flat[c::n] for c in range(n)]
            a["min"], a["max"] = [min(c) for c in cols], [max(c) for c in cols]
        self.g["accessors"].append(a)
        return len(self.g["accessors"]) - 1

    def add(self, kind, obj):
        self.g[kind].append(obj)
        return len(self.g[kind]) - 1


def checker_png():
    d = json.load(open(os.path.join(ROOT, "scenes", "disocclusion.gltf")))
    data = base64.b64decode(d["buffers"][0]["uri"].split(",", 1)[1])
    v = d["bufferViews"][d["images"][0]["bufferView"]]
    return data[v.get("byteOffset", 0):v.get("byteOffset", 0) + v["byteLength"]]


def add_figure(d, seg):
    pos, nrm, jnt, wgt, idx = build_figure(seg)
    big = len(pos) > 65535
    prim = {"attributes": {"POSITION": d.acc(pos, "VEC3", target=34962, minmax=True),
                           "NORMAL": d.acc(nrm, "VEC3", target=34962),
                           "JOINTS_0": d.acc(jnt, "VEC4", 5121, 34962),
                           "WEIGHTS_0": d.acc(wgt, "VEC4", target=34962)},
            "indices": d.acc(idx, "SCALAR", 5125 if big else 5123, 34963),
            "material": d.add("materials", {"name": "figure", "pbrMetallicRoughness": {
                "baseColorFactor": [0.8, 0.45, 0.2, 1], "metallicFactor": 0,
                "roughnessFactor": 0.7}})}
    mesh = d.add("meshes", {"name": "figure", "primitives": [prim]})
    figure = d.add("nodes", {"name": "figure", "translation": [WALK_X[0], 0, 0]})
    nodes = {}
    for name, parent, p in JOINTS:
        pp = JOINTS[JI[parent]][2] if parent else (0, 0, 0)
        local = [round(p[c] - pp[c], 6) for c in range(3)]
        nodes[name] = d.add("nodes", {"name": name, "translation": local})
        parent_node = d.g["nodes"][nodes[parent] if parent else figure]
        parent_node.setdefault("children", []).append(nodes[name])
    nodes["figure"] = figure
    ibm = [[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -p[0], -p[1], -p[2], 1] for _, _, p in JOINTS]
    skin = d.add("skins", {"name": "figure", "joints": [nodes[n] for n, _, _ in JOINTS],
                           "skeleton": nodes["hips"],
                           "inverseBindMatrices": d.acc(ibm, "MAT4")})
    body = d.add("nodes", {"name": "body", "mesh": mesh, "skin": skin})
    times = [i / KEYS_PER_S for i in range(int(CLIP_S * KEYS_PER_S) + 1)]
    t_in = d.acc(times, "SCALAR", minmax=True)
    for name, keys in (("walk", walk_keys), ("wave", wave_keys)):
        samples = [keys(t) for t in times]
        anim = {"name": name, "samplers": [], "channels": []}
        for (node, path) in samples[0]:
            out = d.acc([s[(node, path)] for s in samples], "VEC4" if path == "rotation"
                        else "VEC3")
            anim["channels"].append({"sampler": len(anim["samplers"]),
                                     "target": {"node": nodes[node], "path": path}})
            anim["samplers"].append({"input": t_in, "output": out, "interpolation": "LINEAR"})
        d.add("animations", anim)
    return figure, body, len(idx) // 3


def add_wall(d):
    (x0, x1), (y0, y1), z, r = WALL_X, WALL_Y, WALL_Z, WALL_UV_REPEAT
    aspect = (y1 - y0) / (x1 - x0)
    prim = {"attributes": {
        "POSITION": d.acc([(x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)], "VEC3",
                          target=34962, minmax=True),
        "NORMAL": d.acc([(0, 0, 1)] * 4, "VEC3", target=34962),
        "TEXCOORD_0": d.acc([(0, r * aspect), (r, r * aspect), (r, 0), (0, 0)], "VEC2",
                            target=34962)},
        "indices": d.acc([0, 1, 2, 0, 2, 3], "SCALAR", 5123, 34963)}
    image = d.add("images", {"bufferView": d.view(checker_png()), "mimeType": "image/png"})
    tex = d.add("textures", {"sampler": d.add("samplers", {}), "source": image})
    prim["material"] = d.add("materials", {"name": "checker-wall", "pbrMetallicRoughness": {
        "baseColorTexture": {"index": tex}, "metallicFactor": 0, "roughnessFactor": 1}})
    return d.add("nodes", {"name": "wall", "mesh": d.add("meshes", {"name": "wall",
                                                                    "primitives": [prim]})})


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("--triangles", type=int, default=5000)
    ap.add_argument("--out", default=os.path.join(ROOT, "scenes", "character.gltf"))
    a = ap.parse_args()
    d = Doc()
    figure, body, tris = add_figure(d, segments_for(a.triangles))
    roots = [figure, body, add_wall(d),
             d.add("nodes", {"name": "sun", "rotation": [-0.223714918, 0.134228945, 0,
                                                         0.965367377],
                             "extensions": {"KHR_lights_punctual": {"light": 0}}}),
             d.add("nodes", {"name": "camera", "camera": 0, "translation": [0, 0.9, 1.5]})]
    doc = {"asset": {"version": "2.0", "generator": "xrsc scenes/tools/make_character.py",
                     "copyright": "xrsc project, MIT"},
           "extensionsUsed": ["KHR_lights_punctual"],
           "extensions": {"KHR_lights_punctual": {"lights": [
               {"name": "sun", "type": "directional", "color": [1, 0.95, 0.85],
                "intensity": 3}]}},
           "scene": 0,
           "scenes": [{"name": "character", "nodes": roots,
                       "extras": {"xrsc_environment": [0.2, 0.2, 0.24]}}],
           "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.05}}]}
    doc.update({k: v for k, v in d.g.items() if v})
    doc["buffers"] = [{"byteLength": len(d.blob), "uri": "data:application/octet-stream;base64,"
                       + base64.b64encode(d.blob).decode()}]
    with open(a.out, "w") as f:
        json.dump(doc, f, separators=(",", ":"))
        f.write("\n")
    print("%s: %d triangles" % (a.out, tris + 2))


if __name__ == "__main__":
    main()
