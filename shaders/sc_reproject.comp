// SPDX-License-Identifier: MIT
/**
 * @file sc_reproject.comp
 * @brief Sample cache pass "reproject" (seed 000 §3.1): forward-projects every occupied sample
 *        of the previous copy into this frame's copy of the same eye.
 *
 * One invocation per source pixel (x, y, eye). Each occupied slot's world position is rebuilt
 * from its first hit with the CURRENT instance transforms (App. D) (background samples: their
 * direction) and projected into this frame's view of the eye. Listing 2 reserves a slot of
 * the target pixel for it in order of arrival (first come, first served; a visible sample may
 * take an invisible one's slot), which on a GPU, where the invocations run in no fixed order,
 * makes the kept samples, their slots and so the image differ from run to run. Here every
 * arrival offers a key instead (offer_sorted: visible first, then the lowest source address)
 * and the target keeps the N smallest, sorted: the same min(V + I, N) samples of which
 * min(V, N) visible as Listing 2 keeps, chosen and placed the same way in any order;
 * sc_copy.comp then copies them and writes the mask. Both variants (scp.two_pass 0 and 1) do
 * this now: Listing 2's 1-pass writes during the reservation cannot be order-independent.
 *
 * Visible samples also update the target pixel's closest distance + slope (Eq. 1) in one
 * 64-bit atomicMin and its farthest distance (atomicMax on the float bits), §3.4 (both
 * order-independent); sc_copy.comp counts importance (§3.5).
 *
 * Cross-eye reuse (scp.cross_eye): after its own samples, each invocation sends a copy of every
 * visible sample whose radiance does not depend on the eye (background, or a surface that is
 * not xs_sc_eye_specific) into the OTHER eye's view, reserved there like any visible sample
 * and marked foreign by sc_copy.comp (its source is in the other eye); the previous copy's
 * foreign samples are not carried (their owner sent fresh copies). A copy is the owner's pool
 * address (no second record of the sample, issue 19), so it shows the radiance of the owner's
 * latest shading.
 *
 * `isrt` (scp.isrt_m = M > 0, [DSK*17] as seed 000 §5 / Fig. 10 uses it): no reservation; the
 * slot is the sub-pixel cell of the M x M grid that contains the reprojected position, and of
 * the samples arriving in one cell the one with the smallest key (XS_SC_ISRT_KEY_*: visible
 * first, then the closest, then the lowest source address) wins through a 64-bit atomicMin, so
 * the result does not depend on the order of arrival; sc_copy.comp then copies the winners.
 * The depth words count every visible arrival, losers too: two surfaces in one cell are an
 * edge that Eq. 2 should see.
 */
#version 460
#extension GL_GOOGLE_include_directive : require
#define XS_NO_TLAS
#include "xs_bindings.glsl"
#include "xs_hitinfo.glsl"
#include "sc_common.glsl"

layout(local_size_x = XS_SC_GROUP, local_size_y = XS_SC_GROUP, local_size_z = 1) in;

/* Reservation attempts: each failed one means another sample added mask bits (at most 2 N). */
#define SC_MAX_RESERVE_TRIES (2u * XS_SC_MAX_SLOTS + 1u)

/** The target pixel's depth words (§3.4): closest distance + slope, farthest distance. */
void update_depth_words(uint tpix, bool background, float t, float slope)
{
    if (!background) {
        uint64_t packed = (uint64_t(floatBitsToUint(t)) << 32) | uint64_t(floatBitsToUint(slope));
        atomicMin(sc_depth_min[tpix], packed);
    }
    atomicMax(sc_depth_max[tpix], floatBitsToUint(t));
}

/** `isrt`: offers source sample (slot s of pix) to the cell of pos in target pixel tpix. */
void isrt_offer(uint s, uint pix, uint tpix, vec2 pos, bool visible, float t)
{
    uint key_at = sc_isrt_slot(pos) * sc_plane() + tpix;
    uint64_t key = (uint64_t(visible ? 0u : 1u) << XS_SC_ISRT_KEY_INVISIBLE_SHIFT) |
                   (uint64_t(floatBitsToUint(t)) << XS_SC_ISRT_KEY_T_SHIFT) |
                   uint64_t(s * sc_plane() + pix + 1u);
    atomicMin(sc_src_key[key_at], key);
}

/**
 * Listing 2's reservation, made independent of the order of arrival: source sample (slot s of
 * pix) offers its key (XS_SC_SRC_*: visible first, then the lowest source address) to target
 * pixel tpix's slots, which keep the N smallest keys sorted. Each atomicMin leaves the smaller
 * of (word, key) in slot i and carries the larger one on to slot i + 1, so every word ends as
 * the minimum of what reached it and the rest moves on: the words end as the N smallest keys
 * of all arrivals, in order, whichever order they came in (sc_copy.comp copies them). The
 * words are this frame's copy of the slots' pool addresses (idx[cur], filled with
 * XS_SC_SRC_NONE): sc_copy.comp replaces each key with its sample's pool address, so the keys
 * take no memory of their own (issue 19).
 */
void offer_sorted(uint tpix, uint s, uint pix, bool visible)
{
    uint key = (visible ? 0u : XS_SC_SRC_INVISIBLE) | (s * sc_plane() + pix + 1u);
    for (uint i = 0u; i < scp.slots; i++) {
        uint old = atomicMin(sc_idx[sc_idx_at(scp.cur, i, tpix)], key);
        if (old == XS_SC_SRC_NONE)
            return;
        key = max(old, key);
    }
}

/** Cross-eye reuse: whether the surface sample fh on tri (fetched with attributes) is shaded
 *  per eye only (metal, glass, sharp specular: xs_sc_eye_specific). */
bool eye_specific(sc_tri tri, uvec4 fh)
{
    xs_mat mt = xs_material_at(sc_material(fh), sc_tri_uv(tri, fh));
    return xs_sc_eye_specific(mt.metallic, mt.transmission, mt.roughness, mt.ior) != 0u;
}

/** Projects a world point (w = 1, on tri) or direction (w = 0) into eye teye: the image
 *  position, the distance t to the eye (background: SC_T_BACKGROUND) and Eq. 1's slope; false
 *  behind the eye or outside the image. */
bool project_sample(uint teye, vec4 pw, sc_tri tri, out vec2 pos, out float t, out float slope)
{
    t = SC_T_BACKGROUND;
    slope = 0.0;
    if (!sc_project(teye, pw, pos))
        return false;
    if (pw.w != 0.0) {
        /* |cos| only: the normal's sign does not matter under abs */
        vec3 to_eye = sc_eye_pos(teye) - pw.xyz;
        t = length(to_eye);
        slope = xs_sc_slope(t, abs(dot(tri.ng_unsigned, to_eye / max(t, 1e-30))), sc_phi(teye));
    }
    return true;
}

/**
 * Cross-eye reuse: a copy of visible source sample (slot s of pix, first hit fh, world position
 * or direction pw, on tri unless background) in eye teye, the other eye, marked foreign. It is
 * visible, so no later sample takes its slot over.
 */
void send_copy(uint teye, uint s, uint pix, uvec4 fh, vec4 pw, sc_tri tri)
{
    bool background = pw.w == 0.0;
    vec2 pos;
    float t, slope;
    if (!project_sample(teye, pw, tri, pos, t, slope))
        return;
    uint tpix = sc_pix(teye, uvec2(pos));
    offer_sorted(tpix, s, pix, true); /* foreign: sc_copy.comp sees the source's eye */
    update_depth_words(tpix, background, t, slope);
}

/** Cross-eye reuse: the copies of pixel pix's visible own samples (vis: their bits in the
 *  previous copy's mask layout) in the other eye, surfaces of eye-independent materials and
 *  background samples (the environment is the same for both eyes). */
void send_copies(uint eye, uint pix, uint pm)
{
    uint prev = sc_prev();
    sc_tri tri;
    sc_tri_init(tri);
    for (uint vis = sc_vis(pm) & sc_occ(pm) & sc_all_slots(); vis != 0u; vis &= vis - 1u) {
        uint s = uint(findLSB(vis));
        uvec4 fh = sc_fh[sc_slot_at(prev, s, pix)];
        vec4 pw = vec4(sc_background_dir(fh), 0.0);
        if (!sc_is_background(fh)) {
            sc_tri_fetch(tri, fh, true);
            if (eye_specific(tri, fh))
                continue;
            pw = vec4(sc_tri_position(tri, fh), 1.0);
        }
        send_copy(1u - eye, s, pix, fh, pw, tri);
    }
}

void main()
{
    uvec3 g = gl_GlobalInvocationID;
    if (g.x >= frame.width || g.y >= frame.height)
        return;
    g = sc_work_item(g);
    uint eye = g.z;
    uint pix = sc_pix(eye, g.xy);
    uint prev = sc_prev();
    uint cur = scp.cur;
    uint pm = sc_mask[sc_mask_at(prev, pix)];
    /* cross-eye copies are not carried: their owner sends fresh ones */
    uint occ = sc_occ(pm) & sc_all_slots() & ~sc_foreign_bits(prev, pix);
    sc_tri tri;
    sc_tri_init(tri);

    while (occ != 0u) {
        uint s = uint(findLSB(occ));
        occ &= occ - 1u;
        bool visible = (pm & sc_vbit(s)) != 0u;
        uint src_at = sc_slot_at(prev, s, pix);
        uvec4 fh = sc_fh[src_at];

        bool background = sc_is_background(fh);
        vec4 pw = vec4(sc_background_dir(fh), 0.0);
        if (!background) { /* position and |cos| only */
            sc_tri_fetch(tri, fh, false);
            pw = vec4(sc_tri_position(tri, fh), 1.0);
        }
        vec2 pos;
        float t, slope;
        if (!project_sample(eye, pw, tri, pos, t, slope))
            continue;
        uint tpix = sc_pix(eye, uvec2(pos));
        if (sc_isrt()) {
            isrt_offer(s, pix, tpix, pos, visible, t);
            if (visible)
                update_depth_words(tpix, background, t, slope);
            continue;
        }

        /* Listing 2, write_sample: the reservation; sc_copy.comp writes */
        offer_sorted(tpix, s, pix, visible);
        if (visible)
            update_depth_words(tpix, background, t, slope);
    }
    if (scp.cross_eye != 0u)
        send_copies(eye, pix, pm & ~(sc_foreign_bits(prev, pix) << XS_SC_MAX_SLOTS));
}
