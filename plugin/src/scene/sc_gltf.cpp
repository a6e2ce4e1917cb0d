// SPDX-License-Identifier: MIT
/**
 * @file sc_gltf.cpp
 * @brief The one C++ file: parses glTF/GLB with tinygltf and fills the plain C ::sc_gltf_doc.
 *
 * tinygltf is compiled here (rather than linking Debian's libtinygltf.so) so that the
 * sanitizer and fuzzing builds instrument the parser too. Before tinygltf sees the text, the
 * JSON is checked once with nlohmann::json: syntax errors get their line, nesting depth is
 * bounded (tinygltf converts extras recursively), extensionsRequired is checked, and buffer
 * views are checked against their buffers (tinygltf 2.7.0 reads image bufferViews unchecked).
 */
// stb_image is compiled static here so another module may compile its own copy; xrsc never
// writes glTF, so stb_image_write is left out.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#include <tiny_gltf.h>

#include "sc_gltf.h"
#include "u_diag.h"

#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <new>
#include <string>
#include <vector>

namespace {

/** JSON nesting deeper than this is rejected (real glTF files nest < 10 levels). */
const int kMaxJsonDepth = 64;
/** Images with more pixels than this are not decoded (8k x 8k). */
const uint64_t kMaxImagePixels = 8192ull * 8192ull;
/** External files larger than this are not read. */
const uint64_t kMaxFileBytes = 2ull << 30;

/** Extensions xrsc renders; any other one in extensionsRequired is an error. */
const char *const kSupportedExtensions[] = {
    "KHR_materials_emissive_strength", "KHR_materials_transmission", "KHR_materials_ior",
    "KHR_lights_punctual", "KHR_mesh_quantization", "KHR_materials_unlit",
    "KHR_texture_transform",
#ifdef XRSC_HAVE_DRACO
    "KHR_draco_mesh_compression", // decoded by tinygltf with libdraco (CMake: XRSC_DRACO)
#endif
};

bool is_supported_extension(const std::string &name)
{
    for (const char *s : kSupportedExtensions)
        if (name == s) return true;
    return false;
}

enum image_status { IMAGE_NOT_READ = 0, IMAGE_DECODED, IMAGE_UNDECODABLE };

/** Per-load state shared with tinygltf's callbacks (no globals). */
struct load_ctx {
    bool allow_fs = false;
    int missing_files = 0;
    std::string last_missing;
    std::vector<int> image_status;
};

bool fs_file_exists(const std::string &path, void *user)
{
    load_ctx *ctx = static_cast<load_ctx *>(user);
    struct stat st;
    if (ctx->allow_fs && stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode)) return true;
    ctx->missing_files++;
    ctx->last_missing = path;
    return false;
}

std::string fs_expand(const std::string &path, void *) { return path; }

bool fs_read(std::vector<unsigned char> *out, std::string *err, const std::string &path,
             void *user)
{
    load_ctx *ctx = static_cast<load_ctx *>(user);
    if (!ctx->allow_fs) return false;
    FILE *f = fopen(path.c_str(), "rb");
    if (!f) {
        if (err) *err = "cannot open";
        return false;
    }
    bool ok = fseek(f, 0, SEEK_END) == 0;
    long size = ok ? ftell(f) : -1;
    ok = ok && size >= 0 && (uint64_t)size <= kMaxFileBytes && fseek(f, 0, SEEK_SET) == 0;
    if (ok) {
        out->resize((size_t)size);
        ok = size == 0 || fread(out->data(), 1, (size_t)size, f) == (size_t)size;
    }
    fclose(f);
    if (!ok && err) *err = "cannot read";
    return ok;
}

bool fs_write(std::string *, const std::string &, const std::vector<unsigned char> &, void *)
{
    return false;
}

/** Decodes any image stb knows to RGBA8. Never fails the load: an undecodable image is
 *  recorded and named in the unsupported-features warning. */
bool load_image(tinygltf::Image *image, const int image_idx, std::string *, std::string *, int,
                int, const unsigned char *bytes, int size, void *user)
{
    load_ctx *ctx = static_cast<load_ctx *>(user);
    if (image_idx < 0) return true;
    if ((size_t)image_idx >= ctx->image_status.size())
        ctx->image_status.resize((size_t)image_idx + 1, IMAGE_NOT_READ);
    ctx->image_status[(size_t)image_idx] = IMAGE_UNDECODABLE;
    int w = 0, h = 0, comp = 0;
    if (!bytes || size <= 0 || !stbi_info_from_memory(bytes, size, &w, &h, &comp)) return true;
    if (w <= 0 || h <= 0 || (uint64_t)w * (uint64_t)h > kMaxImagePixels) return true;
    unsigned char *px = stbi_load_from_memory(bytes, size, &w, &h, &comp, 4);
    if (!px) return true;
    image->width = w;
    image->height = h;
    image->component = 4;
    image->bits = 8;
    image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
    image->image.assign(px, px + (size_t)w * (size_t)h * 4);
    stbi_image_free(px);
    ctx->image_status[(size_t)image_idx] = IMAGE_DECODED;
    return true;
}

/** 1-based line of byte offset pos in text. */
int line_of_offset(const char *text, size_t size, size_t pos)
{
    int line = 1;
    for (size_t i = 0; i < pos && i < size; i++)
        if (text[i] == '\n') line++;
    return line;
}

/** Line of the first occurrence of needle in text, 0 when not found. */
int line_of(const char *text, size_t size, const std::string &needle)
{
    if (needle.empty() || !text) return 0;
    std::string hay(text, size);
    size_t pos = hay.find(needle);
    return pos == std::string::npos ? 0 : line_of_offset(text, size, pos);
}

/** Maximum nesting depth of JSON text, counting brackets outside strings. */
int json_depth(const char *text, size_t size)
{
    int depth = 0, max_depth = 0;
    bool in_string = false;
    for (size_t i = 0; i < size; i++) {
        char c = text[i];
        if (in_string) {
            if (c == '\\') i++;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > max_depth) max_depth = depth;
        } else if (c == ']' || c == '}') {
            depth--;
        }
    }
    return max_depth;
}

uint32_t rd_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

float clamp_float(double v)
{
    if (!std::isfinite(v)) return 0.0f;
    if (v > 3.0e38) return 3.0e38f;
    if (v < -3.0e38) return -3.0e38f;
    return (float)v;
}

/** A number Value as int32, -1 when it is not a number or out of range. */
int32_t value_index(const tinygltf::Value &v)
{
    if (!v.IsNumber()) return -1;
    double d = v.GetNumberAsDouble();
    if (!(d >= 0.0 && d < 2147483647.0)) return -1;
    return (int32_t)d;
}

double value_number(const tinygltf::Value &v, const char *key, double def)
{
    if (!v.IsObject() || !v.Has(key)) return def;
    const tinygltf::Value &x = v.Get(key);
    return x.IsNumber() ? x.GetNumberAsDouble() : def;
}

template <typename T> T *alloc_array(size_t n)
{
    if (n == 0) return nullptr;
    return static_cast<T *>(calloc(n, sizeof(T)));
}

void copy_name(char *dst, size_t cap, const std::string &src)
{
    snprintf(dst, cap, "%s", src.c_str());
}

/** A texture reference with its KHR_texture_transform (TextureInfo, NormalTextureInfo and
 *  OcclusionTextureInfo are distinct types with the same fields). */
template <typename Info> sc_gltf_texref texref(sc_gltf_doc *doc, const Info &ti)
{
    sc_gltf_texref r;
    r.texture = ti.index;
    r.tex_coord = ti.texCoord;
    r.offset[0] = r.offset[1] = 0.0f;
    r.rotation_rad = 0.0f;
    r.scale[0] = r.scale[1] = 1.0f;
    auto x = ti.extensions.find("KHR_texture_transform");
    if (x != ti.extensions.end() && x->second.IsObject()) {
        const tinygltf::Value &v = x->second;
        const char *keys[2] = {"offset", "scale"};
        float *dst[2] = {r.offset, r.scale};
        for (int k = 0; k < 2; k++) {
            if (!v.Has(keys[k])) continue;
            const tinygltf::Value &a = v.Get(keys[k]);
            if (a.IsArray() && a.ArrayLen() == 2 && a.Get(0).IsNumber() && a.Get(1).IsNumber())
                for (int c = 0; c < 2; c++) dst[k][c] = clamp_float(a.Get(c).GetNumberAsDouble());
        }
        r.rotation_rad = clamp_float(value_number(v, "rotation", 0.0));
        if (v.Has("texCoord") && v.Get("texCoord").IsNumber())
            r.tex_coord = value_index(v.Get("texCoord"));
    }
    if (ti.index >= 0 && r.tex_coord != 0) sc_gltf_note(doc, "texCoord sets other than 0");
    return r;
}

/** What the JSON pre-check learns and keeps for messages. */
struct precheck {
    std::vector<std::string> buffer_uris;
    std::vector<std::string> image_uris;
};

/** Checks what tinygltf does not (see the file comment). Returns XRSC_OK or fills diag. */
xrsc_result precheck_json(const char *name, const char *text, size_t size, precheck *pc,
                          xrsc_diag *diag)
{
    using nlohmann::json;
    if (json_depth(text, size) > kMaxJsonDepth)
        return u_diag_set(diag, XRSC_ERROR_GLTF_PARSE, name, 0, "",
                          "JSON nests deeper than %d levels", kMaxJsonDepth);
    json j;
    try {
        j = json::parse(text, text + size);
    } catch (const json::parse_error &e) {
        int line = line_of_offset(text, size, e.byte > 0 ? e.byte - 1 : 0);
        return u_diag_set(diag, XRSC_ERROR_GLTF_PARSE, name, line, "", "%s", e.what());
    } catch (const std::exception &e) {
        return u_diag_set(diag, XRSC_ERROR_GLTF_PARSE, name, 0, "", "%s", e.what());
    }
    if (!j.is_object())
        return u_diag_set(diag, XRSC_ERROR_GLTF_PARSE, name, 1, "",
                          "the root of a glTF file must be a JSON object");

    auto it = j.find("extensionsRequired");
    if (it != j.end() && it->is_array()) {
        for (const json &e : *it) {
            std::string ext = e.is_string() ? e.get<std::string>() : std::string("(not a string)");
            if (ext == "KHR_draco_mesh_compression" && !is_supported_extension(ext))
                // Built without libdraco (CMake found no draco package, or XRSC_DRACO=OFF):
                // the file needs re-exporting without mesh compression.
                return u_diag_set(diag, XRSC_ERROR_GLTF_UNSUPPORTED, name,
                                  line_of(text, size, "\"extensionsRequired\""),
                                  "extensionsRequired",
                                  "required extension KHR_draco_mesh_compression (Draco-"
                                  "compressed meshes) is not supported by this build of "
                                  "xrsc (built without libdraco-dev); export the file "
                                  "without mesh compression");
            if (!is_supported_extension(ext))
                return u_diag_set(diag, XRSC_ERROR_GLTF_UNSUPPORTED, name,
                                  line_of(text, size, "\"extensionsRequired\""),
                                  "extensionsRequired",
                                  "required extension %s is not supported by xrsc", ext.c_str());
        }
    }

    std::vector<uint64_t> buffer_len;
    it = j.find("buffers");
    if (it != j.end() && it->is_array()) {
        for (const json &b : *it) {
            uint64_t len = 0;
            std::string uri;
            if (b.is_object()) {
                auto l = b.find("byteLength");
                if (l != b.end() && l->is_number_unsigned()) len = l->get<uint64_t>();
                auto u = b.find("uri");
                if (u != b.end() && u->is_string()) uri = u->get<std::string>();
            }
            buffer_len.push_back(len);
            pc->buffer_uris.push_back(uri);
        }
    }
    it = j.find("images");
    if (it != j.end() && it->is_array()) {
        for (const json &im : *it) {
            std::string uri;
            if (im.is_object()) {
                auto u = im.find("uri");
                if (u != im.end() && u->is_string()) uri = u->get<std::string>();
            }
            pc->image_uris.push_back(uri);
        }
    }
    it = j.find("bufferViews");
    if (it != j.end() && it->is_array()) {
        size_t i = 0;
        for (const json &v : *it) {
            char field[64];
            snprintf(field, sizeof field, "bufferViews[%zu]", i);
            uint64_t off = 0, len = 0;
            int64_t buf = -1;
            if (v.is_object()) {
                auto x = v.find("byteOffset");
                if (x != v.end() && x->is_number_unsigned()) off = x->get<uint64_t>();
                x = v.find("byteLength");
                if (x != v.end() && x->is_number_unsigned()) len = x->get<uint64_t>();
                x = v.find("buffer");
                if (x != v.end() && x->is_number_integer()) buf = x->get<int64_t>();
            }
            if (buf < 0 || (uint64_t)buf >= buffer_len.size())
                return u_diag_set(diag, XRSC_ERROR_GLTF_INVALID, name, 0, field,
                                  "buffer %lld does not exist", (long long)buf);
            if (off > buffer_len[(size_t)buf] || len > buffer_len[(size_t)buf] - off)
                return u_diag_set(diag, XRSC_ERROR_GLTF_INVALID, name, 0, field,
                                  "bytes %llu..%llu overrun buffer %lld of %llu bytes",
                                  (unsigned long long)off, (unsigned long long)(off + len),
                                  (long long)buf, (unsigned long long)buffer_len[(size_t)buf]);
            i++;
        }
    }
    return XRSC_OK;
}

/** Fills doc from the loaded model. Returns XRSC_OK or an error for malformed node data. */
xrsc_result fill_doc(const char *name, tinygltf::Model &m, const load_ctx &ctx, sc_gltf_doc *doc,
                     xrsc_diag *diag)
{
    char field[96];
    for (const std::string &ext : m.extensionsUsed)
        if (!is_supported_extension(ext)) sc_gltf_note(doc, ext.c_str());
    if (!m.skins.empty()) sc_gltf_note(doc, "skins");

    doc->buffer_count = (uint32_t)m.buffers.size();
    doc->buffers = alloc_array<sc_gltf_buffer>(m.buffers.size());
    for (size_t i = 0; i < m.buffers.size(); i++) {
        doc->buffers[i].data = m.buffers[i].data.data();
        doc->buffers[i].size = m.buffers[i].data.size();
    }
    doc->view_count = (uint32_t)m.bufferViews.size();
    doc->views = alloc_array<sc_gltf_view>(m.bufferViews.size());
    for (size_t i = 0; i < m.bufferViews.size(); i++) {
        const tinygltf::BufferView &v = m.bufferViews[i];
        doc->views[i] = {v.buffer, v.byteOffset, v.byteLength, v.byteStride};
    }
    doc->accessor_count = (uint32_t)m.accessors.size();
    doc->accessors = alloc_array<sc_gltf_accessor>(m.accessors.size());
    for (size_t i = 0; i < m.accessors.size(); i++) {
        const tinygltf::Accessor &a = m.accessors[i];
        sc_gltf_accessor *o = &doc->accessors[i];
        o->view = a.bufferView;
        o->offset = a.byteOffset;
        o->component_type = a.componentType;
        int32_t nc = tinygltf::GetNumComponentsInType((uint32_t)a.type);
        o->components = nc > 0 ? (uint32_t)nc : 0;
        o->normalized = a.normalized;
        o->count = a.count;
        o->sparse = a.sparse.isSparse;
        if (a.sparse.isSparse) {
            o->sparse_count = a.sparse.count > 0 ? (size_t)a.sparse.count : 0;
            o->sparse_indices_view = a.sparse.indices.bufferView;
            o->sparse_indices_type = a.sparse.indices.componentType;
            o->sparse_indices_offset =
                a.sparse.indices.byteOffset > 0 ? (size_t)a.sparse.indices.byteOffset : 0;
            o->sparse_values_view = a.sparse.values.bufferView;
            o->sparse_values_offset =
                a.sparse.values.byteOffset > 0 ? (size_t)a.sparse.values.byteOffset : 0;
        }
    }

    size_t prim_total = 0;
    for (const tinygltf::Mesh &mesh : m.meshes) prim_total += mesh.primitives.size();
    doc->primitive_count = (uint32_t)prim_total;
    doc->primitives = alloc_array<sc_gltf_primitive>(prim_total);
    doc->mesh_count = (uint32_t)m.meshes.size();
    doc->meshes = alloc_array<sc_gltf_mesh>(m.meshes.size());
    size_t p = 0;
    for (size_t i = 0; i < m.meshes.size(); i++) {
        doc->meshes[i].first_primitive = (uint32_t)p;
        doc->meshes[i].primitive_count = (uint32_t)m.meshes[i].primitives.size();
        for (const tinygltf::Primitive &pr : m.meshes[i].primitives) {
            sc_gltf_primitive *o = &doc->primitives[p++];
            o->mode = pr.mode < 0 ? SC_GLTF_MODE_TRIANGLES : pr.mode;
            o->indices = pr.indices;
            o->material = pr.material;
            o->position = o->normal = o->tangent = o->texcoord0 = -1;
            auto a = pr.attributes.find("POSITION");
            if (a != pr.attributes.end()) o->position = a->second;
            a = pr.attributes.find("NORMAL");
            if (a != pr.attributes.end()) o->normal = a->second;
            a = pr.attributes.find("TANGENT");
            if (a != pr.attributes.end()) o->tangent = a->second;
            a = pr.attributes.find("TEXCOORD_0");
            if (a != pr.attributes.end()) o->texcoord0 = a->second;
            if (!pr.targets.empty()) sc_gltf_note(doc, "morph targets");
        }
    }

    doc->material_count = (uint32_t)m.materials.size();
    doc->materials = alloc_array<sc_gltf_material>(m.materials.size());
    for (size_t i = 0; i < m.materials.size(); i++) {
        const tinygltf::Material &mt = m.materials[i];
        const tinygltf::PbrMetallicRoughness &pbr = mt.pbrMetallicRoughness;
        sc_gltf_material *o = &doc->materials[i];
        copy_name(o->name, sizeof o->name, mt.name);
        for (int c = 0; c < 4; c++)
            o->base_color[c] = c < (int)pbr.baseColorFactor.size()
                                   ? clamp_float(pbr.baseColorFactor[(size_t)c])
                                   : 1.0f;
        o->base_color_tex = texref(doc, pbr.baseColorTexture);
        o->metallic = clamp_float(pbr.metallicFactor);
        o->roughness = clamp_float(pbr.roughnessFactor);
        o->metal_rough_tex = texref(doc, pbr.metallicRoughnessTexture);
        for (int c = 0; c < 3; c++)
            o->emissive[c] = c < (int)mt.emissiveFactor.size()
                                 ? clamp_float(mt.emissiveFactor[(size_t)c])
                                 : 0.0f;
        o->emissive_tex = texref(doc, mt.emissiveTexture);
        o->emissive_strength = 1.0f;
        o->ior = 1.5f;
        o->double_sided = mt.doubleSided;
        o->normal_tex = texref(doc, mt.normalTexture);
        o->normal_scale = clamp_float(mt.normalTexture.scale);
        // occlusionTexture is deliberately not used: it approximates the ambient occlusion
        // that the path tracer computes itself (multiplying it in would darken twice).
        // alphaMode (glTF 2.0 §3.9.4): anything but MASK / BLEND is OPAQUE, as in viewers.
        o->alpha_mode = mt.alphaMode == "MASK"    ? SC_GLTF_ALPHA_MASK
                        : mt.alphaMode == "BLEND" ? SC_GLTF_ALPHA_BLEND
                                                  : SC_GLTF_ALPHA_OPAQUE;
        o->alpha_cutoff = clamp_float(mt.alphaCutoff);
        for (const auto &ext : mt.extensions) {
            const tinygltf::Value &v = ext.second;
            if (ext.first == "KHR_materials_emissive_strength") {
                o->emissive_strength = clamp_float(value_number(v, "emissiveStrength", 1.0));
            } else if (ext.first == "KHR_materials_transmission") {
                o->transmission = clamp_float(value_number(v, "transmissionFactor", 0.0));
                if (v.IsObject() && v.Has("transmissionTexture"))
                    sc_gltf_note(doc, "transmissionTexture");
            } else if (ext.first == "KHR_materials_unlit") {
                o->unlit = true;
            } else if (ext.first == "KHR_materials_ior") {
                o->ior = clamp_float(value_number(v, "ior", 1.5));
            } else {
                sc_gltf_note(doc, ext.first.c_str());
            }
        }
    }

    doc->texture_count = (uint32_t)m.textures.size();
    doc->textures = alloc_array<sc_gltf_texture>(m.textures.size());
    for (size_t i = 0; i < m.textures.size(); i++) doc->textures[i].image = m.textures[i].source;

    doc->image_count = (uint32_t)m.images.size();
    doc->images = alloc_array<sc_gltf_image>(m.images.size());
    for (size_t i = 0; i < m.images.size(); i++) {
        const tinygltf::Image &im = m.images[i];
        bool ok = i < ctx.image_status.size() && ctx.image_status[i] == IMAGE_DECODED &&
                  im.width > 0 && im.height > 0 &&
                  im.image.size() == (size_t)im.width * (size_t)im.height * 4;
        if (ok) {
            doc->images[i].width = (uint32_t)im.width;
            doc->images[i].height = (uint32_t)im.height;
            doc->images[i].rgba8 = im.image.data();
        } else {
            sc_gltf_note(doc, "undecodable images");
        }
    }

    doc->light_count = (uint32_t)m.lights.size();
    doc->lights = alloc_array<sc_gltf_light>(m.lights.size());
    for (size_t i = 0; i < m.lights.size(); i++) {
        const tinygltf::Light &l = m.lights[i];
        sc_gltf_light *o = &doc->lights[i];
        o->type = l.type == "directional" ? SC_GLTF_LIGHT_DIRECTIONAL
                  : l.type == "point"     ? SC_GLTF_LIGHT_POINT
                  : l.type == "spot"      ? SC_GLTF_LIGHT_SPOT
                                          : SC_GLTF_LIGHT_OTHER;
        for (int c = 0; c < 3; c++)
            o->color[c] = c < (int)l.color.size() ? clamp_float(l.color[(size_t)c]) : 1.0f;
        o->intensity = clamp_float(l.intensity);
    }

    doc->camera_count = (uint32_t)m.cameras.size();
    doc->cameras = alloc_array<sc_gltf_camera>(m.cameras.size());
    for (size_t i = 0; i < m.cameras.size(); i++) {
        doc->cameras[i].perspective = m.cameras[i].type == "perspective";
        doc->cameras[i].yfov_rad = clamp_float(m.cameras[i].perspective.yfov);
        doc->cameras[i].aspect_ratio = clamp_float(m.cameras[i].perspective.aspectRatio);
    }

    size_t child_total = 0;
    for (const tinygltf::Node &n : m.nodes) child_total += n.children.size();
    doc->children_count = (uint32_t)child_total;
    doc->children = alloc_array<int32_t>(child_total);
    doc->node_count = (uint32_t)m.nodes.size();
    doc->nodes = alloc_array<sc_gltf_node>(m.nodes.size());
    size_t c = 0;
    for (size_t i = 0; i < m.nodes.size(); i++) {
        const tinygltf::Node &n = m.nodes[i];
        sc_gltf_node *o = &doc->nodes[i];
        copy_name(o->name, sizeof o->name, n.name);
        o->mesh = n.mesh;
        o->camera = n.camera;
        o->skin = n.skin;
        o->has_weights = !n.weights.empty();
        o->light = -1;
        auto le = n.extensions.find("KHR_lights_punctual");
        if (le != n.extensions.end() && le->second.IsObject() && le->second.Has("light"))
            o->light = value_index(le->second.Get("light"));
        o->rotation[3] = 1.0f;
        o->scale[0] = o->scale[1] = o->scale[2] = 1.0f;
        if (!n.matrix.empty()) {
            if (n.matrix.size() != 16) {
                snprintf(field, sizeof field, "nodes[%zu].matrix", i);
                return u_diag_set(diag, XRSC_ERROR_GLTF_INVALID, name, 0, field,
                                  "matrix has %zu numbers, not 16", n.matrix.size());
            }
            o->has_matrix = true;
            for (int k = 0; k < 16; k++) o->matrix[k] = clamp_float(n.matrix[(size_t)k]);
        }
        struct {
            const std::vector<double> *v;
            float *dst;
            size_t n;
            const char *what;
        } trs[] = {{&n.translation, o->translation, 3, "translation"},
                   {&n.rotation, o->rotation, 4, "rotation"},
                   {&n.scale, o->scale, 3, "scale"}};
        for (const auto &t : trs) {
            if (t.v->empty()) continue;
            if (t.v->size() != t.n) {
                snprintf(field, sizeof field, "nodes[%zu].%s", i, t.what);
                return u_diag_set(diag, XRSC_ERROR_GLTF_INVALID, name, 0, field,
                                  "%s has %zu numbers, not %zu", t.what, t.v->size(), t.n);
            }
            for (size_t k = 0; k < t.n; k++) t.dst[k] = clamp_float((*t.v)[k]);
        }
        o->first_child = (uint32_t)c;
        o->child_count = (uint32_t)n.children.size();
        for (int ch : n.children) doc->children[c++] = ch;
    }

    size_t chan_total = 0;
    for (const tinygltf::Animation &a : m.animations) chan_total += a.channels.size();
    doc->channel_count = (uint32_t)chan_total;
    doc->channels = alloc_array<sc_gltf_channel>(chan_total);
    c = 0;
    for (size_t ai = 0; ai < m.animations.size(); ai++) {
        const tinygltf::Animation &a = m.animations[ai];
        for (size_t ci = 0; ci < a.channels.size(); ci++) {
            const tinygltf::AnimationChannel &ch = a.channels[ci];
            sc_gltf_channel *o = &doc->channels[c++];
            o->animation = (uint32_t)ai;
            o->channel = (uint32_t)ci;
            o->node = ch.target_node;
            o->path = ch.target_path == "translation" ? SC_GLTF_PATH_TRANSLATION
                      : ch.target_path == "rotation"  ? SC_GLTF_PATH_ROTATION
                      : ch.target_path == "scale"     ? SC_GLTF_PATH_SCALE
                      : ch.target_path == "weights"   ? SC_GLTF_PATH_WEIGHTS
                                                      : SC_GLTF_PATH_OTHER;
            o->input = o->output = -1;
            o->interp = SC_GLTF_INTERP_OTHER;
            if (ch.sampler >= 0 && (size_t)ch.sampler < a.samplers.size()) {
                const tinygltf::AnimationSampler &s = a.samplers[(size_t)ch.sampler];
                o->input = s.input;
                o->output = s.output;
                o->interp = s.interpolation == "LINEAR"        ? SC_GLTF_INTERP_LINEAR
                            : s.interpolation == "STEP"        ? SC_GLTF_INTERP_STEP
                            : s.interpolation == "CUBICSPLINE" ? SC_GLTF_INTERP_CUBICSPLINE
                                                               : SC_GLTF_INTERP_OTHER;
            }
        }
    }

    size_t root_total = 0;
    for (const tinygltf::Scene &s : m.scenes) root_total += s.nodes.size();
    doc->roots_count = (uint32_t)root_total;
    doc->roots = alloc_array<int32_t>(root_total);
    doc->scene_count = (uint32_t)m.scenes.size();
    doc->scenes = alloc_array<sc_gltf_scene>(m.scenes.size());
    c = 0;
    for (size_t i = 0; i < m.scenes.size(); i++) {
        const tinygltf::Scene &s = m.scenes[i];
        sc_gltf_scene *o = &doc->scenes[i];
        o->first_root = (uint32_t)c;
        o->root_count = (uint32_t)s.nodes.size();
        for (int r : s.nodes) doc->roots[c++] = r;
        if (s.extras.IsObject() && s.extras.Has("xrsc_environment")) {
            const tinygltf::Value &e = s.extras.Get("xrsc_environment");
            if (e.IsArray() && e.ArrayLen() == 3 && e.Get(0).IsNumber() &&
                e.Get(1).IsNumber() && e.Get(2).IsNumber()) {
                o->has_environment = true;
                for (int k = 0; k < 3; k++)
                    o->environment[k] = clamp_float(e.Get(k).GetNumberAsDouble());
            } else {
                U_LOG_W("%s: scenes[%zu].extras.xrsc_environment is not [r, g, b]; ignored",
                        name, i);
            }
        }
    }
    doc->default_scene = m.defaultScene;

    bool oom = (m.buffers.size() && !doc->buffers) || (m.bufferViews.size() && !doc->views) ||
               (m.accessors.size() && !doc->accessors) || (prim_total && !doc->primitives) ||
               (m.meshes.size() && !doc->meshes) || (m.materials.size() && !doc->materials) ||
               (m.textures.size() && !doc->textures) || (m.images.size() && !doc->images) ||
               (m.lights.size() && !doc->lights) || (m.cameras.size() && !doc->cameras) ||
               (child_total && !doc->children) || (m.nodes.size() && !doc->nodes) ||
               (chan_total && !doc->channels) || (root_total && !doc->roots) ||
               (m.scenes.size() && !doc->scenes);
    if (oom) return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, name, 0, "", "out of memory");
    return XRSC_OK;
}

bool is_data_uri(const std::string &uri) { return uri.compare(0, 5, "data:") == 0; }

xrsc_result parse(const char *name, const uint8_t *data, size_t size, const char *base_dir,
                  sc_gltf_doc **out, xrsc_diag *diag)
{
    if (size > std::numeric_limits<unsigned int>::max())
        return u_diag_set(diag, XRSC_ERROR_FILE_TOO_LARGE, name, 0, "",
                          "%zu bytes is more than tinygltf can read", size);
    if (size == 0) return u_diag_set(diag, XRSC_ERROR_EMPTY_FILE, name, 0, "", "file is empty");

    bool glb = size >= 4 && memcmp(data, "glTF", 4) == 0;
    const char *json_text = reinterpret_cast<const char *>(data);
    size_t json_size = size;
    if (glb) {
        // GLB: 12-byte header, then the JSON chunk (length, type "JSON", bytes).
        const uint32_t kChunkJson = 0x4E4F534Au;
        if (size < 20 || rd_u32(data + 16) != kChunkJson || rd_u32(data + 12) > size - 20)
            return u_diag_set(diag, XRSC_ERROR_GLTF_PARSE, name, 0, "",
                              "GLB header or JSON chunk is malformed");
        json_text = reinterpret_cast<const char *>(data + 20);
        json_size = rd_u32(data + 12);
    }
    precheck pc;
    xrsc_result r = precheck_json(name, json_text, json_size, &pc, diag);
    if (r != XRSC_OK) return r;

    load_ctx ctx;
    ctx.allow_fs = base_dir != nullptr;
    tinygltf::TinyGLTF loader;
    tinygltf::FsCallbacks fs = {fs_file_exists, fs_expand, fs_read, fs_write, &ctx};
    loader.SetFsCallbacks(fs);
    loader.SetImageLoader(load_image, &ctx);
    std::unique_ptr<tinygltf::Model> model(new tinygltf::Model());
    std::string err, warn, dir = base_dir ? base_dir : "";
    bool ok;
    try {
        ok = glb ? loader.LoadBinaryFromMemory(model.get(), &err, &warn, data,
                                               (unsigned int)size, dir)
                 : loader.LoadASCIIFromString(model.get(), &err, &warn, json_text,
                                              (unsigned int)json_size, dir);
    } catch (const std::bad_alloc &) {
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, name, 0, "", "out of memory");
    } catch (const std::exception &e) {
        err = e.what();
        ok = false;
    }
    while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
    if (!ok) {
        if (err.find("File not found") != std::string::npos ||
            err.find("File read error") != std::string::npos) {
            size_t b = model->buffers.size();
            std::string uri = b < pc.buffer_uris.size() ? pc.buffer_uris[b] : "";
            char field[64];
            snprintf(field, sizeof field, "buffers[%zu].uri", b);
            return u_diag_set(diag, XRSC_ERROR_GLTF_MISSING_BUFFER, name,
                              line_of(json_text, json_size, "\"" + uri + "\""), field,
                              "buffer file '%s' cannot be read%s", uri.c_str(),
                              base_dir ? "" : " (no base folder to read files from)");
        }
        bool syntax = err.find("JSON") != std::string::npos ||
                      err.find("GLB") != std::string::npos ||
                      err.find("glTF") != std::string::npos ||
                      err.find("not found in .gltf") != std::string::npos ||
                      err.find("asset") != std::string::npos;
        return u_diag_set(diag, syntax ? XRSC_ERROR_GLTF_PARSE : XRSC_ERROR_GLTF_INVALID, name,
                          0, "", "tinygltf: %s", err.c_str());
    }
    if (!warn.empty()) U_LOG_D("%s: tinygltf: %s", name, warn.c_str());

    // A missing image file is only a warning to tinygltf; for xrsc it is an error.
    for (size_t i = 0; i < model->images.size(); i++) {
        const tinygltf::Image &im = model->images[i];
        bool read = i < ctx.image_status.size() && ctx.image_status[i] != IMAGE_NOT_READ;
        if (!read && im.bufferView < 0 && !im.uri.empty() && !is_data_uri(im.uri)) {
            char field[64];
            snprintf(field, sizeof field, "images[%zu].uri", i);
            return u_diag_set(diag, XRSC_ERROR_GLTF_MISSING_BUFFER, name,
                              line_of(json_text, json_size, "\"" + im.uri + "\""), field,
                              "image file '%s' cannot be read", im.uri.c_str());
        }
    }

    sc_gltf_doc *doc = static_cast<sc_gltf_doc *>(calloc(1, sizeof(sc_gltf_doc)));
    if (!doc) return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, name, 0, "", "out of memory");
    doc->impl = model.release();
    r = fill_doc(name, *static_cast<tinygltf::Model *>(doc->impl), ctx, doc, diag);
    if (r != XRSC_OK) {
        sc_gltf_doc_destroy(&doc);
        return r;
    }
    *out = doc;
    return XRSC_OK;
}

} // namespace

extern "C" xrsc_result sc_gltf_parse(const char *name, const uint8_t *data, size_t size,
                                     const char *base_dir, sc_gltf_doc **out, xrsc_diag *diag)
{
    *out = nullptr;
    try {
        return parse(name, data, size, base_dir, out, diag);
    } catch (const std::bad_alloc &) {
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, name, 0, "", "out of memory");
    } catch (const std::exception &e) {
        return u_diag_set(diag, XRSC_ERROR_GLTF_INVALID, name, 0, "", "%s", e.what());
    }
}

extern "C" void sc_gltf_doc_destroy(sc_gltf_doc **pdoc)
{
    if (!pdoc || !*pdoc) return;
    sc_gltf_doc *doc = *pdoc;
    delete static_cast<tinygltf::Model *>(doc->impl);
    free(doc->buffers);
    free(doc->views);
    free(doc->accessors);
    free(doc->primitives);
    free(doc->meshes);
    free(doc->materials);
    free(doc->textures);
    free(doc->images);
    free(doc->lights);
    free(doc->cameras);
    free(doc->nodes);
    free(doc->children);
    free(doc->channels);
    free(doc->scenes);
    free(doc->roots);
    free(doc);
    *pdoc = nullptr;
}

extern "C" void sc_gltf_note(sc_gltf_doc *doc, const char *feature)
{
    size_t n = strlen(doc->unsupported), f = strlen(feature);
    // Look for the name as a whole list entry.
    const char *p = doc->unsupported;
    while ((p = strstr(p, feature)) != nullptr) {
        bool start = p == doc->unsupported || (p >= doc->unsupported + 2 && p[-2] == ',');
        bool end = p[f] == '\0' || p[f] == ',';
        if (start && end) return;
        p += f;
    }
    if (n + f + 3 >= sizeof doc->unsupported) return;
    snprintf(doc->unsupported + n, sizeof doc->unsupported - n, "%s%s", n ? ", " : "", feature);
}
