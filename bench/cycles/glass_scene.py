# SPDX-License-Identifier: MIT
"""@file glass_scene.py
@brief A small glTF of smooth thin-walled glass for the Cycles check of transmission (issue 18).

    python3 bench/cycles/glass_scene.py OUT.gltf

TransmissionTest's spheres are thin-walled (KHR_materials_transmission without
KHR_materials_volume): glTF defines them as an infinitely thin surface that lets light straight
through, tinted by the base colour and weighted 1 - F, and reflects F. Blender 3.4's importer
turns the same material into a Principled BSDF that refracts (solid glass), so the file itself
cannot be compared model for model. This scene holds the same kind of material in a form both
renderers draw alike (compare.py case `glass`; render_cycles.py --materials lambert builds the
thin wall in Cycles):

- a Lambertian backdrop (metallic 0, KHR_materials_ior 1), 4 x 3 m at z = -1, albedo 0.6;
- a single-sided emissive square (emission 4, facing +z) just in front of it, behind sphere A;
- sphere A: thin glass, radius 0.45 at (-0.7, 0, 0), tint (0.95, 0.85, 0.3), doubleSided;
- sphere B: thin glass, radius 0.45 at (0.7, 0, 0), tint (0.3, 0.7, 0.95), doubleSided, in
  front of the lit backdrop only;
- a thin pane 0.8 x 0.8 m at z = 0.2 centred at (0, -0.9), untinted, over the floor-level
  part of the backdrop.

Smooth normals on the spheres (analytic), all IOR 1.5. No camera: both renderers look from
xrsc's default viewpoint. Written with an embedded base64 buffer.
"""
import base64
import json
import math
import struct
import sys

STACKS, SLICES = 24, 48


def quad(x0, y0, x1, y1, z):
    p = [(x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)]
    n = [(0.0, 0.0, 1.0)] * 4
    return p, n, [0, 1, 2, 0, 2, 3]


def sphere(cx, cy, cz, r):
    p, n, idx = [], [], []
    for i in range(STACKS + 1):
        th = math.pi * i / STACKS
        for j in range(SLICES + 1):
            ph = 2.0 * math.pi * j / SLICES
            d = (math.sin(th) * math.cos(ph), math.cos(th), -math.sin(th) * math.sin(ph))
            n.append(d)
            p.append((cx + r * d[0], cy + r * d[1], cz + r * d[2]))
    w = SLICES + 1
    for i in range(STACKS):
        for j in range(SLICES):
            a, b, c, d = i * w + j, (i + 1) * w + j, (i + 1) * w + j + 1, i * w + j + 1
            idx += [a, b, c, a, c, d]  # counter-clockwise seen from outside
    return p, n, idx


def glass(tint):
    return {"pbrMetallicRoughness": {"baseColorFactor": list(tint) + [1.0], "metallicFactor": 0.0,
                                     "roughnessFactor": 0.0},
            "doubleSided": True,
            "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                           "KHR_materials_ior": {"ior": 1.5}}}


def main():
    out = sys.argv[1]
    materials = [
        {"pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.6, 0.6, 1.0], "metallicFactor": 0.0,
                                  "roughnessFactor": 1.0},
         "extensions": {"KHR_materials_ior": {"ior": 1.0}}},
        {"pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0,
                                  "roughnessFactor": 1.0},
         "emissiveFactor": [1.0, 1.0, 1.0],
         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0},
                        "KHR_materials_ior": {"ior": 1.0}}},
        glass((0.95, 0.85, 0.3)),
        glass((0.3, 0.7, 0.95)),
        glass((1.0, 1.0, 1.0)),
    ]
    parts = [
        (quad(-2.0, -1.5, 2.0, 1.5, -1.0), 0),
        (quad(-0.95, -0.25, -0.45, 0.25, -0.98), 1),
        (sphere(-0.7, 0.0, 0.0, 0.45), 2),
        (sphere(0.7, 0.0, 0.0, 0.45), 3),
        (quad(-0.4, -1.3, 0.4, -0.5, 0.2), 4),
    ]
    blob = bytearray()
    views, accessors, meshes, nodes = [], [], [], []
    for (p, n, idx), mat in parts:
        base = len(accessors)
        for data, typ in ((p, "VEC3"), (n, "VEC3")):
            off = len(blob)
            for v in data:
                blob += struct.pack("<3f", *v)
            views.append({"buffer": 0, "byteOffset": off, "byteLength": len(blob) - off})
            acc = {"bufferView": len(views) - 1, "componentType": 5126, "count": len(data),
                   "type": typ}
            if data is p:
                acc["min"] = [min(v[k] for v in p) for k in range(3)]
                acc["max"] = [max(v[k] for v in p) for k in range(3)]
            accessors.append(acc)
        off = len(blob)
        for i in idx:
            blob += struct.pack("<I", i)
        views.append({"buffer": 0, "byteOffset": off, "byteLength": len(blob) - off})
        accessors.append({"bufferView": len(views) - 1, "componentType": 5125, "count": len(idx),
                          "type": "SCALAR"})
        meshes.append({"primitives": [{"attributes": {"POSITION": base, "NORMAL": base + 1},
                                       "indices": base + 2, "material": mat}]})
        nodes.append({"mesh": len(meshes) - 1})
    doc = {
        "asset": {"version": "2.0", "generator": "xrsc bench/cycles/glass_scene.py"},
        "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_ior",
                           "KHR_materials_emissive_strength"],
        "scene": 0, "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes, "meshes": meshes, "materials": materials,
        "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64,"
                     + base64.b64encode(bytes(blob)).decode()}],
        "bufferViews": views, "accessors": accessors,
    }
    with open(out, "w") as f:
        json.dump(doc, f)


if __name__ == "__main__":
    main()
