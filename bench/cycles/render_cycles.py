# SPDX-License-Identifier: MIT
"""Blender Cycles side of the xrsc reference comparison (issue 13, item 5).

Run headless with Debian's blender (3.4):
    blender -b --factory-startup -P bench/cycles/render_cycles.py -- --scene FILE --out DIR \
        [--res 128] [--fov-deg 50] [--spp 256] [--seeds 4] [--bounces 3] [--env R,G,B] \
        [--threads 1] [--materials gltf|lambert] [--one-sided] [--no-volume]
        [--camera file --yfov RAD --res-y H]

It imports the glTF with Blender's own importer, places a camera where xrsc places the left eye
of a camera-less scene with --ipd 0 and an identity pose (sc_scene.c set_viewpoint: the centre
of the world bounds of every mesh vertex in x and y, z = max z + 1.2 * max(half x, half y),
looking down -Z, +Y up), with a symmetric square frustum of --fov-deg (xrsc: a headset profile
with fov -F/2 F/2 F/2 -F/2), and renders --seeds independent images (Cycles seed = 1..seeds)
of --spp samples each, written as DIR/cycles_SEED.pfm (linear Rec.709 radiance, bottom row
first as the PFM format has it).

--bounces is xrsc's count (bounce rays after the camera ray, so at most B scattering vertices
on a path that reaches a light); Cycles' max_bounces counts the bounces after the first
scattering vertex (0 = direct light only), so every Cycles bounce limit is set to B - 1.
Everything that biases Cycles is off: no clamping, no glossy filter, no light threshold,
no denoiser, caustics on; the pixel filter is a 1-pixel box like xrsc's uniform jitter.

--materials lambert replaces every material by a Diffuse BSDF (roughness 0 = Lambert) of the
same base colour (factor x texture) and the same emission, and a transmitting one by glTF's
smooth thin wall (thin_glass; the glass scene of glass_scene.py): the model-matched variant that xrsc
renders for a glTF whose materials are metallic 0, KHR_materials_ior 1 (compare.py writes it).
--one-sided multiplies the emission of every single-sided material (glTF doubleSided false,
which the importer marks with backface culling) by 1 - Backfacing: xrsc's emitters light only
their front side (xs_emitted), Cycles' mesh lights both (compare.py always passes it).
--camera file keeps the file's first camera (xrsc --viewpoint camera:0 --fov scene) with a
vertical field of view of --yfov radians, --res x --res-y pixels.
--no-volume drops the Volume Absorption that the importer makes of KHR_materials_volume (xrsc
ignores that extension: its glass is clear).
"""
import math
import os
import sys

import bpy
import numpy

numpy.bool = bool  # Debian's numpy 1.24 removed the alias that Blender 3.4's importer uses

VIEW_DISTANCE = 1.2  # sc_scene.c SC_DEFAULT_VIEW_DISTANCE


def parse_args(argv):
    a = {"res": 128, "res-y": None, "yfov": None, "camera": "xrsc", "fov-deg": 50.0, "spp": 256, "seeds": 4, "bounces": 3, "env": "1,1,1",
         "threads": 1, "materials": "gltf", "no-volume": False, "one-sided": False}
    i = 0
    while i < len(argv):
        k = argv[i].lstrip("-")
        if k in ("no-volume", "one-sided"):
            a[k] = True
            i += 1
            continue
        a[k] = argv[i + 1]
        i += 2
    return a


def to_gltf(v):
    """Blender (Z up) -> glTF (Y up): (x, y, z)_b = (x, -z, y)_g."""
    return (v[0], v[2], -v[1])


def xrsc_viewpoint():
    lo = [math.inf] * 3
    hi = [-math.inf] * 3
    for ob in bpy.context.scene.objects:
        if ob.type != "MESH":
            continue
        mw = ob.matrix_world
        for vert in ob.data.vertices:
            p = to_gltf(mw @ vert.co)
            for k in range(3):
                lo[k] = min(lo[k], p[k])
                hi[k] = max(hi[k], p[k])
    hx, hy = 0.5 * (hi[0] - lo[0]), 0.5 * (hi[1] - lo[1])
    eye = (0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), hi[2] + VIEW_DISTANCE * max(hx, hy))
    return eye, lo, hi


def place_camera(scene, eye_gltf, fov_deg, res):
    cam_data = bpy.data.cameras.new("xrsc_eye")
    cam_data.type = "PERSP"
    cam_data.sensor_fit = "VERTICAL"
    cam_data.angle_y = math.radians(fov_deg)
    cam_data.clip_start = 1e-4
    cam_data.clip_end = 1e5
    cam = bpy.data.objects.new("xrsc_eye", cam_data)
    scene.collection.objects.link(cam)
    # glTF position -> Blender; looking down glTF -Z (= Blender +Y) with glTF +Y (= Blender +Z) up
    cam.location = (eye_gltf[0], -eye_gltf[2], eye_gltf[1])
    cam.rotation_euler = (math.radians(90.0), 0.0, 0.0)
    scene.camera = cam
    scene.render.resolution_x = res
    scene.render.resolution_y = res
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = scene.render.pixel_aspect_y = 1.0


def file_camera(scene, yfov_rad, res_x, res_y):
    """--camera file: the file's first camera, as xrsc --viewpoint camera:0 --fov scene sees it
    (its yfov over the image height, the image of res_x x res_y)."""
    cam = next(ob for ob in scene.objects if ob.type == "CAMERA")
    cam.data.type = "PERSP"
    cam.data.sensor_fit = "VERTICAL"
    cam.data.angle_y = yfov_rad
    cam.data.clip_start = 1e-4
    cam.data.clip_end = 1e5
    cam.data.shift_x = cam.data.shift_y = 0.0
    scene.camera = cam
    scene.render.resolution_x = res_x
    scene.render.resolution_y = res_y
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = scene.render.pixel_aspect_y = 1.0
    print("xrsc-cycles: the file's camera %s, yfov %g rad, %dx%d" % (cam.name, yfov_rad, res_x,
                                                                      res_y))


def set_cycles(scene, spp, xrsc_bounces, threads):
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = spp
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.use_preview_denoising = False
    n = max(xrsc_bounces - 1, 0)
    c.max_bounces = n
    c.diffuse_bounces = n
    c.glossy_bounces = n
    c.transmission_bounces = n
    c.volume_bounces = n
    c.transparent_max_bounces = 64
    c.min_light_bounces = 0
    c.min_transparent_bounces = 0
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = True
    c.caustics_refractive = True
    c.light_sampling_threshold = 0.0
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    c.use_animated_seed = False
    scene.render.threads_mode = "FIXED"
    scene.render.threads = threads
    scene.render.use_persistent_data = True
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.image_settings.exr_codec = "NONE"


def set_world(scene, rgb):
    world = bpy.data.worlds.new("xrsc_env")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (rgb[0], rgb[1], rgb[2], 1.0)
    bg.inputs["Strength"].default_value = 1.0
    scene.world = world


def thin_glass(nt, node):
    """glTF's smooth thin-walled transmission (KHR_materials_transmission without
    KHR_materials_volume, xs_bsdf.glsl): a mirror reflection of weight F and a straight-through
    transmission of weight 1 - F tinted by the base colour, F the exact dielectric Fresnel of
    the IOR at the view angle, the same on both sides of the wall. In Cycles: Mix(F,
    Transparent(base colour), Glossy(sharp, white)). Cycles' Fresnel node inverts the IOR on
    back faces, so its input is 1/IOR there (the node inverts it back). Only factors are taken
    (no textures, roughness 0, metallic 0, transmission 1): the glass scene's materials."""
    ior = node.inputs["IOR"].default_value
    print("xrsc-cycles: thin glass, IOR %g, tint %s" % (ior, tuple(node.inputs["Base Color"].default_value)))
    geo = nt.nodes.new("ShaderNodeNewGeometry")
    eta = nt.nodes.new("ShaderNodeMath")
    eta.operation = "MULTIPLY_ADD"
    nt.links.new(geo.outputs["Backfacing"], eta.inputs[0])
    eta.inputs[1].default_value = 1.0 / ior - ior
    eta.inputs[2].default_value = ior
    fres = nt.nodes.new("ShaderNodeFresnel")
    nt.links.new(eta.outputs[0], fres.inputs["IOR"])
    clear = nt.nodes.new("ShaderNodeBsdfTransparent")
    clear.inputs["Color"].default_value = node.inputs["Base Color"].default_value
    mirror = nt.nodes.new("ShaderNodeBsdfGlossy")
    mirror.distribution = "SHARP"
    mirror.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    mix = nt.nodes.new("ShaderNodeMixShader")
    nt.links.new(fres.outputs[0], mix.inputs[0])
    nt.links.new(clear.outputs[0], mix.inputs[1])
    nt.links.new(mirror.outputs[0], mix.inputs[2])
    for link in list(node.outputs[0].links):
        nt.links.new(mix.outputs[0], link.to_socket)


def lambert_materials():
    """Principled BSDF -> Diffuse BSDF of the same base colour input, emission kept; a
    transmitting material becomes glTF's smooth thin wall (thin_glass)."""
    for mat in bpy.data.materials:
        if not mat.use_nodes:
            continue
        nt = mat.node_tree
        for node in list(nt.nodes):
            if node.type != "BSDF_PRINCIPLED":
                continue
            if node.inputs["Transmission"].default_value > 0.0:
                thin_glass(nt, node)
                continue
            diff = nt.nodes.new("ShaderNodeBsdfDiffuse")
            diff.inputs["Roughness"].default_value = 0.0
            src = node.inputs["Base Color"]
            diff.inputs["Color"].default_value = src.default_value
            for link in list(src.links):
                nt.links.new(link.from_socket, diff.inputs["Color"])
            emit = nt.nodes.new("ShaderNodeEmission")
            emit.inputs["Color"].default_value = node.inputs["Emission"].default_value
            for link in list(node.inputs["Emission"].links):
                nt.links.new(link.from_socket, emit.inputs["Color"])
            emit.inputs["Strength"].default_value = node.inputs["Emission Strength"].default_value
            for link in list(node.inputs["Emission Strength"].links):
                nt.links.new(link.from_socket, emit.inputs["Strength"])
            add = nt.nodes.new("ShaderNodeAddShader")
            nt.links.new(diff.outputs[0], add.inputs[0])
            nt.links.new(emit.outputs[0], add.inputs[1])
            for link in list(node.outputs[0].links):
                nt.links.new(add.outputs[0], link.to_socket)


def one_sided_emission():
    """Emission Strength x (1 - Backfacing): emitters light only their front side, as xrsc's
    do for materials that are not doubleSided (xs_emitted); Cycles' mesh lights emit both ways."""
    for mat in bpy.data.materials:
        if not mat.use_nodes or not mat.use_backface_culling:  # glTF doubleSided: both ways
            continue
        nt = mat.node_tree
        for node in list(nt.nodes):
            if node.type != "BSDF_PRINCIPLED":
                continue
            sock = node.inputs["Emission Strength"]
            geo = nt.nodes.new("ShaderNodeNewGeometry")
            front = nt.nodes.new("ShaderNodeMath")
            front.operation = "SUBTRACT"
            front.inputs[0].default_value = 1.0
            nt.links.new(geo.outputs["Backfacing"], front.inputs[1])
            mul = nt.nodes.new("ShaderNodeMath")
            mul.operation = "MULTIPLY"
            mul.inputs[1].default_value = sock.default_value
            for link in list(sock.links):
                nt.links.new(link.from_socket, mul.inputs[1])
            nt.links.new(front.outputs[0], mul.inputs[0])
            nt.links.new(mul.outputs[0], sock)


def drop_volumes():
    for mat in bpy.data.materials:
        if not mat.use_nodes:
            continue
        nt = mat.node_tree
        for node in list(nt.nodes):
            if node.type == "OUTPUT_MATERIAL":
                for link in list(node.inputs["Volume"].links):
                    nt.links.remove(link)


def write_pfm(path, w, h, rgba):
    with open(path + ".tmp", "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
        rgb = numpy.asarray(rgba, dtype=numpy.float32).reshape(h, w, 4)[:, :, :3]
        f.write(rgb.astype("<f4").tobytes())
    os.replace(path + ".tmp", path)


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    a = parse_args(argv)
    out = a["out"]
    os.makedirs(out, exist_ok=True)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    # RAW: a directional light's strength is its glTF intensity, which xrsc takes as the
    # irradiance (sc_scene.h sc_sun); the importer's default (SPEC) divides lux by 683 lm/W.
    bpy.ops.import_scene.gltf(filepath=os.path.abspath(a["scene"]),
                              convert_lighting_mode="RAW")
    scene = bpy.context.scene
    for ob in list(scene.objects):
        # xrsc draws the first directional light as a delta light and ignores point and spot
        # lights; the file's cameras are not used (the camera is placed below)
        if ob.type == "LIGHT" and ob.data.type == "SUN":
            ob.data.angle = 0.0
        elif ob.type == "LIGHT" or (ob.type == "CAMERA" and a["camera"] != "file"):
            bpy.data.objects.remove(ob)
    if a["one-sided"]:
        one_sided_emission()
    if a["materials"] == "lambert":
        lambert_materials()
    if a["no-volume"]:
        drop_volumes()
    res = int(a["res"])
    res_y = int(a["res-y"] or res)
    if a["camera"] == "file":
        file_camera(scene, float(a["yfov"]), res, res_y)
    else:
        eye, lo, hi = xrsc_viewpoint()
        print("xrsc-cycles: bounds min %s max %s eye %s (glTF axes)" % (lo, hi, eye))
        place_camera(scene, eye, float(a["fov-deg"]), res)
    set_cycles(scene, int(a["spp"]), int(a["bounces"]), int(a["threads"]))
    set_world(scene, [float(x) for x in a["env"].split(",")])
    for seed in range(1, int(a["seeds"]) + 1):
        scene.cycles.seed = seed
        exr = os.path.join(os.path.abspath(out), "cycles_%d.exr" % seed)
        scene.render.filepath = exr
        bpy.ops.render.render(write_still=True)
        img = bpy.data.images.load(exr)
        px = numpy.empty(res * res_y * 4, dtype=numpy.float32)
        img.pixels.foreach_get(px)
        bpy.data.images.remove(img)
        write_pfm(os.path.join(out, "cycles_%d.pfm" % seed), res, res_y, px)
        os.remove(exr)
        print("xrsc-cycles: wrote seed %d" % seed, flush=True)


main()
