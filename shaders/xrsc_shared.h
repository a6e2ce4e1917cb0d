// SPDX-License-Identifier: MIT
/**
 * @file xrsc_shared.h
 * @brief GPU data layouts, binding numbers and limits shared by C and GLSL (std430/std140).
 *
 * Included by C (struct definitions, checked with _Static_assert) and by GLSL (compiled with
 * -DXRSC_GLSL). Change a layout here only; never retype a binding number elsewhere.
 */
#ifndef XRSC_SHARED_H
#define XRSC_SHARED_H

#ifdef XRSC_GLSL
#define XS_STRUCT(name) struct name
#define XS_END(name)
#define xs_uint uint
#define xs_float float
#define xs_vec4 vec4
#define xs_uvec4 uvec4
#define xs_mat4 mat4
#else
#include <stdint.h>
#define XS_STRUCT(name) typedef struct name
#define XS_END(name) name
typedef uint32_t xs_uint;
typedef float xs_float;
typedef struct xs_vec4 { float x, y, z, w; } xs_vec4;
typedef struct xs_uvec4 { uint32_t x, y, z, w; } xs_uvec4;
typedef struct xs_mat4 { float m[16]; } xs_mat4; /* column-major */
#endif

/* ---- descriptor set 0: scene and frame (bindings shared by every ray-tracing method) ---- */
#define XS_BIND_TLAS 0       /* accelerationStructureEXT */
#define XS_BIND_FRAME 1      /* uniform xs_frame */
#define XS_BIND_VERTICES 2   /* readonly buffer xs_vertex[] */
#define XS_BIND_INDICES 3    /* readonly buffer uint[] (3 per triangle, absolute vertex index) */
#define XS_BIND_INSTANCES 4  /* readonly buffer xs_instance[] (TLAS instance i = entry i) */
#define XS_BIND_MATERIALS 5  /* readonly buffer xs_material[] */
#define XS_BIND_EMITTERS 6   /* readonly buffer xs_emitter[] */
#define XS_BIND_TEXTURES 7   /* sampler2D[] (variable count, partially bound) */
/* per-eye outputs, image2DArray with layer = eye */
#define XS_BIND_OUT_COLOR 8  /* rgba32f: linear HDR radiance */
#define XS_BIND_OUT_ALBEDO 9 /* rgba32f: demodulated albedo of the first hit (1 for background) */
#define XS_BIND_OUT_DEPTH 10 /* r32f: view-space distance along -Z in metres, 0 = background */
#define XS_BIND_OUT_HITID 11 /* rgba32ui: instance, primitive, bary.u bits, bary.v bits */
#define XS_BIND_ACCUM 12     /* rgba32f: progressive sum (rgb) and sample count (a) */
#define XS_BIND_RAY_COUNTER 13 /* buffer uint64 (as uvec2 lo/hi or atomic uint): rays traced */
#define XS_BIND_ENV_MAP 14     /* readonly buffer float[]: the environment map, XS_ENV_* layout */
#define XS_BIND_LIGHTS 15      /* readonly buffer xs_light[]: KHR_lights_punctual (not the sun) */

/* Layout of XS_BIND_ENV_MAP for a W x H equirectangular map (sc_env.h), N = W * H, in floats:
 * texel i (row-major, rows top to bottom) at 4i: rgb radiance, a = p_texel W H / (2 pi^2);
 * the marginal cdf over rows at XS_ENV_MARGINAL(N) (H floats); row y's conditional cdf at
 * XS_ENV_CONDITIONAL(N, H) + y W (W floats). Without a map the buffer holds 4 zeros. */
#define XS_ENV_MARGINAL(n) (4u * (n))
#define XS_ENV_CONDITIONAL(n, h) (5u * (n) + (h))
#define XS_ENV_FLOATS(n, h) (6u * (n) + (h))

/* ---- descriptor set 1 of spp.rgen: the raw moments of each pixel's samples (seed 000 Eq. 5,
 * for the moments stereo blend), image2DArray rgba32f with layer = eye ---- */
#define XS_SPP_BIND_MU1 0 /* rgb = mean of the N path values, a = N (c_X with c_s = 1) */
#define XS_SPP_BIND_MU2 1 /* rgb = mean of their squares, a = N */

#define XS_MAX_TEXTURES 256
#define XS_NO_TEXTURE 0xFFFFFFFFu
#define XS_NO_EMITTER 0xFFFFFFFFu
#define XS_MISS_INSTANCE 0xFFFFFFFFu

/* ray payload locations and SBT layout */
#define XS_PAYLOAD_PRIMARY 0 /* rayPayloadEXT xs_hit */
#define XS_PAYLOAD_SHADOW 1  /* rayPayloadEXT uint: 1 = unoccluded (set by the shadow miss) */
#define XS_MISS_INDEX_PRIMARY 0
#define XS_MISS_INDEX_SHADOW 1

/* material flags */
#define XS_MAT_DOUBLE_SIDED 1u
#define XS_MAT_UNLIT 2u /* KHR_materials_unlit: shows base colour x texture, scatters nothing */
/* glTF alphaMode (at most one of the two; neither = OPAQUE). alpha = base_color.a x the base
 * colour texture's alpha. MASK: the surface is there where alpha >= alpha_cutoff, a hole
 * elsewhere; BLEND: stochastic transparency, a ray passes with probability 1 - alpha (hit.rahit).
 * Instances of such materials are the only non-opaque ones in the TLAS, so the any-hit shader
 * runs for them only. */
#define XS_MAT_ALPHA_MASK 4u
#define XS_MAT_ALPHA_BLEND 8u
/* Smooth thin-walled transmission lets shadow rays through (xs_path.glsl, xs_glass_
 * transmittance): set for non-BLEND materials without KHR_materials_volume with transmission
 * > 0, metallic < 1 and roughness factor below XS_GLASS_SMOOTH_ROUGHNESS (or a metal/rough
 * texture that may make it so); the shader checks the values at each point. */
#define XS_MAT_GLASS_SHADOW 16u
/* Glass with perceptual roughness below this is treated as perfectly smooth (delta lobes). */
#define XS_GLASS_SMOOTH_ROUGHNESS 0.05
/* Most glass surfaces one shadow ray passes through; behind more it counts as occluded. */
#define XS_GLASS_MAX_LAYERS 8u

/* TLAS instance masks (cullMask of traceRayEXT): every instance is in XS_CULL_ALL; BLEND
 * instances are in XS_CULL_BLEND only, the others in XS_CULL_SOLID only. The sample cache's
 * retrace rays test with XS_CULL_SOLID (sc_trace.rgen: a stochastic surface does not decide
 * whether a cached sample behind it lives on). */
#define XS_CULL_ALL 0xFFu
#define XS_CULL_SOLID 0x01u
#define XS_CULL_BLEND 0x02u
/* Specialization constant (raygen shaders, xs_path.glsl): the scene has XS_CULL_GLASS
 * instances (gpu_rt_program_desc.glass). */
#define XS_SPEC_GLASS_ID 0
/* Specialization constant of sc_shade.rgen: the visibility cache is on
 * (gpu_rt_program_desc.viscache). Off, the driver compiles none of the cache's lookups. */
#define XS_SPEC_VISCACHE_ID 1

/* Instances of XS_MAT_GLASS_SHADOW materials are in XS_CULL_GLASS only (not SOLID): a shadow
 * ray first tests XS_CULL_NO_GLASS and then walks the glass it passes (xs_path.glsl); the sample
 * cache's retraces test XS_CULL_SOLID | XS_CULL_GLASS. */
#define XS_CULL_GLASS 0x04u
#define XS_CULL_NO_GLASS (XS_CULL_ALL & ~XS_CULL_GLASS)

/* texture slots of xs_material.uv_rows (KHR_texture_transform, one 2x3 matrix per slot) */
#define XS_TEX_BASE 0
#define XS_TEX_METAL_ROUGH 1
#define XS_TEX_EMISSION 2
#define XS_TEX_NORMAL 3
#define XS_TEX_SLOTS 4
/* bits of xs_material.uv1_mask: (1 << XS_TEX_*) and (1 << XS_UV1_*) = that texture reads
 * TEXCOORD_1 (xs_vertex.uv1) instead of TEXCOORD_0 */
#define XS_UV1_TRANSMISSION 4
#define XS_UV1_SPECULAR 5
#define XS_UV1_SPECULAR_COLOR 6
#define XS_UV1_CLEARCOAT 7
#define XS_UV1_CLEARCOAT_ROUGH 8
#define XS_UV1_SHEEN_COLOR 9
#define XS_UV1_SHEEN_ROUGH 10

/* xs_frame.jitter: sub-pixel positions of the samples (spp.rgen) */
#define XS_JITTER_CENTRE 0u /* every sample through the pixel centre */
#define XS_JITTER_RANDOM 1u /* each sample at a random position (the RNG's first 2 numbers) */
#define XS_JITTER_OFFSET 2u /* every sample at (jitter_x, jitter_y): method `taa`'s Halton */

/* path tracer defaults (seed 000 §5.1: three bounces, Russian roulette from the second) */
#define XS_DEFAULT_MAX_BOUNCES 3u
#define XS_RR_START_BOUNCE 2u

XS_STRUCT(xs_vertex)
{
    xs_vec4 position_u; /* xyz position (object space), w = uv.x */
    xs_vec4 normal_v;   /* xyz normal (object space), w = uv.y */
    xs_vec4 tangent;    /* xyz tangent (object space, along +u), w = handedness +-1 (glTF) */
    xs_vec4 uv1;        /* xy TEXCOORD_1 (a copy of TEXCOORD_0 when absent), zw 0 */
} XS_END(xs_vertex);

XS_STRUCT(xs_instance)
{
    xs_mat4 object_to_world;
    xs_mat4 normal_to_world;      /* inverse transpose of object_to_world */
    xs_mat4 prev_object_to_world; /* last frame's, for reprojection (seed 000 App. D) */
    xs_uint first_index;          /* into indices[], triangle t uses first_index + 3t .. +2 */
    xs_uint material;
    xs_uint emitter_base; /* emitter of triangle t is emitter_base + t, or XS_NO_EMITTER */
    xs_uint triangle_count;
} XS_END(xs_instance);

XS_STRUCT(xs_material)
{
    xs_vec4 base_color; /* linear RGBA factor */
    xs_vec4 emission;   /* rgb linear emissive (strength applied), w unused */
    xs_float metallic;
    xs_float roughness; /* perceptual; GGX alpha = roughness^2 */
    xs_float transmission;
    xs_float ior;
    xs_uint base_color_tex; /* index into textures[] or XS_NO_TEXTURE */
    xs_uint metal_rough_tex;
    xs_uint emission_tex;
    xs_uint flags; /* XS_MAT_* */
    xs_uint normal_tex;      /* tangent-space normal map (linear) or XS_NO_TEXTURE */
    xs_float normal_scale;   /* scales the map's x and y (glTF normalTexture.scale) */
    xs_float alpha_cutoff;   /* XS_MAT_ALPHA_MASK: glTF alphaCutoff (default 0.5) */
    xs_uint uv1_mask;        /* textures that read TEXCOORD_1: bits XS_TEX_* and XS_UV1_* */
    /* slot k's uv' = (dot(uv_rows[2k].xyz, (u, v, 1)), dot(uv_rows[2k+1].xyz, (u, v, 1))) */
    xs_vec4 uv_rows[2 * XS_TEX_SLOTS];
    /* ---- KHR_materials_specular / _clearcoat / _sheen / _volume (xs_bsdf.glsl). Their
     * textures use no KHR_texture_transform (their set: uv1_mask). All zero = none of them, except
     * specular (1) and specular_color (1): sc_scene.c fills the defaults. */
    xs_vec4 specular;    /* rgb specularColorFactor, w = specularFactor (1, 1, 1, 1 = plain glTF) */
    xs_vec4 sheen;       /* rgb sheenColorFactor (0 = no sheen), w = sheenRoughnessFactor */
    xs_vec4 attenuation; /* rgb sigma_a = -ln(attenuationColor) / attenuationDistance, 1/m; w = thicknessFactor
                          * (KHR_materials_volume: > 0 = a refracting volume, 0 = thin-walled) */
    xs_float clearcoat;           /* clearcoatFactor, 0 = no coat */
    xs_float clearcoat_roughness; /* clearcoatRoughnessFactor (perceptual) */
    xs_uint transmission_tex;     /* R x transmission, or XS_NO_TEXTURE */
    xs_uint specular_tex;         /* A x specularFactor */
    xs_uint specular_color_tex;   /* sRGB rgb x specularColorFactor */
    xs_uint clearcoat_tex;        /* R x clearcoatFactor */
    xs_uint clearcoat_rough_tex;  /* G x clearcoatRoughnessFactor */
    xs_uint sheen_color_tex;      /* sRGB rgb x sheenColorFactor */
    xs_uint sheen_rough_tex;      /* A x sheenRoughnessFactor */
    xs_uint ext_pad0, ext_pad1, ext_pad2;
} XS_END(xs_material);

XS_STRUCT(xs_emitter)
{
    xs_uint instance;
    xs_uint primitive;
    xs_float pmf; /* probability of choosing this emitter */
    xs_float cdf; /* inclusive prefix sum of pmf, for binary search */
} XS_END(xs_emitter);

XS_STRUCT(xs_eye)
{
    xs_mat4 view;     /* world → eye */
    xs_mat4 view_inv; /* eye → world */
    xs_mat4 proj;     /* Vulkan clip space, from XrFovf */
    xs_vec4 tan_fov;  /* tan(angleLeft), tan(angleRight), tan(angleUp), tan(angleDown) */
} XS_END(xs_eye);

XS_STRUCT(xs_frame)
{
    xs_eye eyes[2];
    xs_vec4 environment;   /* rgb constant environment radiance */
    xs_vec4 sun_direction; /* xyz towards the sun (unit), w = 1 if present */
    xs_vec4 sun_radiance;  /* rgb irradiance normal to the sun */
    xs_uint width, height; /* per eye, pixels */
    xs_uint frame_index;   /* RNG stream */
    xs_uint samples_per_pixel;
    xs_uint max_bounces;
    xs_uint emitter_count;
    xs_uint accumulate; /* 1: add to XS_BIND_ACCUM and write its mean; 0: this frame only */
    xs_uint jitter;     /* XS_JITTER_*: where in the pixel the samples go */
    xs_uint seed;
    xs_float jitter_x, jitter_y; /* XS_JITTER_OFFSET: the sub-pixel position in [0, 1)^2 */
    /* environment map (XS_BIND_ENV_MAP): env_width 0 = none, the constant `environment` */
    xs_uint env_width, env_height;
    xs_uint env_sampling;     /* 1: importance-sample the map in next-event estimation */
    xs_float env_rotation;    /* radians about +Y (sc_env.h) */
    xs_float sun_cos_max;     /* cos of the sun disk's angular radius; 0 = a delta sun */
    xs_uint light_count;      /* entries of XS_BIND_LIGHTS; 0: no punctual light, no RNG draw */
    xs_uint glass_instances;  /* XS_CULL_GLASS instances; 0: a shadow ray is one ray, as before */
    xs_uint light_pad1, light_pad2;
} XS_END(xs_frame);

/* xs_light.type: KHR_lights_punctual's three kinds */
#define XS_LIGHT_DIRECTIONAL 0u
#define XS_LIGHT_POINT 1u
#define XS_LIGHT_SPOT 2u

/* One punctual (delta) light of XS_BIND_LIGHTS in world space. Next-event estimation picks one
 * light per path vertex with probability pmf (proportional to an estimate of its power,
 * gpu_scene.h) by binary search of cdf. Radiometry (glTF units taken as radiometric, as the
 * sun's lux → irradiance): point/spot give radiant intensity I (candela → W/sr), so the
 * irradiance at distance d facing the light is I / d^2 x spot x window; directional lights
 * give irradiance normal to the light (lux). */
XS_STRUCT(xs_light)
{
    xs_vec4 position;  /* xyz world position (point, spot); w = range in metres, 0 = infinite */
    xs_vec4 direction; /* xyz unit: directional: towards the light (node +Z); spot: the axis
                        * it shines along (node -Z); w unused */
    xs_vec4 intensity; /* rgb colour x intensity (W/sr, or W/m^2 for directional); w = pmf */
    xs_uint type;      /* XS_LIGHT_* */
    xs_float spot_scale;  /* glTF spot: 1 / max(0.001, cos(inner) - cos(outer)) */
    xs_float spot_offset; /* -cos(outer) x spot_scale; attenuation = sat(cd x scale + off)^2 */
    xs_float cdf;         /* inclusive prefix sum of the pmfs (last = 1) */
} XS_END(xs_light);

/* The primary payload: what the closest-hit shader reports. */
XS_STRUCT(xs_hit)
{
    xs_uint instance; /* XS_MISS_INSTANCE on a miss */
    xs_uint primitive;
    xs_float bary_u, bary_v; /* barycentrics of vertices 1 and 2 */
    xs_float t;              /* ray distance */
    xs_uint front_face;      /* 1 if the ray hit the triangle's front (CCW) side */
    xs_uint pad0, pad1;
} XS_END(xs_hit);

#ifndef XRSC_GLSL
#include <stddef.h>
_Static_assert(sizeof(xs_vertex) == 64, "xs_vertex layout");
_Static_assert(sizeof(xs_instance) == 208, "xs_instance layout");
_Static_assert(sizeof(xs_material) == 304, "xs_material layout");
_Static_assert(offsetof(xs_material, specular) == 208, "xs_material layout");
_Static_assert(offsetof(xs_material, clearcoat) == 256, "xs_material layout");
_Static_assert(offsetof(xs_material, uv_rows) == 80, "xs_material layout");
_Static_assert(offsetof(xs_material, alpha_cutoff) == 72, "xs_material layout");
_Static_assert(sizeof(xs_emitter) == 16, "xs_emitter layout");
_Static_assert(sizeof(xs_eye) == 208, "xs_eye layout");
_Static_assert(offsetof(xs_frame, width) == 464, "xs_frame layout");
_Static_assert(sizeof(xs_frame) % 16 == 0, "xs_frame layout");
_Static_assert(offsetof(xs_frame, sun_cos_max) == 524, "xs_frame layout");
_Static_assert(sizeof(xs_hit) == 32, "xs_hit layout");
_Static_assert(offsetof(xs_frame, light_count) == 528, "xs_frame layout");
_Static_assert(sizeof(xs_light) == 64, "xs_light layout");
_Static_assert(offsetof(xs_light, type) == 48, "xs_light layout");
#endif

/* ---- deformation pass (deform.comp, gpu_deform.c): skins and morph targets posed on the GPU
 * each frame into the scene's vertices[] (which the BLAS of a deformed mesh is built from) ---- */
#define XS_DEFORM_BIND_VERTICES 0   /* buffer xs_vertex[]: the scene's vertices; posed ones written */
#define XS_DEFORM_BIND_REST 1       /* readonly xs_vertex[]: rest vertices of the deformed meshes */
#define XS_DEFORM_BIND_INFLUENCES 2 /* readonly xs_skin_influence[] (sc_scene.influences) */
#define XS_DEFORM_BIND_DELTAS 3     /* readonly xs_morph_delta[] (sc_scene.deltas) */
#define XS_DEFORM_BIND_MATRICES 4   /* readonly mat4[]: joint matrices (sc_scene.pose_matrices) */
#define XS_DEFORM_BIND_WEIGHTS 5    /* readonly float[]: morph weights (sc_scene.pose_weights) */
#define XS_DEFORM_BIND_PREV 6       /* buffer vec4[]: last frame's posed object-space position of
                                     * every scene vertex (xyz; static vertices: never written) */
#define XS_DEFORM_GROUP_SIZE 64

/* Four skin influences of one vertex (one JOINTS_n/WEIGHTS_n set; joints index the skin). */
XS_STRUCT(xs_skin_influence)
{
    xs_uvec4 joints;
    xs_vec4 weights;
} XS_END(xs_skin_influence);

/* One morph target's displacement of one vertex (w unused). */
XS_STRUCT(xs_morph_delta)
{
    xs_vec4 position;
    xs_vec4 normal;
    xs_vec4 tangent;
} XS_END(xs_morph_delta);

/* Push constants of one dispatch of deform.comp: one deformed mesh (sc_mesh fields). */
XS_STRUCT(xs_deform_push)
{
    xs_uint first_vertex;    /* in vertices[] */
    xs_uint vertex_count;
    xs_uint rest_base;       /* its first vertex in the rest copy */
    xs_uint first_influence; /* set k of vertex v: first_influence + k * vertex_count + v */
    xs_uint skin_sets;       /* 0: no skin */
    xs_uint first_matrix;
    xs_uint first_delta;     /* target k of vertex v: first_delta + k * vertex_count + v */
    xs_uint target_count;
    xs_uint first_weight;
    xs_uint keep_prev;       /* 1: prev = the position before this pass (a frame step); 0: no
                              * motion (prev = the new pose) */
    xs_uint joint_count;     /* matrices from first_matrix */
    xs_uint pad0;
} XS_END(xs_deform_push);

#ifndef XRSC_GLSL
_Static_assert(sizeof(xs_skin_influence) == 32, "xs_skin_influence layout");
_Static_assert(sizeof(xs_morph_delta) == 48, "xs_morph_delta layout");
_Static_assert(sizeof(xs_deform_push) == 48, "xs_deform_push layout");
#endif

#endif /* XRSC_SHARED_H */
