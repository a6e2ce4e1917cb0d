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
 * Before that, the bytes are checked to be glTF 2.0 at all (check_container: another format
 * is named, a GLB's lengths are checked against the file, glTF 1.0 is refused by name). After
 * tinygltf, EXT_meshopt_compression buffer views are decoded with libmeshoptimizer (tinygltf
 * does not know the extension; its fallback buffers without a uri get a stand-in data uri so
 * that tinygltf accepts them).
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

#ifdef XRSC_HAVE_MESHOPT
#include <meshoptimizer.h>
#endif

#include <strings.h>
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

static void note_in(char *list, size_t cap, const char *feature);

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
    "KHR_texture_transform", "KHR_materials_specular", "KHR_materials_clearcoat",
    "KHR_materials_sheen", "KHR_materials_volume", "EXT_mesh_gpu_instancing",
    "KHR_materials_pbrSpecularGlossiness",
#ifdef XRSC_HAVE_MESHOPT
    "EXT_meshopt_compression", // decoded after parsing with libmeshoptimizer (CMake: XRSC_MESHOPT)
#endif
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
    if (ti.index >= 0 && r.tex_coord > 1) sc_gltf_note(doc, "texCoord sets other than 0 and 1");
    return r;
}

/** A texture reference inside an extension's JSON (`key`: {"index", "texCoord"}); none when
 *  absent. KHR_texture_transform on these is noted and not applied. */
sc_gltf_texref texref_value(sc_gltf_doc *doc, const tinygltf::Value &v, const char *key)
{
    sc_gltf_texref r;
    r.texture = -1;
    r.tex_coord = 0;
    r.offset[0] = r.offset[1] = 0.0f;
    r.rotation_rad = 0.0f;
    r.scale[0] = r.scale[1] = 1.0f;
    if (!v.IsObject() || !v.Has(key) || !v.Get(key).IsObject()) return r;
    const tinygltf::Value &t = v.Get(key);
    if (t.Has("index") && t.Get("index").IsNumber()) r.texture = value_index(t.Get("index"));
    if (t.Has("texCoord") && t.Get("texCoord").IsNumber())
        r.tex_coord = value_index(t.Get("texCoord"));
    if (r.texture >= 0 && r.tex_coord > 1) sc_gltf_note(doc, "texCoord sets other than 0 and 1");
    if (t.Has("extensions") && t.Get("extensions").IsObject() &&
        t.Get("extensions").Has("KHR_texture_transform"))
        sc_gltf_note(doc, "KHR_texture_transform on material extension textures");
    return r;
}

/** Reads up to n numbers of the array `key` into dst (left as they are when absent). */
void value_numbers(const tinygltf::Value &v, const char *key, float *dst, int n)
{
    if (!v.IsObject() || !v.Has(key)) return;
    const tinygltf::Value &a = v.Get(key);
    if (!a.IsArray() || (int)a.ArrayLen() != n) return;
    for (int c = 0; c < n; c++)
        if (a.Get(c).IsNumber()) dst[c] = clamp_float(a.Get(c).GetNumberAsDouble());
}

/** What the JSON pre-check learns and keeps for messages. */
struct precheck {
    std::vector<std::string> buffer_uris;
    std::vector<std::string> image_uris;
    /** JSON for tinygltf when it had to be changed (meshopt fallback buffers), else empty. */
    std::string rewritten;
};

/** Data that stands in for a meshopt fallback buffer (no uri, no bytes: tinygltf would
 *  refuse it); its views are decoded from the compressed buffer instead. */
const char *const kFallbackUri = "data:application/octet-stream;base64,AAAAAA==";
const unsigned kFallbackBytes = 4;

/** glTF 1.0 (asset.version "1.0", or objects where 2.0 has arrays) is refused by name. */
xrsc_result check_version(const char *name, const char *text, size_t size,
                          const nlohmann::json &j, xrsc_diag *diag)
{
    std::string version;
    auto a = j.find("asset");
    if (a != j.end() && a->is_object()) {
        auto v = a->find("version");
        if (v != a->end() && v->is_string()) version = v->get<std::string>();
    }
    auto meshes = j.find("meshes");
    bool v1_layout = meshes != j.end() && meshes->is_object();
    if ((!version.empty() && version.compare(0, 2, "2.") != 0) ||
        (version.empty() && v1_layout))
        return u_diag_set(diag, XRSC_ERROR_GLTF_VERSION, name,
                          line_of(text, size, "\"version\""), "asset.version",
                          "glTF %s: xrsc reads glTF 2.0 only (convert the file, e.g. with "
                          "gltf-pipeline or Blender)",
                          version.empty() ? "1.0 layout (meshes is an object)" : version.c_str());
    return XRSC_OK;
}

/** extensionsRequired: every name must be one xrsc renders. */
xrsc_result check_required(const char *name, const char *text, size_t size,
                           const nlohmann::json &j, xrsc_diag *diag)
{
    auto it = j.find("extensionsRequired");
    if (it == j.end() || !it->is_array()) return XRSC_OK;
    int line = line_of(text, size, "\"extensionsRequired\"");
    for (const nlohmann::json &e : *it) {
        std::string ext = e.is_string() ? e.get<std::string>() : std::string("(not a string)");
        if (is_supported_extension(ext)) continue;
        const char *why = "";
        if (ext == "KHR_draco_mesh_compression")
            // Built without libdraco (CMake found no draco package, or XRSC_DRACO=OFF).
            why = " (Draco-compressed meshes: this build of xrsc has no libdraco-dev); export "
                  "the file without mesh compression";
        else if (ext == "EXT_meshopt_compression")
            why = " (this build of xrsc has no libmeshoptimizer-dev); export the file without "
                  "meshopt compression";
        else if (ext == "KHR_texture_basisu")
            why = " (KTX2/Basis Universal textures, which xrsc cannot decode); export the "
                  "textures as PNG or JPEG, or with a PNG/JPEG fallback source";
        return u_diag_set(diag, XRSC_ERROR_GLTF_UNSUPPORTED, name, line, "extensionsRequired",
                          "required extension %s is not supported by xrsc%s", ext.c_str(), why);
    }
    return XRSC_OK;
}

/** EXT_meshopt_compression fallback buffers (no uri) get a small data uri for tinygltf;
 *  true when j was changed. */
bool stand_in_fallback_buffers(nlohmann::json &j)
{
    bool changed = false;
    auto it = j.find("buffers");
    if (it == j.end() || !it->is_array()) return false;
    for (nlohmann::json &b : *it) {
        if (!b.is_object() || b.contains("uri")) continue;
        auto x = b.find("extensions");
        if (x == b.end() || !x->is_object()) continue;
        auto m = x->find("EXT_meshopt_compression");
        if (m == x->end() || !m->is_object()) continue;
        auto f = m->find("fallback");
        if (f == m->end() || !f->is_boolean() || !f->get<bool>()) continue;
        b["uri"] = kFallbackUri;
        b["byteLength"] = kFallbackBytes;
        changed = true;
    }
    return changed;
}

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

    xrsc_result r = check_version(name, text, size, j, diag);
    if (r == XRSC_OK) r = check_required(name, text, size, j, diag);
    if (r != XRSC_OK) return r;

    std::vector<uint64_t> buffer_len;
    auto it = j.find("buffers");
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
    if (stand_in_fallback_buffers(j)) pc->rewritten = j.dump();
    return XRSC_OK;
}

/* ------------------------------------------------------------ EXT_meshopt_compression -- */

/** The tinygltf model and what xrsc decoded beside it (sc_gltf_doc.impl). */
struct doc_impl {
    tinygltf::Model model;
    std::vector<std::vector<uint8_t>> decoded; /**< meshopt buffer views, decoded */
    std::vector<int32_t> view_decoded;         /**< per bufferView: index in decoded or -1 */
    std::vector<size_t> view_stride;           /**< per bufferView: the decoded byteStride */
};

#ifdef XRSC_HAVE_MESHOPT
/** A decoded view may be at most this many times its compressed bytes (+ kMeshoptSlack):
 *  the codecs spend at least 2 bits per 16 vertex bytes and 4 bits per triangle, so real
 *  data stays far below; a forged count cannot make xrsc allocate unbounded memory. */
const uint64_t kMeshoptMaxRatio = 256, kMeshoptSlack = 1 << 16;

/** One view's EXT_meshopt_compression object, decoded into out (count * byteStride bytes).
 *  Returns "" or what is wrong. */
std::string meshopt_decode_view(const tinygltf::Model &m, const tinygltf::Value &x,
                                std::vector<uint8_t> *out, size_t *out_stride)
{
    if (!x.IsObject()) return "is not an object";
    int32_t buf = x.Has("buffer") ? value_index(x.Get("buffer")) : -1;
    double off = value_number(x, "byteOffset", 0.0), len = value_number(x, "byteLength", -1.0);
    double stride = value_number(x, "byteStride", -1.0), count = value_number(x, "count", -1.0);
    std::string mode = x.Has("mode") && x.Get("mode").IsString() ? x.Get("mode").Get<std::string>()
                                                                : "";
    std::string filter = x.Has("filter") && x.Get("filter").IsString()
                             ? x.Get("filter").Get<std::string>()
                             : "NONE";
    if (buf < 0 || (size_t)buf >= m.buffers.size()) return "buffer does not exist";
    const std::vector<unsigned char> &src = m.buffers[(size_t)buf].data;
    if (!(off >= 0 && len >= 0 && off + len <= (double)src.size()))
        return "byteOffset/byteLength overrun the buffer";
    if (!(stride >= 1 && stride <= 256 && count >= 0 && count < 4294967296.0))
        return "byteStride or count is missing or out of range";
    uint64_t bytes = (uint64_t)count * (uint64_t)stride;
    if (bytes > (uint64_t)len * kMeshoptMaxRatio + kMeshoptSlack)
        return "count x byteStride is implausibly large for its compressed bytes";
    out->assign((size_t)bytes, 0);
    *out_stride = (size_t)stride;
    const unsigned char *p = src.data() + (size_t)off;
    size_t n = (size_t)count, sz = (size_t)stride, l = (size_t)len;
    int rc;
    if (mode == "ATTRIBUTES") {
        if (sz % 4 != 0) return "ATTRIBUTES need a byteStride that is a multiple of 4";
        rc = meshopt_decodeVertexBuffer(out->data(), n, sz, p, l);
    } else if (mode == "TRIANGLES" || mode == "INDICES") {
        if (sz != 2 && sz != 4) return "indices need a byteStride of 2 or 4";
        if (mode == "TRIANGLES" && n % 3 != 0) return "TRIANGLES count is not a multiple of 3";
        rc = mode == "TRIANGLES" ? meshopt_decodeIndexBuffer(out->data(), n, sz, p, l)
                                 : meshopt_decodeIndexSequence(out->data(), n, sz, p, l);
    } else {
        return "mode '" + mode + "' is not ATTRIBUTES, TRIANGLES or INDICES";
    }
    if (rc != 0) return "the compressed data does not decode (meshopt error " +
                        std::to_string(rc) + ")";
    if (filter == "NONE") return "";
    if (mode != "ATTRIBUTES") return "filters apply to ATTRIBUTES only";
    if (filter == "OCTAHEDRAL" && (sz == 4 || sz == 8))
        meshopt_decodeFilterOct(out->data(), n, sz);
    else if (filter == "QUATERNION" && sz == 8)
        meshopt_decodeFilterQuat(out->data(), n, sz);
    else if (filter == "EXPONENTIAL")
        meshopt_decodeFilterExp(out->data(), n, sz);
    else
        return "filter '" + filter + "' with byteStride " + std::to_string(sz) + " is invalid";
    return "";
}
#endif

/** Decodes every bufferView that has EXT_meshopt_compression (when built with meshopt;
 *  otherwise the extension is optional-and-ignored or was refused as required). */
xrsc_result decode_meshopt(const char *name, doc_impl *d, xrsc_diag *diag)
{
    const tinygltf::Model &m = d->model;
    d->view_decoded.assign(m.bufferViews.size(), -1);
    d->view_stride.assign(m.bufferViews.size(), 0);
#ifdef XRSC_HAVE_MESHOPT
    for (size_t i = 0; i < m.bufferViews.size(); i++) {
        auto x = m.bufferViews[i].extensions.find("EXT_meshopt_compression");
        if (x == m.bufferViews[i].extensions.end()) continue;
        std::vector<uint8_t> out;
        std::string why = meshopt_decode_view(m, x->second, &out, &d->view_stride[i]);
        if (!why.empty()) {
            char field[96];
            snprintf(field, sizeof field, "bufferViews[%zu].extensions.EXT_meshopt_compression",
                     i);
            return u_diag_set(diag, XRSC_ERROR_GLTF_INVALID, name, 0, field, "%s", why.c_str());
        }
        d->view_decoded[i] = (int32_t)d->decoded.size();
        d->decoded.push_back(std::move(out));
    }
#else
    (void)name;
    (void)diag;
#endif
    return XRSC_OK;
}

bool is_data_uri(const std::string &uri) { return uri.compare(0, 5, "data:") == 0; }

/** KHR_texture_transform of a texture-info JSON object into r (identity when absent). */
void texture_transform(const tinygltf::Value &info, sc_gltf_texref *r)
{
    if (!info.IsObject() || !info.Has("extensions")) return;
    const tinygltf::Value &exts = info.Get("extensions");
    if (!exts.IsObject() || !exts.Has("KHR_texture_transform")) return;
    const tinygltf::Value &v = exts.Get("KHR_texture_transform");
    if (!v.IsObject()) return;
    const char *keys[2] = {"offset", "scale"};
    float *dst[2] = {r->offset, r->scale};
    for (int k = 0; k < 2; k++) {
        if (!v.Has(keys[k])) continue;
        const tinygltf::Value &a = v.Get(keys[k]);
        if (a.IsArray() && a.ArrayLen() == 2 && a.Get(0).IsNumber() && a.Get(1).IsNumber())
            for (int c = 0; c < 2; c++) dst[k][c] = clamp_float(a.Get(c).GetNumberAsDouble());
    }
    r->rotation_rad = clamp_float(value_number(v, "rotation", 0.0));
    if (v.Has("texCoord") && v.Get("texCoord").IsNumber())
        r->tex_coord = value_index(v.Get("texCoord"));
}

/** A texture-info given as a JSON value (extensions' textures: tinygltf keeps them raw), with
 *  its KHR_texture_transform: for spec-gloss textures, which become a base-colour or
 *  metal/rough slot and keep their transform on the GPU. */
sc_gltf_texref texref_value_transformed(sc_gltf_doc *doc, const tinygltf::Value &parent,
                                        const char *key)
{
    sc_gltf_texref r = {-1, 0, {0.0f, 0.0f}, 0.0f, {1.0f, 1.0f}};
    if (!parent.IsObject() || !parent.Has(key)) return r;
    const tinygltf::Value &info = parent.Get(key);
    if (!info.IsObject() || !info.Has("index")) return r;
    r.texture = value_index(info.Get("index"));
    if (r.texture < 0) r.texture = INT32_MAX; // present but invalid: sc_scene.c names it
    if (info.Has("texCoord")) r.tex_coord = value_index(info.Get("texCoord"));
    texture_transform(info, &r);
    if (r.tex_coord > 1) sc_gltf_note(doc, "texCoord sets other than 0 and 1");
    return r;
}

/** KHR_materials_pbrSpecularGlossiness's factors and textures (converted in sc_scene.c). */
void fill_spec_gloss(sc_gltf_doc *doc, const tinygltf::Value &v, sc_gltf_material *o)
{
    o->spec_gloss = true;
    for (int c = 0; c < 4; c++) o->diffuse[c] = 1.0f;
    for (int c = 0; c < 3; c++) o->sg_specular[c] = 1.0f;
    o->glossiness = clamp_float(value_number(v, "glossinessFactor", 1.0));
    const char *keys[2] = {"diffuseFactor", "specularFactor"};
    float *dst[2] = {o->diffuse, o->sg_specular};
    for (int k = 0; k < 2; k++) {
        if (!v.IsObject() || !v.Has(keys[k])) continue;
        const tinygltf::Value &a = v.Get(keys[k]);
        int n = k == 0 ? 4 : 3;
        if (!a.IsArray() || a.ArrayLen() != (size_t)n) continue;
        for (int c = 0; c < n; c++)
            if (a.Get(c).IsNumber()) dst[k][c] = clamp_float(a.Get(c).GetNumberAsDouble());
    }
    o->diffuse_tex = texref_value_transformed(doc, v, "diffuseTexture");
    o->spec_gloss_tex = texref_value_transformed(doc, v, "specularGlossinessTexture");
}

/** EXT_mesh_gpu_instancing's attribute accessors of node n. */
void fill_instancing(const tinygltf::Node &n, sc_gltf_node *o)
{
    o->inst_translation = o->inst_rotation = o->inst_scale = -1;
    auto x = n.extensions.find("EXT_mesh_gpu_instancing");
    if (x == n.extensions.end() || !x->second.IsObject()) return;
    o->instanced = true;
    if (!x->second.Has("attributes")) return;
    const tinygltf::Value &a = x->second.Get("attributes");
    if (!a.IsObject()) return;
    if (a.Has("TRANSLATION")) o->inst_translation = value_index(a.Get("TRANSLATION"));
    if (a.Has("ROTATION")) o->inst_rotation = value_index(a.Get("ROTATION"));
    if (a.Has("SCALE")) o->inst_scale = value_index(a.Get("SCALE"));
}

/** The clips (animations) and the facts `xrsc scene info` reports; false when out of memory.
 *  Channels are laid out clip after clip in doc->channels (fill_doc). */
bool fill_clips_and_facts(const tinygltf::Model &m, sc_gltf_doc *doc)
{
    sc_gltf_facts *f = &doc->facts;
    f->skin_count = (uint32_t)m.skins.size();
    for (const tinygltf::Mesh &mesh : m.meshes) {
        uint32_t targets = 0;
        for (const tinygltf::Primitive &pr : mesh.primitives) targets += (uint32_t)pr.targets.size();
        f->morph_target_count += targets;
        f->morph_mesh_count += targets ? 1u : 0u;
    }
    for (const std::string &ext : m.extensionsUsed)
        note_in(f->extensions_used, sizeof f->extensions_used, ext.c_str());
    for (const std::string &ext : m.extensionsRequired)
        note_in(f->extensions_required, sizeof f->extensions_required, ext.c_str());
    doc->clip_count = (uint32_t)m.animations.size();
    doc->clips = alloc_array<sc_gltf_clip>(m.animations.size());
    if (m.animations.size() && !doc->clips) return false;
    uint32_t first = 0;
    for (size_t i = 0; i < m.animations.size(); i++) {
        copy_name(doc->clips[i].name, sizeof doc->clips[i].name, m.animations[i].name);
        doc->clips[i].first_channel = first;
        doc->clips[i].channel_count = (uint32_t)m.animations[i].channels.size();
        first += doc->clips[i].channel_count;
    }
    return true;
}

/** Fills doc from the loaded model. Returns XRSC_OK or an error for malformed node data. */
/** Accessor of attribute `key` of a primitive or morph target, -1 when absent. */
int32_t attribute(const std::map<std::string, int> &attrs, const std::string &key)
{
    auto a = attrs.find(key);
    return a != attrs.end() ? a->second : -1;
}

/** Skins, JOINTS_n / WEIGHTS_n, morph targets and morph weights (after meshes and nodes are
 *  filled, in the same order). False when out of memory. */
bool fill_deform(const tinygltf::Model &m, sc_gltf_doc *doc)
{
    size_t nt = 0, nw = 0, nj = 0, p = 0;
    for (const tinygltf::Mesh &mesh : m.meshes) {
        nw += mesh.weights.size();
        for (const tinygltf::Primitive &pr : mesh.primitives) nt += pr.targets.size();
    }
    for (const tinygltf::Node &n : m.nodes) nw += n.weights.size();
    for (const tinygltf::Skin &sk : m.skins) nj += sk.joints.size();
    doc->targets = alloc_array<sc_gltf_target>(nt);
    doc->weights = alloc_array<float>(nw);
    doc->skins = alloc_array<sc_gltf_skin>(m.skins.size());
    doc->skin_joints = alloc_array<int32_t>(nj);
    if ((nt && !doc->targets) || (nw && !doc->weights) || (nj && !doc->skin_joints) ||
        (m.skins.size() && !doc->skins))
        return false;
    for (size_t i = 0; i < m.meshes.size(); i++) {
        sc_gltf_mesh *om = &doc->meshes[i];
        om->first_weight = doc->weight_count;
        om->weight_count = (uint32_t)m.meshes[i].weights.size();
        for (double w : m.meshes[i].weights) doc->weights[doc->weight_count++] = clamp_float(w);
        for (const tinygltf::Primitive &pr : m.meshes[i].primitives) {
            sc_gltf_primitive *o = &doc->primitives[p++];
            for (int k = 0; k < SC_GLTF_MAX_JOINT_SETS; k++) {
                o->joints[k] = attribute(pr.attributes, "JOINTS_" + std::to_string(k));
                o->weights[k] = attribute(pr.attributes, "WEIGHTS_" + std::to_string(k));
            }
            if (attribute(pr.attributes, "JOINTS_" + std::to_string(SC_GLTF_MAX_JOINT_SETS)) >= 0)
                sc_gltf_note(doc, "JOINTS_n beyond JOINTS_3");
            o->first_target = doc->target_count;
            o->target_count = (uint32_t)pr.targets.size();
            for (const auto &t : pr.targets)
                doc->targets[doc->target_count++] = {attribute(t, "POSITION"),
                                                      attribute(t, "NORMAL"),
                                                      attribute(t, "TANGENT")};
        }
    }
    for (size_t i = 0; i < m.nodes.size(); i++) {
        doc->nodes[i].first_weight = doc->weight_count;
        doc->nodes[i].weight_count = (uint32_t)m.nodes[i].weights.size();
        for (double w : m.nodes[i].weights) doc->weights[doc->weight_count++] = clamp_float(w);
    }
    doc->skin_count = (uint32_t)m.skins.size();
    for (size_t i = 0; i < m.skins.size(); i++) {
        doc->skins[i] = {m.skins[i].inverseBindMatrices, doc->skin_joint_count,
                         (uint32_t)m.skins[i].joints.size()};
        for (int j : m.skins[i].joints) doc->skin_joints[doc->skin_joint_count++] = j;
    }
    return true;
}

xrsc_result fill_doc(const char *name, doc_impl &di, const load_ctx &ctx, sc_gltf_doc *doc,
                     xrsc_diag *diag)
{
    char field[96];
    tinygltf::Model &m = di.model;
    for (const std::string &ext : m.extensionsUsed)
        if (!is_supported_extension(ext)) sc_gltf_note_extension(doc, ext.c_str());

    // The file's buffers, then one per meshopt-decoded view.
    size_t nbuf = m.buffers.size() + di.decoded.size();
    doc->buffer_count = (uint32_t)nbuf;
    doc->buffers = alloc_array<sc_gltf_buffer>(nbuf);
    for (size_t i = 0; doc->buffers && i < nbuf; i++) {
        const std::vector<unsigned char> &data =
            i < m.buffers.size() ? m.buffers[i].data : di.decoded[i - m.buffers.size()];
        doc->buffers[i].data = data.data();
        doc->buffers[i].size = data.size();
    }
    doc->view_count = (uint32_t)m.bufferViews.size();
    doc->views = alloc_array<sc_gltf_view>(m.bufferViews.size());
    for (size_t i = 0; doc->views && i < m.bufferViews.size(); i++) {
        const tinygltf::BufferView &v = m.bufferViews[i];
        int32_t dec = i < di.view_decoded.size() ? di.view_decoded[i] : -1;
        if (dec >= 0)
            doc->views[i] = {(int32_t)(m.buffers.size() + (size_t)dec), 0,
                             di.decoded[(size_t)dec].size(), v.byteStride};
        else
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
            o->position = o->normal = o->tangent = o->texcoord0 = o->texcoord1 = -1;
            auto a = pr.attributes.find("POSITION");
            if (a != pr.attributes.end()) o->position = a->second;
            a = pr.attributes.find("NORMAL");
            if (a != pr.attributes.end()) o->normal = a->second;
            a = pr.attributes.find("TANGENT");
            if (a != pr.attributes.end()) o->tangent = a->second;
            a = pr.attributes.find("TEXCOORD_0");
            if (a != pr.attributes.end()) o->texcoord0 = a->second;
            a = pr.attributes.find("TEXCOORD_1");
            if (a != pr.attributes.end()) o->texcoord1 = a->second;
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
        sc_gltf_texref none = texref_value(doc, tinygltf::Value(), "");
        o->transmission_tex = o->specular_tex = o->specular_color_tex = none;
        o->clearcoat_tex = o->clearcoat_rough_tex = o->sheen_color_tex = o->sheen_rough_tex = none;
        o->specular = 1.0f;
        for (int c = 0; c < 3; c++) o->specular_color[c] = o->attenuation_color[c] = 1.0f;
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
                o->transmission_tex = texref_value(doc, v, "transmissionTexture");
            } else if (ext.first == "KHR_materials_specular") {
                o->specular = clamp_float(value_number(v, "specularFactor", 1.0));
                o->specular_tex = texref_value(doc, v, "specularTexture");
                value_numbers(v, "specularColorFactor", o->specular_color, 3);
                o->specular_color_tex = texref_value(doc, v, "specularColorTexture");
            } else if (ext.first == "KHR_materials_clearcoat") {
                o->clearcoat = clamp_float(value_number(v, "clearcoatFactor", 0.0));
                o->clearcoat_tex = texref_value(doc, v, "clearcoatTexture");
                o->clearcoat_roughness =
                    clamp_float(value_number(v, "clearcoatRoughnessFactor", 0.0));
                o->clearcoat_rough_tex = texref_value(doc, v, "clearcoatRoughnessTexture");
                if (v.IsObject() && v.Has("clearcoatNormalTexture"))
                    sc_gltf_note(doc, "clearcoatNormalTexture");
            } else if (ext.first == "KHR_materials_sheen") {
                value_numbers(v, "sheenColorFactor", o->sheen_color, 3);
                o->sheen_color_tex = texref_value(doc, v, "sheenColorTexture");
                o->sheen_roughness = clamp_float(value_number(v, "sheenRoughnessFactor", 0.0));
                o->sheen_rough_tex = texref_value(doc, v, "sheenRoughnessTexture");
            } else if (ext.first == "KHR_materials_volume") {
                o->thickness = clamp_float(value_number(v, "thicknessFactor", 0.0));
                value_numbers(v, "attenuationColor", o->attenuation_color, 3);
                o->attenuation_distance =
                    clamp_float(value_number(v, "attenuationDistance", 0.0));
                if (v.IsObject() && v.Has("thicknessTexture"))
                    sc_gltf_note(doc, "thicknessTexture");
            } else if (ext.first == "KHR_materials_unlit") {
                o->unlit = true;
            } else if (ext.first == "KHR_materials_ior") {
                o->ior = clamp_float(value_number(v, "ior", 1.5));
            } else if (ext.first == "KHR_materials_pbrSpecularGlossiness") {
                fill_spec_gloss(doc, v, o);
            } else {
                sc_gltf_note_extension(doc, ext.first.c_str());
            }
        }
    }

    doc->texture_count = (uint32_t)m.textures.size();
    doc->textures = alloc_array<sc_gltf_texture>(m.textures.size());
    for (size_t i = 0; doc->textures && i < m.textures.size(); i++) {
        const tinygltf::Texture &t = m.textures[i];
        sc_gltf_texture *o = &doc->textures[i];
        o->image = t.source;
        o->wrap_s = o->wrap_t = SC_GLTF_WRAP_REPEAT;
        o->mag_filter = o->min_filter = -1;
        if (t.sampler >= 0 && (size_t)t.sampler < m.samplers.size()) {
            const tinygltf::Sampler &sm = m.samplers[(size_t)t.sampler];
            o->wrap_s = sm.wrapS;
            o->wrap_t = sm.wrapT;
            o->mag_filter = sm.magFilter;
            o->min_filter = sm.minFilter;
        }
    }

    doc->image_count = (uint32_t)m.images.size();
    doc->images = alloc_array<sc_gltf_image>(m.images.size());
    for (size_t i = 0; i < m.images.size(); i++) {
        const tinygltf::Image &im = m.images[i];
        bool ok = i < ctx.image_status.size() && ctx.image_status[i] == IMAGE_DECODED &&
                  im.width > 0 && im.height > 0 &&
                  im.image.size() == (size_t)im.width * (size_t)im.height * 4;
        copy_name(doc->images[i].uri, sizeof doc->images[i].uri,
                  is_data_uri(im.uri) ? std::string("(data uri)") : im.uri);
        if (ok) {
            doc->images[i].width = (uint32_t)im.width;
            doc->images[i].height = (uint32_t)im.height;
            doc->images[i].rgba8 = im.image.data();
        } else {
            // Never read: an external file that is missing (a data uri or bufferView that
            // was not decodable reached load_image).
            bool read = i < ctx.image_status.size() && ctx.image_status[i] != IMAGE_NOT_READ;
            doc->images[i].missing = !read && im.bufferView < 0 && !im.uri.empty() &&
                                     !is_data_uri(im.uri);
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
        o->range = clamp_float(l.range);
        o->inner_cone_rad = clamp_float(l.spot.innerConeAngle);
        o->outer_cone_rad = clamp_float(l.spot.outerConeAngle);
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
        fill_instancing(n, o);
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
    if (!fill_clips_and_facts(m, doc))
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, name, 0, "", "out of memory");

    bool oom = (nbuf && !doc->buffers) || (m.bufferViews.size() && !doc->views) ||
               (m.accessors.size() && !doc->accessors) || (prim_total && !doc->primitives) ||
               (m.meshes.size() && !doc->meshes) || (m.materials.size() && !doc->materials) ||
               (m.textures.size() && !doc->textures) || (m.images.size() && !doc->images) ||
               (m.lights.size() && !doc->lights) || (m.cameras.size() && !doc->cameras) ||
               (child_total && !doc->children) || (m.nodes.size() && !doc->nodes) ||
               (chan_total && !doc->channels) || (root_total && !doc->roots) ||
               (m.scenes.size() && !doc->scenes);
    if (oom || !fill_deform(m, doc))
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, name, 0, "", "out of memory");
    return XRSC_OK;
}

/* ------------------------------------------------------------ container checks ------- */

/** A name for the format data looks like (glTF 2.0 being JSON or GLB), "" when unknown. */
const char *guess_format(const uint8_t *data, size_t size)
{
    struct magic {
        const char *bytes;
        size_t len;
        const char *format;
    };
    static const magic kMagics[] = {
        {"\x89PNG", 4, "a PNG image"},       {"\xff\xd8\xff", 3, "a JPEG image"},
        {"PK\x03\x04", 4, "a ZIP archive"},  {"\x1f\x8b", 2, "a gzip archive"},
        {"Kaydara FBX Binary", 18, "FBX"},   {"; FBX", 5, "FBX"},
        {"ply", 3, "PLY"},                   {"solid", 5, "ASCII STL"},
        {"#usda", 5, "USD"},                 {"PXR-USDC", 8, "USD"},
        {"BLENDER", 7, "a .blend file"},     {"<?xml", 5, "XML (COLLADA?)"},
        {"<COLLADA", 8, "COLLADA"},          {"\xabKTX", 4, "a KTX texture"},
        {"#?RADIANCE", 10, "a Radiance .hdr image"},
    };
    for (const magic &m : kMagics)
        if (size >= m.len && memcmp(data, m.bytes, m.len) == 0) return m.format;
    // OBJ: its first line that is not a comment or blank starts with an OBJ statement.
    static const char *const kObjWords[] = {"v", "vn", "vt", "f", "o", "g", "s",
                                            "mtllib", "usemtl", "l", "p"};
    size_t i = 0;
    while (i < size) {
        size_t end = i;
        while (end < size && data[end] != '\n') end++;
        size_t w = i;
        while (w < end && (data[w] == ' ' || data[w] == '\t' || data[w] == '\r')) w++;
        if (w < end && data[w] != '#') {
            size_t we = w;
            while (we < end && data[we] != ' ' && data[we] != '\t') we++;
            for (const char *word : kObjWords)
                if (we - w == strlen(word) && memcmp(data + w, word, we - w) == 0 && we < end)
                    return "OBJ";
            return "";
        }
        i = end + 1;
    }
    return "";
}

bool ends_with_glb(const char *name)
{
    size_t n = strlen(name);
    return n >= 4 && strcasecmp(name + n - 4, ".glb") == 0;
}

/** A GLB's header and chunk lengths against the file's size (before tinygltf reads it). */
xrsc_result check_glb(const char *name, const uint8_t *data, size_t size, xrsc_diag *diag)
{
    const size_t kHeader = 12, kChunkHeader = 8;
    if (size < kHeader)
        return u_diag_set(diag, XRSC_ERROR_GLB_TRUNCATED, name, 0, "header",
                          "GLB is truncated: its header needs %zu bytes, the file has %zu",
                          kHeader, size);
    uint32_t version = rd_u32(data + 4), length = rd_u32(data + 8);
    if (version != 2)
        return u_diag_set(diag, XRSC_ERROR_GLTF_VERSION, name, 0, "header.version",
                          "GLB version %u: xrsc reads glTF 2.0 only%s", version,
                          version == 1 ? " (this is glTF 1.0; convert it, e.g. with gltf-pipeline)"
                                       : "");
    if (length > size)
        return u_diag_set(diag, XRSC_ERROR_GLB_TRUNCATED, name, 0, "header.length",
                          "GLB is truncated: its header says %u bytes, the file has %zu", length,
                          size);
    size_t pos = kHeader;
    for (int chunk = 0; pos + kChunkHeader <= length; chunk++) {
        uint64_t end = (uint64_t)pos + kChunkHeader + rd_u32(data + pos);
        if (end > length)
            return u_diag_set(diag, XRSC_ERROR_GLB_TRUNCATED, name, 0,
                              chunk == 0 ? "JSON chunk" : "BIN chunk",
                              "GLB is truncated: chunk %d needs %llu bytes, the file has %u",
                              chunk, (unsigned long long)end, length);
        pos = (size_t)end;
    }
    if (pos == kHeader)
        return u_diag_set(diag, XRSC_ERROR_GLB_TRUNCATED, name, 0, "JSON chunk",
                          "GLB is truncated: no JSON chunk after the header (%u bytes)", length);
    return XRSC_OK;
}

/** Refuses bytes that are neither GLB nor JSON, with what they look like. */
xrsc_result check_container(const char *name, const uint8_t *data, size_t size, bool *out_glb,
                            xrsc_diag *diag)
{
    *out_glb = size >= 4 && memcmp(data, "glTF", 4) == 0;
    if (*out_glb) return check_glb(name, data, size, diag);
    size_t i = 0;
    if (size >= 3 && memcmp(data, "\xef\xbb\xbf", 3) == 0) i = 3; // UTF-8 byte order mark
    while (i < size && (data[i] == ' ' || data[i] == '\t' || data[i] == '\r' || data[i] == '\n'))
        i++;
    if (i < size && (data[i] == '{' || data[i] == '[')) return XRSC_OK; // JSON: precheck_json
    const char *format = guess_format(data, size);
    char looks[96];
    snprintf(looks, sizeof looks, "%s%s", *format ? ": looks like " : "", format);
    if (ends_with_glb(name)) {
        unsigned char m[4] = {0, 0, 0, 0};
        memcpy(m, data, size < 4 ? size : 4);
        return u_diag_set(diag, XRSC_ERROR_GLB_MAGIC, name, 0, "header.magic",
                          "not a GLB file: it starts with bytes %02x %02x %02x %02x, not 'glTF'%s",
                          m[0], m[1], m[2], m[3], looks);
    }
    return u_diag_set(diag, XRSC_ERROR_GLTF_NOT_GLTF, name, 1, "", "not a glTF 2.0 file%s",
                      *format ? looks : " (neither JSON nor GLB)");
}

/** A GLB whose JSON chunk is replaced by json (the BIN chunk and others kept). */
std::vector<uint8_t> glb_with_json(const uint8_t *data, size_t size, const std::string &json)
{
    size_t old_end = 20 + rd_u32(data + 12), padded = (json.size() + 3) & ~(size_t)3;
    std::vector<uint8_t> out(20 + padded + (size - old_end), ' ');
    auto put = [&out](size_t at, uint32_t v) {
        for (int k = 0; k < 4; k++) out[at + (size_t)k] = (uint8_t)(v >> (8 * k));
    };
    memcpy(out.data(), data, 12);
    put(8, (uint32_t)out.size());
    put(12, (uint32_t)padded);
    memcpy(out.data() + 16, data + 16, 4);
    memcpy(out.data() + 20, json.data(), json.size());
    if (size > old_end) memcpy(out.data() + 20 + padded, data + old_end, size - old_end);
    return out;
}

/** Runs tinygltf on the (possibly rewritten) bytes. Returns XRSC_OK or fills diag. */
xrsc_result run_tinygltf(const char *name, const uint8_t *data, size_t size, bool glb,
                         const char *json_text, size_t json_size, const precheck &pc,
                         const char *base_dir, load_ctx *ctx, tinygltf::Model *model,
                         xrsc_diag *diag)
{
    tinygltf::TinyGLTF loader;
    tinygltf::FsCallbacks fs = {fs_file_exists, fs_expand, fs_read, fs_write, ctx};
    loader.SetFsCallbacks(fs);
    loader.SetImageLoader(load_image, ctx);
    std::string err, warn, dir = base_dir ? base_dir : "";
    std::vector<uint8_t> glb_bytes;
    if (glb && !pc.rewritten.empty()) glb_bytes = glb_with_json(data, size, pc.rewritten);
    const std::string *text = pc.rewritten.empty() ? nullptr : &pc.rewritten;
    bool ok;
    try {
        if (glb)
            ok = glb_bytes.empty()
                     ? loader.LoadBinaryFromMemory(model, &err, &warn, data, (unsigned)size, dir)
                     : loader.LoadBinaryFromMemory(model, &err, &warn, glb_bytes.data(),
                                                   (unsigned)glb_bytes.size(), dir);
        else
            ok = text ? loader.LoadASCIIFromString(model, &err, &warn, text->data(),
                                                   (unsigned)text->size(), dir)
                      : loader.LoadASCIIFromString(model, &err, &warn, json_text,
                                                   (unsigned)json_size, dir);
    } catch (const std::bad_alloc &) {
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, name, 0, "", "out of memory");
    } catch (const std::exception &e) {
        err = e.what();
        ok = false;
    }
    while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
    if (!warn.empty()) U_LOG_D("%s: tinygltf: %s", name, warn.c_str());
    if (ok) return XRSC_OK;
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
    bool syntax = err.find("JSON") != std::string::npos || err.find("GLB") != std::string::npos ||
                  err.find("glTF") != std::string::npos ||
                  err.find("not found in .gltf") != std::string::npos ||
                  err.find("asset") != std::string::npos;
    return u_diag_set(diag, syntax ? XRSC_ERROR_GLTF_PARSE : XRSC_ERROR_GLTF_INVALID, name, 0,
                      "", "tinygltf: %s", err.c_str());
}

xrsc_result parse(const char *name, const uint8_t *data, size_t size, const char *base_dir,
                  sc_gltf_doc **out, xrsc_diag *diag)
{
    if (size > std::numeric_limits<unsigned int>::max())
        return u_diag_set(diag, XRSC_ERROR_FILE_TOO_LARGE, name, 0, "",
                          "%zu bytes is more than tinygltf can read", size);
    if (size == 0) return u_diag_set(diag, XRSC_ERROR_EMPTY_FILE, name, 0, "", "file is empty");

    bool glb = false;
    xrsc_result r = check_container(name, data, size, &glb, diag);
    if (r != XRSC_OK) return r;
    const char *json_text = reinterpret_cast<const char *>(data);
    size_t json_size = size;
    if (glb) {
        // GLB: 12-byte header, then the JSON chunk (length, type "JSON", bytes); the lengths
        // were checked against the file by check_glb.
        const uint32_t kChunkJson = 0x4E4F534Au;
        if (size < 20 || rd_u32(data + 16) != kChunkJson || rd_u32(data + 12) > size - 20)
            return u_diag_set(diag, XRSC_ERROR_GLTF_PARSE, name, 0, "",
                              "GLB header or JSON chunk is malformed");
        json_text = reinterpret_cast<const char *>(data + 20);
        json_size = rd_u32(data + 12);
    }
    precheck pc;
    r = precheck_json(name, json_text, json_size, &pc, diag);
    if (r != XRSC_OK) return r;

    load_ctx ctx;
    ctx.allow_fs = base_dir != nullptr;
    std::unique_ptr<doc_impl> impl(new doc_impl());
    r = run_tinygltf(name, data, size, glb, json_text, json_size, pc, base_dir, &ctx,
                     &impl->model, diag);
    if (r == XRSC_OK) r = decode_meshopt(name, impl.get(), diag);
    if (r != XRSC_OK) return r;

    sc_gltf_doc *doc = static_cast<sc_gltf_doc *>(calloc(1, sizeof(sc_gltf_doc)));
    if (!doc) return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, name, 0, "", "out of memory");
    doc_impl *di = impl.release();
    doc->impl = di;
    r = fill_doc(name, *di, ctx, doc, diag);
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
    delete static_cast<doc_impl *>(doc->impl);
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
    free(doc->clips);
    free(doc->scenes);
    free(doc->roots);
    free(doc->targets);
    free(doc->weights);
    free(doc->skins);
    free(doc->skin_joints);
    free(doc);
    *pdoc = nullptr;
}

/** Adds feature to a comma-separated list unless it is already an entry. */
static void note_in(char *list, size_t cap, const char *feature)
{
    size_t n = strlen(list), f = strlen(feature);
    // Look for the name as a whole list entry.
    const char *p = list;
    while ((p = strstr(p, feature)) != nullptr) {
        bool start = p == list || (p >= list + 2 && p[-2] == ',');
        bool end = p[f] == '\0' || p[f] == ',';
        if (start && end) return;
        p += f;
    }
    if (n + f + 3 >= cap) return;
    snprintf(list + n, cap - n, "%s%s", n ? ", " : "", feature);
}

extern "C" void sc_gltf_note(sc_gltf_doc *doc, const char *feature)
{
    note_in(doc->unsupported, sizeof doc->unsupported, feature);
}

extern "C" void sc_gltf_note_extension(sc_gltf_doc *doc, const char *name)
{
    note_in(doc->ignored_extensions, sizeof doc->ignored_extensions, name);
}
