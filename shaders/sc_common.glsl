// SPDX-License-Identifier: MIT
/**
 * @file sc_common.glsl
 * @brief What every sample-cache shader shares: the cache bindings (xs_samplecache.h), buffer
 *        indexing, first-hit encoding/decoding (Listing 1) and projection into an eye.
 *
 * Include after xs_bindings.glsl (and xs_hitinfo.glsl). Ray-tracing shaders define
 * XS_SC_SET XS_SC_RT_SET first; compute shaders get set 0 (next to the scene bindings).
 */
#ifndef SC_COMMON_GLSL
#define SC_COMMON_GLSL

#include "xs_samplecache.h"
#include "xs_sc_math.h"

#ifndef XS_SC_SET
#define XS_SC_SET 0
#endif

layout(set = XS_SC_SET, binding = XS_SC_BIND_PARAMS, std140) uniform XsScParamsBlock
{
    xs_sc_params scp;
};
layout(set = XS_SC_SET, binding = XS_SC_BIND_MASK, std430) coherent buffer XsScMaskBlock
{
    uint sc_mask[];
};
layout(set = XS_SC_SET, binding = XS_SC_BIND_FH, std430) buffer XsScFhBlock
{
    uvec4 sc_fh[];
};
layout(set = XS_SC_SET, binding = XS_SC_BIND_RAD, std430) buffer XsScRadBlock
{
    uvec2 sc_rad[]; /* four halves: (r, g), (b, c_s) (XS_SC_RAD_BYTES) */
};
layout(set = XS_SC_SET, binding = XS_SC_BIND_DEPTH_MIN, std430) buffer XsScDepthMinBlock
{
    uint64_t sc_depth_min[];
};
layout(set = XS_SC_SET, binding = XS_SC_BIND_DEPTH_MAX, std430) buffer XsScDepthMaxBlock
{
    uint sc_depth_max[];
};
layout(set = XS_SC_SET, binding = XS_SC_BIND_SRC, std430) buffer XsScSrcBlock
{
    uint sc_src[];
};
/* `isrt`: the same binding holds the reprojection's 64-bit keys [slot][pix] instead
 * (XS_SC_ISRT_KEY_*; the buffer is sized for them when scp.isrt_m > 0). */
layout(set = XS_SC_SET, binding = XS_SC_BIND_SRC, std430) buffer XsScSrcKeyBlock
{
    uint64_t sc_src_key[];
};
layout(set = XS_SC_SET, binding = XS_SC_BIND_PLAN, std430) buffer XsScPlanBlock
{
    /* x trace bits, y new-sample bits, z shade bits, w visible count (for the density pass;
     * variance-guided shading then leaves the candidates' bucket range there) */
    uvec4 sc_plan[];
};
layout(set = XS_SC_SET, binding = XS_SC_BIND_STATS, std430) buffer XsScStatsBlock
{
    xs_sc_stats sc_stats[]; /* [copy * 2 + eye] */
};

layout(set = XS_SC_SET, binding = XS_SC_BIND_SHADE_LIST, std430) buffer XsScShadeListBlock
{
    uint sc_shade_count;
    uint sc_pool_full; /* new samples not created this frame: the pool was full (issue 19) */
    uint64_t sc_shade_rays; /* rays the shading pass traced (XS_SC_SHADE_LIST_HEADER) */
    uint sc_shade_list[];
};

/* Cross-eye reuse (scp.cross_eye): bit s of foreign[c][pix] = slot s is the other eye's copy. */
layout(set = XS_SC_SET, binding = XS_SC_BIND_FOREIGN, std430) buffer XsScForeignBlock
{
    uint sc_foreign[];
};

/* The sample pool (issue 19, xs_samplecache.h): idx[c][slot][pix] = pool address of the slot's
 * sample in fh[] and rad[]; used[pix] bit k = entry k * plane + pix taken this frame. */
layout(set = XS_SC_SET, binding = XS_SC_BIND_IDX, std430) buffer XsScIdxBlock
{
    uint sc_idx[];
};
layout(set = XS_SC_SET, binding = XS_SC_BIND_USED, std430) buffer XsScUsedBlock
{
    uint sc_used[];
};

/* Background depth: distance of samples that hit the environment (sorted after every
 * surface: a pixel mixing both fails Eq. 2; a pure background pixel is consistent). */
#define SC_T_BACKGROUND uintBitsToFloat(0x7F800000u)
/* depth_min "no sample" (cleared to all ones) and depth_max "no sample" (cleared to 0). */
#define SC_DEPTH_MIN_NONE 0xFFFFFFFFFFFFFFFFul

uint sc_plane() { return 2u * frame.width * frame.height; }
uint sc_pix(uint eye, uvec2 p) { return (eye * frame.height + p.y) * frame.width + p.x; }
uint sc_prev() { return 1u - scp.cur; }
/** Index of the mask of copy c. */
uint sc_mask_at(uint c, uint pix) { return c * sc_plane() + pix; }
/** Index of slot s of copy c in idx[]. */
uint sc_idx_at(uint c, uint s, uint pix) { return (c * scp.slots + s) * sc_plane() + pix; }
/** Pool address (index in fh[] and rad[]) of the sample in slot s of copy c. */
uint sc_slot_at(uint c, uint s, uint pix) { return sc_idx[sc_idx_at(c, s, pix)]; }
/** Index in rad[] of pool address a: in `hybrid` (XS_SC_RAD_NONE) one dummy entry. */
uint sc_rad_of(uint a) { return scp.shade_cache == XS_SC_RAD_NONE ? 0u : a; }
/** Index in rad[] of slot s of copy c. */
uint sc_rad_at(uint c, uint s, uint pix)
{
    if (scp.shade_cache == XS_SC_RAD_NONE)
        return 0u;
    return sc_slot_at(c, s, pix);
}
/** Marks pool address a taken this frame (a slot of this frame's copy refers to it). */
void sc_pool_take(uint a)
{
    atomicOr(sc_used[a % sc_plane()], 1u << (a / sc_plane()));
}
/** A 32-bit integer hash (Wang's), for the pool's probe sequence. */
uint sc_pool_hash(uint x)
{
    x = (x ^ 61u) ^ (x >> 16);
    x *= 9u;
    x ^= x >> 4;
    x *= 0x27D4EB2Du;
    return x ^ (x >> 15);
}
/**
 * A free pool entry for a new sample of pixel pix, taken: one of pix's own K entries, else of
 * pixels spread over the whole pool (a hashed probe sequence: where the view pans, the pixels
 * that see new content are the ones whose entries hold the samples born there the frames
 * before, so their neighbours' are as full); XS_SC_POOL_NONE after XS_SC_POOL_PROBES full
 * words. Runs after the reprojection has marked every carried sample's entry.
 */
uint sc_pool_alloc(uint pix)
{
    uint all_k = scp.pool_k >= 32u ? 0xFFFFFFFFu : (1u << scp.pool_k) - 1u;
    uint plane = sc_plane();
    for (uint i = 0u; i < XS_SC_POOL_PROBES; i++) {
        uint q = i == 0u ? pix : sc_pool_hash(pix * XS_SC_POOL_PROBES + i) % plane;
        uint used = sc_used[q];
        while ((~used & all_k) != 0u) {
            uint bit = 1u << uint(findLSB(~used & all_k));
            used = atomicOr(sc_used[q], bit);
            if ((used & bit) == 0u)
                return uint(findLSB(bit)) * plane + q;
        }
    }
    atomicAdd(sc_pool_full, 1u);
    return XS_SC_POOL_NONE;
}
/** The radiance record at index at (sc_rad_at): L_s in rgb, c_s in a. */
vec4 sc_rad_load(uint at)
{
    uvec2 r = sc_rad[at];
    return vec4(unpackHalf2x16(r.x), unpackHalf2x16(r.y));
}
/** Stores L_s and c_s as halves (clamped to the largest finite half, XS_SC_RAD_BYTES). */
void sc_rad_store(uint at, vec4 v)
{
    v = min(v, vec4(XS_SC_RAD_HALF_MAX));
    sc_rad[at] = uvec2(packHalf2x16(v.xy), packHalf2x16(v.zw));
}

/** Cross-eye reuse: the slots of pixel pix in copy c that are the other eye's (0 when off). */
uint sc_foreign_bits(uint c, uint pix)
{
    return scp.cross_eye != 0u ? sc_foreign[c * sc_plane() + pix] : 0u;
}

uint sc_occ(uint m) { return m & XS_SC_OCC_MASK; }
uint sc_vis(uint m) { return m >> XS_SC_MAX_SLOTS; }
uint sc_obit(uint s) { return 1u << s; }
uint sc_vbit(uint s) { return 1u << (s + XS_SC_MAX_SLOTS); }
uint sc_all_slots() { return (1u << scp.slots) - 1u; }
float sc_phi(uint eye) { return eye == 0u ? scp.phi_left : scp.phi_right; }
vec3 sc_eye_pos(uint eye) { return frame.eyes[eye].view_inv[3].xyz; }

/** Whether a surface sample's instance turned since the previous frame: the linear part of its
 *  transform changed, so its faces see the light under another angle and the radiance it
 *  cached belongs to another pose (XS_SC_MOVING_ALPHA_MIN). An instance that only slides keeps
 *  its orientation: false. */
bool sc_instance_turned(uint instance)
{
    return mat3(instances[instance].object_to_world) !=
           mat3(instances[instance].prev_object_to_world);
}

/** The share of App. C's clamp for world point p seen from eye (xs_sc_view_motion): the angle
 *  between its view from the eye's previous position and from this one (1 on a first frame). */
float sc_view_motion(uint eye, vec3 p)
{
    vec4 prev = scp.eye_prev[eye];
    if (prev.w == 0.0)
        return 1.0;
    vec3 a = normalize(p - prev.xyz), b = normalize(p - sc_eye_pos(eye));
    float angle = 2.0 * asin(min(0.5 * length(a - b), 1.0)); /* exact for small angles */
    return xs_sc_view_motion(angle, sc_phi(eye));
}

/** `isrt` [DSK*17]: slot s of a pixel is the fixed sub-pixel cell (s % M, s / M) of an M x M
 *  grid (seed 000 §5, Fig. 10). */
bool sc_isrt() { return scp.isrt_m != 0u; }

/** The work item (x, y, eye) of invocation g of a per-pixel pass whose result must not depend
 *  on the order its invocations run in: g itself, or under scp.debug_permute (tests) the
 *  reverse order, so a test on lavapipe (which runs them in a fixed order) sees a different
 *  one. g must be inside the image. */
uvec3 sc_work_item(uvec3 g)
{
    if (scp.debug_permute == 0u)
        return g;
    return uvec3(frame.width - 1u - g.x, frame.height - 1u - g.y, 1u - g.z);
}
/** The slot (cell) of a sub-pixel position: pos in pixels, its fraction picks the cell. */
uint sc_isrt_slot(vec2 pos)
{
    uvec2 c = min(uvec2(fract(pos) * float(scp.isrt_m)), uvec2(scp.isrt_m - 1u));
    return c.y * scp.isrt_m + c.x;
}
/** The centre of slot s's cell, in [0, 1)^2 of the pixel. */
vec2 sc_isrt_cell_centre(uint s)
{
    return (vec2(s % scp.isrt_m, s / scp.isrt_m) + 0.5) / float(scp.isrt_m);
}

/** Listing 1 (xs_sc_math.h for the 24-bit barycentrics). */
uvec4 sc_encode_hit(uint instance, uint primitive, vec2 bary, uint material)
{
    return uvec4(xs_sc_pack_x(bary.x, material), xs_sc_pack_y(bary.y, material), primitive,
                 instance);
}

/** A background sample: the unit world direction of its ray. */
uvec4 sc_encode_background(vec3 dir)
{
    return uvec4(floatBitsToUint(dir), XS_SC_BACKGROUND);
}

bool sc_is_background(uvec4 fh) { return fh.w == XS_SC_BACKGROUND; }
vec2 sc_bary(uvec4 fh) { return vec2(xs_sc_unpack_bary(fh.x), xs_sc_unpack_bary(fh.y)); }
uint sc_material(uvec4 fh) { return xs_sc_unpack_material(fh.x, fh.y); }
vec3 sc_background_dir(uvec4 fh) { return uintBitsToFloat(fh.xyz); }

/** The surface of a stored hit with the CURRENT instance transforms (App. D: moving objects
 *  need nothing else). The material index comes from fh (Listing 1). */
xs_surface sc_surface(uvec4 fh)
{
    xs_surface s = xs_surface_at(fh.w, fh.z, sc_bary(fh));
    s.material = sc_material(fh);
    return s;
}

/**
 * The last triangle one invocation rebuilt: its world-space corners and unit geometric normal
 * up to sign. The samples of one pixel mostly lie on one triangle, and on lavapipe the
 * per-lane buffer loads and the corner transforms dominate the passes that loop over a
 * pixel's samples (reproject, reconstruct): sc_tri_fetch loads a triangle only when the key
 * (instance, primitive) changes. Corners, position and normal are those of xs_surface_at, with
 * the CURRENT instance transforms (App. D: moving objects need nothing else); the normal is
 * not oriented by the vertex normals (passes that need |cos| only).
 */
struct sc_tri {
    uint instance; /* XS_SC_BACKGROUND: empty */
    uint primitive;
    bool attributes; /* the fields below were loaded */
    vec3 p0, p1, p2;
    vec3 ng_unsigned;
    /* with attributes (sc_tri_fetch): the vertex normals in world space, not normalised, and
     * the vertex uv (xy TEXCOORD_0, zw TEXCOORD_1) */
    vec3 n0, n1, n2;
    vec4 uv0, uv1, uv2;
};

void sc_tri_init(out sc_tri tri)
{
    tri.instance = XS_SC_BACKGROUND;
    tri.primitive = 0u;
    tri.attributes = false;
    tri.p0 = tri.p1 = tri.p2 = tri.ng_unsigned = tri.n0 = tri.n1 = tri.n2 = vec3(0.0);
    tri.uv0 = tri.uv1 = tri.uv2 = vec4(0.0);
}

/** Makes tri the triangle of surface hit fh (loads it unless it is already, with the
 *  attributes when asked); attributes: also the vertex normals and uv (sc_tri_outside,
 *  sc_tri_uv). */
void sc_tri_fetch(inout sc_tri tri, uvec4 fh, bool attributes)
{
    if (tri.instance == fh.w && tri.primitive == fh.z && (tri.attributes || !attributes))
        return;
    xs_instance inst = instances[fh.w];
    uint base = inst.first_index + 3u * fh.z;
    uvec3 vi = uvec3(indices[base], indices[base + 1u], indices[base + 2u]);
    vec4 a0 = vertices[vi.x].position_u, a1 = vertices[vi.y].position_u,
         a2 = vertices[vi.z].position_u;
    tri.instance = fh.w;
    tri.primitive = fh.z;
    tri.p0 = (inst.object_to_world * vec4(a0.xyz, 1.0)).xyz;
    tri.p1 = (inst.object_to_world * vec4(a1.xyz, 1.0)).xyz;
    tri.p2 = (inst.object_to_world * vec4(a2.xyz, 1.0)).xyz;
    vec3 cr = cross(tri.p1 - tri.p0, tri.p2 - tri.p0);
    float cr_len = length(cr);
    tri.ng_unsigned = cr_len > 0.0 ? cr / cr_len : vec3(0.0, 0.0, 1.0);
    tri.attributes = attributes;
    if (!attributes)
        return;
    vec4 b0 = vertices[vi.x].normal_v, b1 = vertices[vi.y].normal_v, b2 = vertices[vi.z].normal_v;
    mat3 n2w = mat3(inst.normal_to_world);
    tri.n0 = n2w * b0.xyz;
    tri.n1 = n2w * b1.xyz;
    tri.n2 = n2w * b2.xyz;
    tri.uv0 = vec4(a0.w, b0.w, vertices[vi.x].uv1.xy);
    tri.uv1 = vec4(a1.w, b1.w, vertices[vi.y].uv1.xy);
    tri.uv2 = vec4(a2.w, b2.w, vertices[vi.z].uv1.xy);
}

/** The barycentric weights of surface hit fh (corner 0, 1, 2). */
vec3 sc_tri_weights(uvec4 fh)
{
    vec2 bary = sc_bary(fh);
    return vec3(1.0 - bary.x - bary.y, bary.x, bary.y);
}

/** The uv sets of surface hit fh on tri (fetched with attributes; xs_surface.uv). */
vec4 sc_tri_uv(sc_tri tri, uvec4 fh)
{
    vec3 w = sc_tri_weights(fh);
    return w.x * tri.uv0 + w.y * tri.uv1 + w.z * tri.uv2;
}

/** Whether direction wo (unit, from the surface) lies on the outside of surface hit fh on tri
 *  (fetched with attributes): the side its interpolated vertex normal points to, as
 *  xs_surface_at and xs_surface_orient decide it. */
bool sc_tri_outside(sc_tri tri, uvec4 fh, vec3 wo)
{
    vec3 w = sc_tri_weights(fh);
    vec3 ns = w.x * tri.n0 + w.y * tri.n1 + w.z * tri.n2;
    float ns_len = length(ns);
    bool flip = ns_len > 1e-20 && !isnan(ns_len) && dot(tri.ng_unsigned, ns) < 0.0;
    return dot(wo, flip ? -tri.ng_unsigned : tri.ng_unsigned) >= 0.0;
}

/** The world position of surface hit fh on tri (sc_tri_fetch(tri, fh) first). */
vec3 sc_tri_position(sc_tri tri, uvec4 fh)
{
    vec3 w = sc_tri_weights(fh);
    return w.x * tri.p0 + w.y * tri.p1 + w.z * tri.p2;
}

/**
 * Projects a world point (w = 1) or direction (w = 0) into eye `eye` of this frame with the
 * camera convention of xs_camera.glsl (eye-space direction (mix(tanL, tanR, u), mix(tanU,
 * tanD, v), -1), u, v in [0, 1] across the image). Returns false behind the eye or outside
 * the image; pos = image position in pixels.
 */
bool sc_project(uint eye, vec4 p_world, out vec2 pos)
{
    xs_eye e = frame.eyes[eye];
    vec3 q = (e.view * p_world).xyz;
    pos = vec2(-1.0);
    if (!(q.z < 0.0))
        return false;
    vec2 tn = q.xy / -q.z;
    vec2 uv = vec2((tn.x - e.tan_fov.x) / (e.tan_fov.y - e.tan_fov.x),
                   (tn.y - e.tan_fov.z) / (e.tan_fov.w - e.tan_fov.z));
    pos = uv * vec2(frame.width, frame.height);
    return all(greaterThanEqual(pos, vec2(0.0))) &&
           all(lessThan(pos, vec2(frame.width, frame.height)));
}

/** The factor radiance is demodulated by / remodulated with (§3.3; xs_demod, shared with the
 *  hash cache). */
vec3 sc_demod(vec3 albedo) { return xs_demod(albedo); }

/** Per-eye statistics of copy c. */
uint sc_stats_at(uint c, uint eye) { return c * 2u + eye; }

/** The previous frame's importance bounds of eye (§3.5); false when it had no samples. */
bool sc_prev_bounds(uint eye, out float w_min, out float w_max)
{
    xs_sc_stats st = sc_stats[sc_stats_at(sc_prev(), eye)];
    w_min = uintBitsToFloat(~st.w_min_inv);
    w_max = uintBitsToFloat(st.w_max);
    return st.w_min_inv != 0u && st.w_max != 0u;
}

/** Counts a sample of importance w into this frame's histogram and bounds (§3.5). */
void sc_count_importance(uint eye, float w)
{
    float w_min, w_max;
    if (!sc_prev_bounds(eye, w_min, w_max)) {
        w_min = w;
        w_max = w;
    }
    uint si = sc_stats_at(scp.cur, eye);
    atomicAdd(sc_stats[si].hist[xs_sc_bucket(w, w_min, w_max)], 1u);
    atomicAdd(sc_stats[si].count, 1u);
    atomicMax(sc_stats[si].w_min_inv, ~floatBitsToUint(w));
    atomicMax(sc_stats[si].w_max, floatBitsToUint(w));
}

/** Variance-guided shading: the visible surface samples of pixel pix in copy c (as
 *  sc_shade_candidates) and out_v, the relative variance of one observation
 *  (xs_sc_pixel_variance) from those of them that have been shaded (c_s > 0), in one walk
 *  (each pool address, first hit and radiance record loaded once: on lavapipe every per-lane
 *  load is a gather). */
uint sc_shade_candidates_variance(uint c, uint pix, out float out_v, out bool observed)
{
    uint m = sc_mask[sc_mask_at(c, pix)];
    uint cand = 0u;
    float k = 0.0, sc = 0.0, scl = 0.0, scl2 = 0.0;
    for (uint bits = sc_vis(m) & sc_occ(m) & sc_all_slots(); bits != 0u; bits &= bits - 1u) {
        uint s = uint(findLSB(bits));
        uint a = sc_slot_at(c, s, pix);
        if (sc_is_background(sc_fh[a]))
            continue;
        cand |= sc_obit(s);
        vec4 r = sc_rad_load(sc_rad_of(a));
        if (!(r.w > 0.0))
            continue;
        float l = dot(r.rgb, vec3(0.2126, 0.7152, 0.0722));
        k += 1.0;
        sc += r.w;
        scl += r.w * l;
        scl2 += r.w * l * l;
    }
    out_v = xs_sc_pixel_variance(k, sc, scl, scl2);
    observed = k > 0.0;
    return cand;
}

/** The visible surface samples of pixel pix in copy c (background samples need no shading). */
uint sc_shade_candidates(uint c, uint pix)
{
    uint m = sc_mask[sc_mask_at(c, pix)];
    uint cand = 0u;
    for (uint bits = sc_vis(m) & sc_occ(m) & sc_all_slots(); bits != 0u; bits &= bits - 1u) {
        uint s = uint(findLSB(bits));
        if (!sc_is_background(sc_fh[sc_slot_at(c, s, pix)]))
            cand |= sc_obit(s);
    }
    return cand;
}

/** i-th set bit at or after `start` (cyclically), or -1 when bits is 0: round robin. */
int sc_round_robin(uint bits, uint start)
{
    if (bits == 0u)
        return -1;
    uint n = scp.slots;
    uint rot = ((bits >> start) | (bits << (n - start))) & ((1u << n) - 1u);
    if (start == 0u)
        rot = bits;
    return int((uint(findLSB(rot)) + start) % n);
}

/** Appends an entry to the work list (the shade-list buffer: the trace list from the density
 *  pass to the trace pass, then the shade list); entries past scp.shade_capacity are
 *  dropped (the count keeps the total). */
void sc_list_append(uint entry)
{
    uint at = atomicAdd(sc_shade_count, 1u);
    if (at < scp.shade_capacity)
        sc_shade_list[at] = entry;
}

#if XS_SC_SET == XS_SC_RT_SET
/** The work-list entry of this launch invocation, false past the list's end (the launch's
 *  layout: XS_SC_LIST_WIDTH, XS_SC_LIST_BLOCK, XS_SC_SHADE_STRIPES in xs_samplecache.h). */
bool sc_list_entry(out uint entry)
{
    uint q = gl_LaunchSizeEXT.y / (XS_SC_SHADE_STRIPES * XS_SC_LIST_BLOCK);
    uint b = gl_LaunchIDEXT.y / XS_SC_LIST_BLOCK;
    uint row = ((b % q) * XS_SC_SHADE_STRIPES + b / q) * XS_SC_LIST_BLOCK +
               gl_LaunchIDEXT.y % XS_SC_LIST_BLOCK;
    uint idx = row * XS_SC_LIST_WIDTH + gl_LaunchIDEXT.x;
    entry = 0u;
    uint n = min(sc_shade_count, scp.shade_capacity);
    if (idx >= n)
        return false;
    if (scp.debug_permute != 0u) /* tests: the reverse order (sc_work_item) */
        idx = n - 1u - idx;
    entry = sc_shade_list[idx];
    return true;
}

/** Eye and pixel of a both-eyes pixel index (sc_pix). */
uvec3 sc_pixel_of(uint pix)
{
    uint per_eye = frame.width * frame.height;
    uint eye = pix / per_eye;
    uint p = pix - eye * per_eye;
    return uvec3(p % frame.width, p / frame.width, eye);
}
#endif

/** The 3x3 bounds of pixel p: the neighbourhood of §3.2 and §3.4, clipped to the image. */
void sc_neighbourhood(uvec2 p, out uvec2 lo, out uvec2 hi)
{
    lo = uvec2(max(ivec2(p) - 1, ivec2(0)));
    hi = uvec2(min(ivec2(p) + 1, ivec2(frame.width, frame.height) - 1));
}

#endif
