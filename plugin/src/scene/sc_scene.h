// SPDX-License-Identifier: MIT
/**
 * @file sc_scene.h
 * @brief The CPU scene model: what a glTF 2.0 file becomes before it goes to the GPU.
 *
 * Everything is flattened into arrays owned by ::sc_scene and freed by ::sc_scene_destroy.
 * Geometry: one ::sc_mesh per glTF mesh primitive (triangles only), vertices and indices in
 * one shared array each. Instances: one ::sc_instance per (node, primitive) pair, with the
 * node's world transform at the time last evaluated by ::sc_scene_evaluate.
 * Coordinates are glTF's (right-handed, +Y up, metres) which equal OpenXR's.
 */
#pragma once

#include "sc_env.h"
#include "xrsc/result.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define SC_NO_TEXTURE UINT32_MAX
/** Distinct warning IDs a scene records (sc_scene.warning_ids). */
#define SC_MAX_WARNING_IDS 16
/** Sun of --sky when neither the option nor the file gives one: 45 degrees up, behind the
 *  default viewpoint's right shoulder (x, y, z before normalisation). */
#define SC_DEFAULT_SUN_DIRECTION {0.5f, 0.70710678f, 0.5f}

typedef struct sc_vertex {
    float position[3];
    float normal[3]; /**< unit; generated (flat) when the file has none */
    float uv[2];     /**< TEXCOORD_0, (0,0) when absent */
    float uv1[2];    /**< TEXCOORD_1, a copy of uv when absent (textures with texCoord 1) */
    /** Unit tangent (xyz, along +u) and handedness w = +-1 (bitangent = w * cross(normal,
     *  tangent)), as glTF's TANGENT. From the file when it has TANGENT, else generated from
     *  the UV derivatives (see sc_scene.c, sc_tangents). */
    float tangent[4];
} sc_vertex;

typedef struct sc_mesh {
    uint32_t first_vertex, vertex_count; /**< range in sc_scene.vertices */
    uint32_t first_index, index_count;   /**< range in sc_scene.indices; index_count % 3 == 0.
                                          *   Index values are absolute: they index
                                          *   sc_scene.vertices directly (first_vertex is
                                          *   already added). Triangles are in Morton order
                                          *   (see ::sc_morton_sort_triangles). */
    uint32_t material;                   /**< index in sc_scene.materials (a default is added) */
    /** Deformation (skin and/or morph targets, see sc_skin.c): deform_node is the node whose
     *  skin and morph weights pose the mesh (SC_NO_DEFORM: a rigid mesh, all fields below 0).
     *  skin_sets: JOINTS_n/WEIGHTS_n sets; set k of vertex v (0-based in the mesh) is
     *  sc_scene.influences[first_influence + k * vertex_count + v]. target_count morph
     *  targets; target k of vertex v is sc_scene.deltas[first_delta + k * vertex_count + v].
     *  Each frame's pose (::sc_scene_evaluate): skin_joint_count joint matrices from
     *  sc_scene.pose_matrices[16 * first_pose_matrix] and target_count weights from
     *  sc_scene.pose_weights[first_pose_weight]. */
    uint32_t deform_node;
    uint32_t skin_sets, first_influence, skin_joint_count, first_pose_matrix;
    uint32_t target_count, first_delta, first_pose_weight;
} sc_mesh;

/** sc_mesh.deform_node of a rigid mesh. */
#define SC_NO_DEFORM UINT32_MAX

/** Four skin influences of one vertex (one JOINTS_n/WEIGHTS_n set); joints index the skin's
 *  joint list. */
typedef struct sc_skin_influence {
    uint32_t joints[4];
    float weights[4];
} sc_skin_influence;

/** One morph target's displacement of one vertex (glTF `targets`; absent attributes 0). */
typedef struct sc_morph_delta {
    float position[3], normal[3], tangent[3];
} sc_morph_delta;

/** A glTF skin: joint j is node sc_scene.skin_joints[first_joint + j] with the inverse bind
 *  matrix sc_scene.inverse_binds[16 * (first_joint + j)] (column-major). */
typedef struct sc_skin {
    uint32_t first_joint, joint_count;
} sc_skin;

/** Texture slots of a material, in the order of sc_material.uv_transform. */
enum { SC_TEX_BASE, SC_TEX_METAL_ROUGH, SC_TEX_EMISSION, SC_TEX_NORMAL, SC_TEX_SLOTS };
/** Bits of sc_material.uv1_mask beyond the slots above (bit SC_TEX_* for those): the
 *  extensions' textures (xrsc_shared.h XS_UV1_*). */
enum {
    SC_UV1_TRANSMISSION = SC_TEX_SLOTS,
    SC_UV1_SPECULAR,
    SC_UV1_SPECULAR_COLOR,
    SC_UV1_CLEARCOAT,
    SC_UV1_CLEARCOAT_ROUGH,
    SC_UV1_SHEEN_COLOR,
    SC_UV1_SHEEN_ROUGH,
    SC_UV1_BITS
};

/** glTF 2.0 material.alphaMode. */
typedef enum sc_alpha_mode {
    SC_ALPHA_OPAQUE = 0, /**< alpha ignored */
    SC_ALPHA_MASK,       /**< a hole where alpha < alpha_cutoff */
    SC_ALPHA_BLEND,      /**< blended over what is behind: stochastic transparency */
} sc_alpha_mode;

typedef struct sc_material {
    float base_color[4];        /**< linear RGBA factor */
    uint32_t base_color_tex;    /**< texture index (sRGB) or SC_NO_TEXTURE */
    float metallic, roughness;  /**< factors (perceptual roughness, GGX alpha = roughness^2) */
    uint32_t metal_rough_tex;   /**< texture index (linear, G = roughness, B = metallic) */
    float emission[3];          /**< linear emissive factor x KHR_materials_emissive_strength */
    uint32_t emission_tex;      /**< texture index (sRGB) or SC_NO_TEXTURE */
    float transmission;         /**< KHR_materials_transmission factor, 0 = opaque */
    float ior;                  /**< KHR_materials_ior, default 1.5 */
    uint32_t normal_tex;        /**< tangent-space normal map (linear) or SC_NO_TEXTURE */
    float normal_scale;         /**< normalTexture.scale (scales the map's x and y) */
    bool unlit;                 /**< KHR_materials_unlit: shows base colour x texture, unlit */
    bool double_sided;          /**< false: back faces (glTF winding) are culled for camera
                                 *   rays, as glTF viewers cull them */
    sc_alpha_mode alpha_mode;   /**< alpha = base_color[3] x the base colour texture's alpha */
    float alpha_cutoff;         /**< SC_ALPHA_MASK threshold (glTF alphaCutoff, default 0.5) */
    /** KHR_texture_transform per slot (SC_TEX_*): uv' = (m[0] u + m[1] v + m[2],
     *  m[3] u + m[4] v + m[5]); identity when the file has none. */
    float uv_transform[SC_TEX_SLOTS][6];
    /** Which texture reads TEXCOORD_1 (glTF texCoord 1) instead of TEXCOORD_0: bit SC_TEX_*
     *  or SC_UV1_*. Sets above 1 are not read (their textures are left out, warned). */
    uint32_t uv1_mask;
    char name[64];
    /* The extensions below read their textures without KHR_texture_transform. */
    uint32_t transmission_tex;  /**< KHR_materials_transmission texture (R, linear) */
    float specular;             /**< KHR_materials_specular specularFactor, 1 = plain glTF */
    float specular_color[3];    /**< specularColorFactor, (1, 1, 1) = plain glTF */
    uint32_t specular_tex;      /**< A x specular (linear) */
    uint32_t specular_color_tex;/**< rgb x specular_color (sRGB) */
    float clearcoat;            /**< KHR_materials_clearcoat factor, 0 = no coat */
    float clearcoat_roughness;  /**< perceptual */
    uint32_t clearcoat_tex;     /**< R x clearcoat (linear) */
    uint32_t clearcoat_rough_tex; /**< G x clearcoat_roughness (linear) */
    float sheen_color[3];       /**< KHR_materials_sheen colour, 0 = no sheen */
    float sheen_roughness;      /**< perceptual */
    uint32_t sheen_color_tex;   /**< rgb x sheen_color (sRGB) */
    uint32_t sheen_rough_tex;   /**< A x sheen_roughness (linear) */
    /** KHR_materials_volume thicknessFactor: > 0 makes a transmissive material a refracting
     *  volume; 0 (absent) = thin-walled, light passes straight through (the extension's rule). */
    float thickness;
    /** Beer-Lambert absorption coefficient inside the volume, 1/m per channel:
     *  -ln(attenuationColor) / attenuationDistance; 0 without attenuation. */
    float sigma_a[3];
} sc_material;

/** glTF sampler wrap modes (zero: REPEAT, glTF's default). */
typedef enum sc_wrap { SC_WRAP_REPEAT, SC_WRAP_CLAMP_TO_EDGE, SC_WRAP_MIRRORED_REPEAT } sc_wrap;

/** A texture's glTF sampler; zero = REPEAT, linear filtering (no mipmaps are kept: a
 *  minFilter's mipmap variants use their base filter). */
typedef struct sc_sampler {
    sc_wrap wrap_u, wrap_v; /**< wrapS, wrapT */
    bool mag_nearest, min_nearest;
} sc_sampler;

typedef struct sc_texture {
    uint32_t width, height;
    uint8_t *rgba8; /**< width*height*4 bytes, rows top to bottom */
    bool srgb;      /**< true for base colour and emission */
    sc_sampler sampler;
} sc_texture;

typedef struct sc_node {
    int32_t parent;          /**< -1 for roots */
    float translation[3];    /**< local TRS (as in the file, updated by animation) */
    float rotation[4];       /**< quaternion x, y, z, w */
    float scale[3];
    float world[16];         /**< column-major local → world, from ::sc_scene_evaluate */
    char name[64];
    bool has_matrix;         /**< the file gave a matrix (not animated): used instead of TRS */
    float matrix[16];        /**< column-major local matrix when has_matrix (TRS = its
                              *   decomposition) */
    int32_t skin;            /**< index in sc_scene.skins, -1 when none */
    /** Morph weights (node.weights, else its mesh's, else 0; animated by `weights` channels):
     *  sc_scene.node_weights[first_weight .. + weight_count]. */
    uint32_t first_weight, weight_count;
} sc_node;

typedef struct sc_instance {
    uint32_t mesh;      /**< index in sc_scene.meshes */
    uint32_t node;      /**< index in sc_scene.nodes */
    float world[16];    /**< node world transform (column-major), from ::sc_scene_evaluate */
    bool animated;      /**< the node or one of its ancestors is animated */
    /** EXT_mesh_gpu_instancing: world = node world x local (column-major TRS of the
     *  instance's TRANSLATION/ROTATION/SCALE), when has_local. */
    bool has_local;
    float local[16];
} sc_instance;

/** One emissive triangle: an area light. The emitters of one instance are contiguous and in
 *  triangle order, one for every triangle of an instance whose material emits (zero-area
 *  triangles get power 0), so emitter = first emitter of the instance + primitive. */
typedef struct sc_emitter {
    uint32_t instance, primitive; /**< primitive = triangle index within the mesh */
    float power;                  /**< luminance(emission) x world area at load time */
} sc_emitter;

typedef enum sc_anim_path {
    SC_ANIM_TRANSLATION,
    SC_ANIM_ROTATION,
    SC_ANIM_SCALE,
    SC_ANIM_WEIGHTS, /**< the node's morph weights (sc_node.weight_count values per key) */
} sc_anim_path;
typedef enum sc_anim_interp { SC_INTERP_LINEAR, SC_INTERP_STEP, SC_INTERP_CUBICSPLINE } sc_anim_interp;

typedef struct sc_anim_channel {
    uint32_t node;
    sc_anim_path path;
    sc_anim_interp interp;
    uint32_t key_count;
    float *times;  /**< seconds, key_count entries, increasing */
    float *values; /**< key_count x (3, 4 or weight count) floats (x3 again for CUBICSPLINE:
                    *   in, value, out) */
    uint32_t components; /**< values per key and element: 3, 4, or the node's weight count */
} sc_anim_channel;

/** One animation clip of the file (glTF `animations[i]`), whether it plays or not. */
typedef struct sc_clip {
    char name[128];         /**< "" when the file gives none */
    float duration_s;       /**< the last key time over its channels' inputs */
    uint32_t channel_count; /**< its channels in the file (every path) */
} sc_clip;

/** sc_scene.clip_playing when no clip plays, or when every clip does (sc_load_options). */
#define SC_CLIP_NONE (-1)
#define SC_CLIP_ALL (-2)

/** What the file holds beyond what is drawn, for `xrsc scene info`. */
typedef struct sc_file_facts {
    uint32_t node_count, mesh_count, image_count, material_count; /**< the file's */
    uint32_t skin_count, morph_target_count, morph_mesh_count;    /**< see sc_gltf_facts */
    char extensions_used[1024], extensions_required[1024];       /**< comma-separated */
} sc_file_facts;

typedef struct sc_sun {
    bool present;
    float direction[3]; /**< unit, pointing FROM the scene TOWARDS the sun (world space) */
    float radiance[3];  /**< irradiance on a surface facing the sun: color x intensity */
    /** 0: a delta light (glTF directional); else a disk of this angular radius (the sky's
     *  sun), importance-sampled as a cone and seen by rays that escape towards it. */
    float angular_radius_rad;
} sc_sun;

typedef enum sc_light_type { SC_LIGHT_DIRECTIONAL, SC_LIGHT_POINT, SC_LIGHT_SPOT } sc_light_type;

/** A KHR_lights_punctual light other than the sun (::sc_sun is the file's first directional
 *  light): every further directional light, every point and spot light, one per node that
 *  names it. Its position and direction are its node's world transform (sc_node.world:
 *  origin, and -Z = where it shines), so animated nodes move it; scale does not change it. */
typedef struct sc_light {
    sc_light_type type;
    uint32_t node;        /**< index in sc_scene.nodes */
    float intensity[3];   /**< colour x intensity: W/sr (point, spot: candela taken as W/sr)
                           *   or irradiance normal to the light (directional: lux) */
    float range_m;        /**< 0 = infinite; else glTF's window clamp(1 - (d/range)^4, 0, 1) */
    float inner_cone_rad, outer_cone_rad; /**< spot: 0 <= inner <= outer <= pi/2 (clamped) */
    bool animated;        /**< the node or an ancestor is animated */
} sc_light;
/** A perspective glTF camera: its node's world pose at time 0 (scale removed). */
typedef struct sc_camera {
    uint32_t node;
    float yfov_rad;
    float position[3];
    float orientation[4]; /**< x, y, z, w */
} sc_camera;

/** Wall time of the load's stages (ms), for the run's `load` line and measurements. The
 *  geometry, tangent and Morton times are sums over the primitives; build_ms includes them. */
typedef struct sc_load_timing {
    double read_ms;     /**< reading the file (sc_scene_load only) */
    double parse_ms;    /**< tinygltf: JSON, buffers, images decoded */
    double geometry_ms; /**< accessors read, vertices and indices filled */
    double tangents_ms; /**< tangents checked or generated */
    double morton_ms;   /**< triangles sorted along the Morton curve */
    double build_ms;    /**< the whole scene from the parsed document */
} sc_load_timing;

typedef struct sc_scene {
    char path[512];
    sc_vertex *vertices;   uint32_t vertex_count;
    uint32_t *indices;     uint32_t index_count;
    sc_mesh *meshes;       uint32_t mesh_count;
    sc_material *materials; uint32_t material_count;
    sc_texture *textures;  uint32_t texture_count;
    sc_node *nodes;        uint32_t node_count;
    sc_instance *instances; uint32_t instance_count;
    sc_emitter *emitters;  uint32_t emitter_count;
    sc_anim_channel *channels; uint32_t channel_count;
    float animation_duration_s; /**< max key time over all channels, 0 when static */
    sc_sun sun;
    sc_light *lights;      uint32_t light_count; /**< punctual lights besides the sun */
    float environment[3]; /**< constant environment radiance (see sc_load_options); with a
                           *   map: the map's mean radiance, for passes that do not read it */
    /** Environment map (--env-map or the baked sky): width 0 when the environment is the
     *  constant above. Rotation about +Y in radians (sc_env.h). */
    sc_env_map env_map;
    float env_rotation_rad;
    /** The map is the built-in studio environment (sc_studio_bake): the scene has no light
     *  and no environment was given (sc_load_options). */
    bool env_studio;
    /** Viewpoint: the first perspective camera's node when has_camera; otherwise, looking
     *  down -Z from (cx, cy, max_z + 1.2 * max(half_x, half_y)) of the world bounds. */
    bool has_camera;
    float camera_yfov_rad;     /**< the camera's perspective.yfov when has_camera */
    float camera_aspect_ratio; /**< its aspectRatio, 0 when the file gives none */
    /** Every perspective camera of the drawn scene in the order the nodes are walked
     *  (depth-first from the scene's roots; cameras[0] is the viewpoint's). */
    sc_camera *cameras;
    uint32_t camera_count;
    float viewpoint_position[3];
    float viewpoint_orientation[4]; /**< x, y, z, w */
    float bounds_min[3], bounds_max[3]; /**< world AABB at time 0 */
    uint64_t triangle_count; /**< over all instances */
    uint32_t warning_count;  /**< warnings the load printed (each at most once), for tests */
    /** The IDs (XRSC_WARN_*) of the warnings the load printed, each ID once, in order of
     *  first occurrence (see ::sc_scene_warned). */
    xrsc_result warning_ids[SC_MAX_WARNING_IDS];
    uint32_t warning_id_count;
    sc_load_timing load_timing;
    /** The file's clips (all of them) and the one whose channels play (an index,
     *  SC_CLIP_NONE or SC_CLIP_ALL): channels[] and animation_duration_s are its. */
    sc_clip *clips;
    uint32_t clip_count;
    int32_t clip_playing;
    sc_file_facts facts;
    uint32_t *node_order; /**< internal: node indices, parents before children */
    /* ---- skins and morph targets (sc_mesh deformation fields) ---- */
    sc_skin *skins;                uint32_t skin_count;
    uint32_t *skin_joints;         uint32_t skin_joint_total; /**< node indices */
    float *inverse_binds;          /**< 16 floats per skin_joints entry */
    sc_skin_influence *influences; uint32_t influence_count;
    sc_morph_delta *deltas;        uint32_t delta_count;
    float *node_weights;           uint32_t node_weight_count;
    /** The current pose (::sc_scene_evaluate): per deformed mesh its joint matrices
     *  inverse(world of deform_node) x world of joint x inverse bind (column-major, so that
     *  the posed object-space vertex is sum_i w_i M_i v) and its morph weights. */
    float *pose_matrices;          uint32_t pose_matrix_count;
    float *pose_weights;           uint32_t pose_weight_count;
    uint32_t deform_mesh_count;    /**< meshes with deform_node != SC_NO_DEFORM */
} sc_scene;

/**
 * Load options. Zero means the documented default.
 * environment: when env_set is false, the scene's `extras.xrsc_environment` [r,g,b] if present,
 * else the built-in studio environment map (sc_studio_bake; env_intensity, env_rotation_deg
 * and env_no_importance apply to it) when the scene has no directional light (emissive
 * triangles and point/spot lights notwithstanding: glTF models without a sun expect
 * image-based lighting, which viewers keep on beside lamps), else 0.
 * env_set with (1, 1, 1) gives the grey of earlier versions.
 * env_map_path (a Radiance .hdr or an OpenEXR .exr, equirectangular) or sky replace the
 * constant environment;
 * env_map_path wins over sky.
 */
typedef struct sc_load_options {
    bool env_set;
    float environment[3];
    const char *env_map_path; /**< NULL: none */
    float env_intensity;      /**< scales the map (the sky: sun and sky); 0 means 1 */
    float env_rotation_deg;   /**< turns the map (or sky) about +Y, counter-clockwise from above */
    /** The Preetham sun and sky (sc_env.h): the sky becomes the environment map and the sun a
     *  disk light that replaces the file's directional lights (sc_scene.lights keeps only
     *  its point and spot lights). */
    bool sky;
    float sky_turbidity;      /**< 0 means SC_SKY_DEFAULT_TURBIDITY */
    bool sun_direction_set;   /**< else the file's sun direction, else SC_DEFAULT_SUN_DIRECTION */
    float sun_direction[3];   /**< towards the sun; normalised on load */
    /** For tests and benchmarks: no light samples of the map (escaping BSDF rays only). */
    bool env_no_importance;
    /** Keep the file's triangle order (skip the Morton sort); for tests and benchmarks. */
    bool keep_triangle_order;
    /** The clip that plays (looping): NULL, "" or "first" = the file's first clip (none when
     *  it has none); "all" = every clip's channels at once; "none" = no animation; else a
     *  clip's index in `animations` (digits) or its name. A name or index the file does not
     *  have: XRSC_ERROR_ANIMATION_UNKNOWN, field "animation", the message listing the clips. */
    const char *animation;
} sc_load_options;

/**
 * Loads a .gltf or .glb file. On error returns a negative ::xrsc_result, fills diag with
 * file, line (best effort for JSON) and field, and leaves *out NULL. Features that are
 * ignored are named in ONE warning (logged once per load); each ignored optional extension
 * gets its own warning (XRSC_WARN_GLTF_EXTENSION_IGNORED). What cannot be drawn is stood in
 * for with a warning whose ID sc_scene.warning_ids records: a missing image file
 * (XRSC_WARN_GLTF_IMAGE_MISSING) or an undecodable image (_IMAGE_UNDECODABLE) makes its
 * texture slot absent (white base colour, flat normal, the factors alone); points and lines
 * are skipped (XRSC_WARN_GLTF_PRIMITIVE_SKIPPED, one warning). Errors: a required extension
 * that is not supported, a missing buffer file, indices out of range, and the container
 * errors of sc_gltf_parse (not glTF: XRSC_ERROR_GLTF_NOT_GLTF; glTF 1.0: _GLTF_VERSION; a .glb
 * without its magic: _GLB_MAGIC; a truncated GLB: _GLB_TRUNCATED).
 * Supported: meshes (TRIANGLES; TRIANGLE_STRIP and TRIANGLE_FAN become triangle lists),
 * KHR_draco_mesh_compression when built with libdraco (CMake XRSC_DRACO; else a required one
 * is refused naming it), EXT_meshopt_compression when built with libmeshoptimizer (CMake
 * XRSC_MESHOPT; same), EXT_mesh_gpu_instancing (one instance per TRANSLATION/ROTATION/SCALE
 * element), sampler wrap modes and nearest/linear filters per texture,
 * KHR_materials_pbrSpecularGlossiness (converted to metal/rough at load, see sc_scene.c),
 * node hierarchy, TEXCOORD_0 and TEXCOORD_1 (each texture reads the set its texCoord names;
 * a texture naming set 2 or above is left out, warned), materials (baseColor factor
 * and texture, metallicRoughness factor and texture, emissive factor and texture, normal
 * texture (tangent space, TANGENT or generated tangents), KHR_materials_emissive_strength,
 * KHR_materials_transmission (and its texture), KHR_materials_ior, KHR_materials_unlit,
 * KHR_texture_transform, KHR_materials_specular, _clearcoat, _sheen, _volume: see sc_material),
 * cameras (first perspective camera's node = viewpoint, its yfov and aspectRatio kept),
 * KHR_lights_punctual (the first directional light = sun; every other light, point and spot
 * with range and cone angles, in sc_scene.lights), node animation (T/R/S and morph weights;
 * LINEAR, STEP, CUBICSPLINE), skins (JOINTS_n/WEIGHTS_n sets 0-3, inverseBindMatrices) and
 * morph targets (POSITION/NORMAL/TANGENT deltas; node weights, else mesh weights, else 0),
 * kept as sc_mesh deformation data and posed by ::sc_scene_evaluate (sc_skin.c; the GPU
 * applies the pose, gpu_deform.h). A skinned or morphed mesh drawn by several nodes shows
 * the first node's pose (named in the ignored-features warning). A scene whose `nodes` also lists non-root nodes draws the roots they reach
 * (each node once), with one warning. occlusionTexture is ignored without a warning: a path
 * tracer computes the occlusion it approximates.
 */
xrsc_result sc_scene_load(const char *path, const sc_load_options *opt, sc_scene **out,
                          xrsc_diag *diag);
/**
 * Loads glTF from memory: GLB when data starts with "glTF", else JSON text. name is used in
 * messages and sc_scene.path. External buffers and images are read from base_dir; with
 * base_dir NULL no file is read (an external uri is then XRSC_ERROR_GLTF_MISSING_BUFFER).
 * Same errors and ownership as ::sc_scene_load (data is not kept).
 */
xrsc_result sc_scene_load_memory(const char *name, const void *data, size_t size,
                                 const char *base_dir, const sc_load_options *opt,
                                 sc_scene **out, xrsc_diag *diag);
/** True when loading the scene printed a warning with this ID (XRSC_WARN_*). */
bool sc_scene_warned(const sc_scene *scene, xrsc_result id);
/** Frees the scene; accepts NULL and sets *scene to NULL. */
void sc_scene_destroy(sc_scene **scene);
/**
 * Evaluates the animation at time_s (looping over animation_duration_s) and updates
 * nodes[].world and instances[].world. Called once at load with time 0.
 */
void sc_scene_evaluate(sc_scene *scene, double time_s);

/** Fills sc_scene.pose_matrices and pose_weights from the nodes' world transforms and
 *  weights (sc_scene_evaluate calls it). */
void sc_scene_pose(sc_scene *scene);
/**
 * The CPU reference of the GPU's deformation (deform.comp): vertex v (absolute index in
 * sc_scene.vertices, of deformed mesh `mesh`) under the current pose, object space of the
 * mesh's instance: morph targets first (p + sum w_k dp_k), then the skin
 * (sum_i w_i M_i p over every set, weights as in the file). out_normal may be NULL.
 */
void sc_scene_posed_vertex(const sc_scene *scene, uint32_t mesh, uint32_t v, float out_pos[3],
                           float out_normal[3]);

/**
 * Resolves which clip plays from sc_load_options.animation (see there) over the file's clips:
 * *out_playing becomes a clip index, SC_CLIP_NONE or SC_CLIP_ALL. A name or index that is not
 * a clip of the file: XRSC_ERROR_ANIMATION_UNKNOWN with field "animation" and a message that
 * lists the clips (file names the scene in diag).
 */
xrsc_result sc_clip_resolve(const sc_clip *clips, uint32_t clip_count, const char *animation,
                            const char *file, int32_t *out_playing, xrsc_diag *diag);

/**
 * Reorders the triangles of one mesh along a Morton (Z-order) curve of their centroids,
 * quantised with one uniform scale over the three axes of the mesh's bounding box, so that
 * BVH builders that split in input order (lavapipe) get spatially coherent leaves. indices
 * are absolute into vertices; index_count % 3 == 0. The multiset of triangles is unchanged
 * and each triangle keeps its vertex order (winding). Returns false only when out of memory
 * (indices then unchanged).
 */
bool sc_morton_sort_triangles(const sc_vertex *vertices, uint32_t *indices, uint32_t index_count);

#ifdef __cplusplus
}
#endif
