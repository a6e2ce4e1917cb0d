#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# @file make-big-gltf.py
# @brief Writes a tessellated wavy sheet of about N triangles as .gltf + .bin (positions,
#        normals, UVs, 32-bit indices) for load-time and memory measurements; never commit
#        its output (a 1M-triangle file is ~30 MB).
#        Usage: make-big-gltf.py OUT.gltf|OUT.glb [N] [flat]  (flat: no NORMAL, as scans often are)
import array, json, math, os, struct, sys

out = sys.argv[1]
tris = int(sys.argv[2]) if len(sys.argv) > 2 else 1000000
flat = len(sys.argv) > 3 and sys.argv[3] == 'flat'
glb = out.endswith('.glb')
n = int(math.sqrt(tris / 2)) + 1  # vertices per side: 2 (n-1)^2 triangles
size_m = 2.0
pos, nrm, uv = array.array('f'), array.array('f'), array.array('f')
for j in range(n):
    for i in range(n):
        u, v = i / (n - 1), j / (n - 1)
        x, z = (u - 0.5) * size_m, (v - 0.5) * size_m
        y = 0.05 * math.sin(12 * x) * math.cos(9 * z)
        dx = 0.05 * 12 * math.cos(12 * x) * math.cos(9 * z)
        dz = -0.05 * 9 * math.sin(12 * x) * math.sin(9 * z)
        l = math.sqrt(dx * dx + 1 + dz * dz)
        pos.extend((x, y, z))
        nrm.extend((-dx / l, 1 / l, -dz / l))
        uv.extend((u, v))
idx = array.array('I')
for j in range(n - 1):
    for i in range(n - 1):
        a = j * n + i
        idx.extend((a, a + n, a + 1, a + 1, a + n, a + n + 1))
parts = [pos.tobytes(), nrm.tobytes(), uv.tobytes(), idx.tobytes()]
offs = [0]
for p in parts:
    offs.append(offs[-1] + len(p))
vc = n * n
attrs = {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}
if flat:
    del attrs["NORMAL"]
binname = os.path.splitext(os.path.basename(out))[0] + '.bin'
doc = {
    "asset": {"version": "2.0", "generator": "xrsc scripts/make-big-gltf.py"},
    "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": attrs, "indices": 3, "material": 0}]}],
    "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1],
                                            "metallicFactor": 0, "roughnessFactor": 0.6}}],
    "buffers": [{"byteLength": offs[-1]} if glb else {"byteLength": offs[-1], "uri": binname}],
    "bufferViews": [{"buffer": 0, "byteOffset": offs[k], "byteLength": len(parts[k])}
                    for k in range(4)],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": vc, "type": "VEC3",
         "min": [-size_m / 2, -0.05, -size_m / 2], "max": [size_m / 2, 0.05, size_m / 2]},
        {"bufferView": 1, "componentType": 5126, "count": vc, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5126, "count": vc, "type": "VEC2"},
        {"bufferView": 3, "componentType": 5125, "count": len(idx), "type": "SCALAR"}],
}
blob = b''.join(parts)
if glb:
    js = json.dumps(doc).encode()
    js += b' ' * (-len(js) % 4)
    blob += b'\0' * (-len(blob) % 4)
    with open(out, 'wb') as f:
        f.write(struct.pack('<III', 0x46546C67, 2, 12 + 8 + len(js) + 8 + len(blob)))
        f.write(struct.pack('<II', len(js), 0x4E4F534A) + js)
        f.write(struct.pack('<II', len(blob), 0x004E4942) + blob)
else:
    with open(os.path.join(os.path.dirname(out) or '.', binname), 'wb') as f:
        f.write(blob)
    with open(out, 'w') as f:
        json.dump(doc, f)
print(f"{out}: {len(idx) // 3} triangles, {vc} vertices{' (flat)' if flat else ''}")
