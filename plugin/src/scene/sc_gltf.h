// SPDX-License-Identifier: MIT
/**
 * @file sc_gltf.h
 * @brief Internal: a plain-C view of a parsed glTF 2.0 document, filled by sc_gltf.cpp (the one
 * C++ file, wrapping tinygltf) and turned into an ::sc_scene by sc_scene.c.
 *
 * Indices into the document's arrays are int32_t with -1 for "absent" and are NOT validated
 * here (the C side checks every one). Buffers point into memory owned by the document.
 */
#pragma once

#include "xrsc/result.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** glTF componentType values (the GL enums the file stores). */
enum {
    SC_GLTF_BYTE = 5120,
    SC_GLTF_UNSIGNED_BYTE = 5121,
    SC_GLTF_SHORT = 5122,
    SC_GLTF_UNSIGNED_SHORT = 5123,
    SC_GLTF_UNSIGNED_INT = 5125,
    SC_GLTF_FLOAT = 5126,
};

/** glTF primitive modes xrsc renders (strips and fans become triangle lists). */
#define SC_GLTF_MODE_TRIANGLES 4
#define SC_GLTF_MODE_TRIANGLE_STRIP 5
#define SC_GLTF_MODE_TRIANGLE_FAN 6

/** glTF sampler values (GL enums), sc_gltf_texture. */
#define SC_GLTF_WRAP_REPEAT 10497
#define SC_GLTF_WRAP_CLAMP_TO_EDGE 33071
#define SC_GLTF_WRAP_MIRRORED_REPEAT 33648
#define SC_GLTF_FILTER_NEAREST 9728
#define SC_GLTF_FILTER_LINEAR 9729

typedef struct sc_gltf_buffer {
    const uint8_t *data;
    size_t size;
} sc_gltf_buffer;

typedef struct sc_gltf_view {
    int32_t buffer;
    size_t offset, length, stride; /**< stride 0 = tightly packed */
} sc_gltf_view;

typedef struct sc_gltf_accessor {
    int32_t view; /**< -1: all zeros (then sparse may fill values) */
    size_t offset;
    int32_t component_type; /**< SC_GLTF_* */
    uint32_t components;    /**< 1 (SCALAR), 2, 3, 4 (VECn), 4/9/16 (MATn); 0 when unknown */
    bool normalized;
    size_t count;
    bool sparse;
    size_t sparse_count;
    int32_t sparse_indices_view, sparse_indices_type;
    size_t sparse_indices_offset;
    int32_t sparse_values_view;
    size_t sparse_values_offset;
} sc_gltf_accessor;

/** JOINTS_n / WEIGHTS_n sets read per primitive (each gives 4 influences per vertex). */
#define SC_GLTF_MAX_JOINT_SETS 4

typedef struct sc_gltf_primitive {
    int32_t mode; /**< glTF mode (default 4 filled in) */
    int32_t position, normal, tangent, texcoord0, indices, material; /**< accessor/material or -1 */
    /** JOINTS_n and WEIGHTS_n accessors (-1 when absent), n < SC_GLTF_MAX_JOINT_SETS. */
    int32_t joints[SC_GLTF_MAX_JOINT_SETS], weights[SC_GLTF_MAX_JOINT_SETS];
    uint32_t first_target, target_count; /**< morph targets: range in sc_gltf_doc.targets */
    int32_t texcoord1; /**< TEXCOORD_1 accessor or -1 (textures whose texCoord is 1 read it) */
} sc_gltf_primitive;

/** One morph target of a primitive: its POSITION / NORMAL / TANGENT delta accessors or -1. */
typedef struct sc_gltf_target {
    int32_t position, normal, tangent;
} sc_gltf_target;

typedef struct sc_gltf_mesh {
    uint32_t first_primitive, primitive_count;
    uint32_t first_weight, weight_count; /**< mesh.weights: range in sc_gltf_doc.weights */
} sc_gltf_mesh;

/** glTF skin: joints (node indices) in sc_gltf_doc.skin_joints; inverseBindMatrices accessor
 *  or -1 (identity). */
typedef struct sc_gltf_skin {
    int32_t inverse_bind_matrices;
    uint32_t first_joint, joint_count;
} sc_gltf_skin;

typedef struct sc_gltf_texref {
    int32_t texture;   /**< index in textures, -1 when none */
    int32_t tex_coord; /**< TEXCOORD set (KHR_texture_transform's texCoord when it gives one) */
    /** KHR_texture_transform: uv' = T(offset) R(rotation) S(scale) uv; identity when absent. */
    float offset[2], rotation_rad, scale[2];
} sc_gltf_texref;

/** material.alphaMode */
enum { SC_GLTF_ALPHA_OPAQUE, SC_GLTF_ALPHA_MASK, SC_GLTF_ALPHA_BLEND };

typedef struct sc_gltf_material {
    char name[64];
    float base_color[4];
    sc_gltf_texref base_color_tex;
    float metallic, roughness;
    sc_gltf_texref metal_rough_tex;
    float emissive[3];
    float emissive_strength; /**< KHR_materials_emissive_strength, 1 when absent */
    sc_gltf_texref emissive_tex;
    float transmission;      /**< KHR_materials_transmission factor, 0 when absent */
    float ior;               /**< KHR_materials_ior, 1.5 when absent */
    sc_gltf_texref normal_tex;
    float normal_scale;      /**< normalTexture.scale, 1 when absent */
    bool unlit;              /**< KHR_materials_unlit */
    bool double_sided;
    /** KHR_materials_pbrSpecularGlossiness (converted to metal/rough by sc_scene.c). */
    bool spec_gloss;
    float diffuse[4], sg_specular[3], glossiness; /**< sg_: specularFactor of spec-gloss */
    sc_gltf_texref diffuse_tex, spec_gloss_tex;
    sc_gltf_texref transmission_tex; /**< KHR_materials_transmission transmissionTexture (R) */
    /** KHR_materials_specular: specularFactor (1 when absent), its texture (A),
     *  specularColorFactor (1, 1, 1 when absent) and its texture (sRGB rgb). */
    float specular;
    sc_gltf_texref specular_tex;
    float specular_color[3];
    sc_gltf_texref specular_color_tex;
    /** KHR_materials_clearcoat: factor (0 when absent, texture R), roughness (texture G). */
    float clearcoat, clearcoat_roughness;
    sc_gltf_texref clearcoat_tex, clearcoat_rough_tex;
    /** KHR_materials_sheen: colour (0 when absent, texture sRGB rgb), roughness (texture A). */
    float sheen_color[3], sheen_roughness;
    sc_gltf_texref sheen_color_tex, sheen_rough_tex;
    /** KHR_materials_volume: thicknessFactor (0 when absent: thin-walled), attenuation colour
     *  (1, 1, 1) and distance (0 when absent, meaning infinite). */
    float thickness, attenuation_color[3], attenuation_distance;
    int alpha_mode;          /**< SC_GLTF_ALPHA_* from alphaMode; anything else = OPAQUE */
    float alpha_cutoff;      /**< alphaCutoff, 0.5 when absent */
} sc_gltf_material;

typedef struct sc_gltf_texture {
    int32_t image; /**< index in images, -1 when none */
    /** Its sampler: wrap modes SC_GLTF_WRAP_* (REPEAT when absent); filters as in the file
     *  (NEAREST/LINEAR and the mipmap variants), -1 when absent. */
    int32_t wrap_s, wrap_t, mag_filter, min_filter;
} sc_gltf_texture;

typedef struct sc_gltf_image {
    uint32_t width, height;
    const uint8_t *rgba8; /**< NULL when it could not be read or decoded (sc_scene.c warns
                           *   when a material uses it) */
    bool missing;         /**< an external file that could not be read */
    char uri[160];        /**< for messages ("" for bufferView images) */
} sc_gltf_image;

typedef enum sc_gltf_light_type {
    SC_GLTF_LIGHT_OTHER,
    SC_GLTF_LIGHT_DIRECTIONAL,
    SC_GLTF_LIGHT_POINT,
    SC_GLTF_LIGHT_SPOT,
} sc_gltf_light_type;

typedef struct sc_gltf_light {
    sc_gltf_light_type type;
    float color[3];
    float intensity;
    float range;                          /**< metres; 0 = infinite (glTF: undefined) */
    float inner_cone_rad, outer_cone_rad; /**< spot.innerConeAngle / outerConeAngle */
} sc_gltf_light;

typedef struct sc_gltf_camera {
    bool perspective;
    float yfov_rad;     /**< perspective.yfov */
    float aspect_ratio; /**< perspective.aspectRatio, 0 when absent */
} sc_gltf_camera;

typedef struct sc_gltf_node {
    char name[64];
    int32_t mesh, camera, light, skin;
    bool has_weights; /**< morph target weights */
    uint32_t first_weight, weight_count; /**< node.weights: range in sc_gltf_doc.weights */
    bool has_matrix;
    float matrix[16]; /**< column-major, when has_matrix */
    float translation[3], rotation[4], scale[3];
    uint32_t first_child, child_count; /**< range in sc_gltf_doc.children */
    /** EXT_mesh_gpu_instancing attribute accessors (-1 when absent); `instanced` when the
     *  node has the extension. */
    bool instanced;
    int32_t inst_translation, inst_rotation, inst_scale;
} sc_gltf_node;

typedef enum sc_gltf_path {
    SC_GLTF_PATH_TRANSLATION,
    SC_GLTF_PATH_ROTATION,
    SC_GLTF_PATH_SCALE,
    SC_GLTF_PATH_WEIGHTS,
    SC_GLTF_PATH_OTHER,
} sc_gltf_path;

typedef enum sc_gltf_interp {
    SC_GLTF_INTERP_LINEAR,
    SC_GLTF_INTERP_STEP,
    SC_GLTF_INTERP_CUBICSPLINE,
    SC_GLTF_INTERP_OTHER,
} sc_gltf_interp;

typedef struct sc_gltf_channel {
    uint32_t animation, channel; /**< indices in the file, for messages */
    int32_t node;
    sc_gltf_path path;
    sc_gltf_interp interp;
    int32_t input, output; /**< accessors; -1 when the sampler index is invalid */
} sc_gltf_channel;

/** One glTF animation (a clip): its channels are the range [first_channel, +channel_count)
 *  of sc_gltf_doc.channels (every path, weights and unknown ones included). */
typedef struct sc_gltf_clip {
    char name[128]; /**< animations[i].name, "" when it has none */
    uint32_t first_channel, channel_count;
} sc_gltf_clip;

/** What the file holds beyond what the scene draws, for `xrsc scene info` (counted in the
 *  file, whether or not xrsc uses it). */
typedef struct sc_gltf_facts {
    uint32_t skin_count;          /**< skins */
    uint32_t morph_target_count;  /**< morph targets, summed over the primitives */
    uint32_t morph_mesh_count;    /**< meshes with at least one primitive with targets */
    char extensions_used[1024];     /**< extensionsUsed, comma-separated */
    char extensions_required[1024]; /**< extensionsRequired, comma-separated */
} sc_gltf_facts;

typedef struct sc_gltf_scene {
    uint32_t first_root, root_count; /**< range in sc_gltf_doc.roots */
    bool has_environment;
    float environment[3]; /**< extras.xrsc_environment */
} sc_gltf_scene;

typedef struct sc_gltf_doc {
    sc_gltf_buffer *buffers;     uint32_t buffer_count;
    sc_gltf_view *views;         uint32_t view_count;
    sc_gltf_accessor *accessors; uint32_t accessor_count;
    sc_gltf_primitive *primitives; uint32_t primitive_count;
    sc_gltf_mesh *meshes;        uint32_t mesh_count;
    sc_gltf_material *materials; uint32_t material_count;
    sc_gltf_texture *textures;   uint32_t texture_count;
    sc_gltf_image *images;       uint32_t image_count;
    sc_gltf_light *lights;       uint32_t light_count;
    sc_gltf_camera *cameras;     uint32_t camera_count;
    sc_gltf_node *nodes;         uint32_t node_count;
    int32_t *children;           uint32_t children_count;
    sc_gltf_channel *channels;   uint32_t channel_count;
    sc_gltf_scene *scenes;       uint32_t scene_count;
    int32_t *roots;              uint32_t roots_count;
    int32_t default_scene; /**< -1 when the file names none */
    sc_gltf_target *targets;     uint32_t target_count;
    float *weights;              uint32_t weight_count; /**< mesh and node morph weights */
    sc_gltf_skin *skins;         uint32_t skin_count;
    int32_t *skin_joints;        uint32_t skin_joint_count;
    sc_gltf_clip *clips;         uint32_t clip_count; /**< the file's animations, in order */
    sc_gltf_facts facts;
    /** Comma-separated names of ignored features, each once (see ::sc_gltf_note). */
    char unsupported[1024];
    /** Comma-separated optional extensions that are ignored, each once: one warning each. */
    char ignored_extensions[1024];
    void *impl; /**< owns buffers, images and meshopt-decoded buffer views */
} sc_gltf_doc;

/**
 * Parses glTF JSON or GLB bytes (GLB when data starts with "glTF"). name is used in
 * messages; external files are looked up in base_dir, and none are read when base_dir is
 * NULL. Before tinygltf sees the bytes: XRSC_ERROR_GLTF_NOT_GLTF (neither JSON nor GLB; the
 * message names the format it looks like), XRSC_ERROR_GLB_MAGIC (a .glb without the magic),
 * XRSC_ERROR_GLB_TRUNCATED (expected and actual length), XRSC_ERROR_GLTF_VERSION (glTF 1.0).
 * Errors: XRSC_ERROR_GLTF_PARSE (JSON/GLB syntax, with the line), _MISSING_BUFFER
 * (buffers[i].uri with the line of the uri), _UNSUPPORTED (extensionsRequired), _INVALID
 * (inconsistent structure, a meshopt buffer view that does not decode). A missing or
 * undecodable image is not an error (sc_gltf_image.rgba8 NULL). EXT_meshopt_compression
 * buffer views are decoded here (libmeshoptimizer, when built with it): their sc_gltf_view
 * points into a decoded buffer appended after the file's buffers.
 */
xrsc_result sc_gltf_parse(const char *name, const uint8_t *data, size_t size,
                          const char *base_dir, sc_gltf_doc **out, xrsc_diag *diag);
void sc_gltf_doc_destroy(sc_gltf_doc **doc);
/** Adds a feature name to doc->unsupported unless already listed. */
void sc_gltf_note(sc_gltf_doc *doc, const char *feature);
/** Adds an optional extension's name to doc->ignored_extensions unless already listed. */
void sc_gltf_note_extension(sc_gltf_doc *doc, const char *name);

#ifdef __cplusplus
}
#endif
