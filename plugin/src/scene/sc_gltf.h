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

typedef struct sc_gltf_primitive {
    int32_t mode; /**< glTF mode (default 4 filled in) */
    int32_t position, normal, tangent, texcoord0, indices, material; /**< accessor/material or -1 */
} sc_gltf_primitive;

typedef struct sc_gltf_mesh {
    uint32_t first_primitive, primitive_count;
} sc_gltf_mesh;

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
    int alpha_mode;          /**< SC_GLTF_ALPHA_* from alphaMode; anything else = OPAQUE */
    float alpha_cutoff;      /**< alphaCutoff, 0.5 when absent */
} sc_gltf_material;

typedef struct sc_gltf_texture {
    int32_t image; /**< index in images, -1 when none */
} sc_gltf_texture;

typedef struct sc_gltf_image {
    uint32_t width, height;
    const uint8_t *rgba8; /**< NULL when it could not be decoded (then a warning is noted) */
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
    bool has_matrix;
    float matrix[16]; /**< column-major, when has_matrix */
    float translation[3], rotation[4], scale[3];
    uint32_t first_child, child_count; /**< range in sc_gltf_doc.children */
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
    /** Comma-separated names of ignored features, each once (see ::sc_gltf_note). */
    char unsupported[1024];
    void *impl; /**< the tinygltf model that owns buffers and images */
} sc_gltf_doc;

/**
 * Parses glTF JSON or GLB bytes (GLB when data starts with "glTF"). name is used in
 * messages; external files are looked up in base_dir, and none are read when base_dir is
 * NULL. Errors: XRSC_ERROR_GLTF_PARSE (JSON/GLB syntax, with the line), _MISSING_BUFFER
 * (buffers[i].uri / images[i].uri with the line of the uri), _UNSUPPORTED
 * (extensionsRequired), _INVALID (inconsistent structure found by tinygltf).
 */
xrsc_result sc_gltf_parse(const char *name, const uint8_t *data, size_t size,
                          const char *base_dir, sc_gltf_doc **out, xrsc_diag *diag);
void sc_gltf_doc_destroy(sc_gltf_doc **doc);
/** Adds a feature name to doc->unsupported unless already listed. */
void sc_gltf_note(sc_gltf_doc *doc, const char *feature);

#ifdef __cplusplus
}
#endif
