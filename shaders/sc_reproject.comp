// SPDX-License-Identifier: MIT
/**
 * @file sc_reproject.comp
 * @brief Sample cache pass "reproject" (seed 000 §3.1): forward-projects every occupied sample
 *        of the previous copy into this frame's copy of the same eye.
 *
 * One invocation per source pixel (x, y, eye). Each occupied slot's world position is rebuilt
 * from its first hit with the CURRENT instance transforms (App. D) (background samples: their
 * direction), projected into this frame's view of the eye, and stored in a slot reserved on
 * the target pixel's mask (Listing 2, with a compare-and-swap for its atomic OR: see
 * try_reserve): a lost race is retried; when all slots are taken a visible sample takes an
 * invisible one's slot; an invisible sample that finds no free slot is dropped.
 *
 * 1-pass (scp.two_pass = 0): the winner writes fh and rad at once (the two benign races of
 * §3.1 are accepted, as the paper does). 2-pass: the winner writes only its source address
 * into src[] with atomicMax of (visible << 31 | address + 1), so a visible sample that took
 * over an invisible one's slot always wins, and sc_copy.comp copies the data.
 *
 * Visible samples also update the target pixel's closest distance + slope (Eq. 1) in one
 * 64-bit atomicMin and its farthest distance (atomicMax on the float bits), §3.4; the 1-pass
 * variant counts importance (§3.5) here, the 2-pass one in sc_copy.comp.
 *
 * Cross-eye reuse (scp.cross_eye): after its own samples, each invocation sends a copy of every
 * visible sample whose radiance does not depend on the eye (background, or a surface that is
 * not xs_sc_eye_specific) into the OTHER eye's view, reserved there like any visible sample
 * and marked foreign (xs_samplecache.h); the previous copy's foreign samples are not carried
 * (their owner sent fresh copies). A copy carries the radiance the owner's last shading left.
 * The copies are sent after the own samples' loop, so with cross-eye reuse off the order of
 * the atomics, and the images, are those of before.
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

/** Listing 2, choose_target_slot: a free slot, else (visible samples only) an invisible one. */
int choose_target_slot(bool visible, uint m)
{
    uint free_slots = ~sc_occ(m) & sc_all_slots();
    if (free_slots != 0u)
        return findLSB(free_slots);
    if (visible) {
        uint invisible = sc_occ(m) & ~sc_vis(m) & sc_all_slots();
        if (invisible != 0u)
            return findLSB(invisible);
    }
    return -1;
}

/**
 * Listing 2, try_reserve, as one compare-and-swap of the target mask: slot i's occupancy bit
 * (and visibility bit for a visible sample) are set only if the mask is still m, the value the
 * slot was chosen from; otherwise m becomes the current mask and the caller chooses again.
 *
 * Listing 2 itself ORs the bits in and lets a visible sample keep a slot whose occupant turned
 * out to be invisible. With a stale m that happens while free slots remain (two samples chose
 * the same "free" slot, the invisible one got there first): an eviction without need, whose
 * count depends on the order of arrival. The compare-and-swap evicts only in a full pixel, so
 * a pixel receiving V visible and I invisible samples keeps min(V + I, N) of them, min(V, N)
 * visible, in any order. The mask only gains bits during the pass (at most 2 N changes), so
 * SC_MAX_RESERVE_TRIES attempts always suffice.
 */
bool try_reserve(uint tmask, uint i, bool visible, inout uint m)
{
    uint want = m | sc_obit(i) | (visible ? sc_vbit(i) : 0u);
    uint seen = atomicCompSwap(sc_mask[tmask], m, want);
    bool success = seen == m;
    m = success ? want : seen;
    return success;
}

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

/** Listing 2, write_sample's reservation: a slot of target mask tmask for a (visible) sample;
 *  false when none is left. */
bool reserve_slot(uint tmask, bool visible, out uint slot)
{
    uint m = sc_mask[tmask];
    slot = 0u;
    for (uint tries = 0u; tries < SC_MAX_RESERVE_TRIES; tries++) {
        int i = choose_target_slot(visible, m);
        if (i < 0)
            return false;
        if (try_reserve(tmask, uint(i), visible, m)) {
            slot = uint(i);
            return true;
        }
    }
    return false;
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

/** Listing 2, write_sample after the reservation: source sample (slot s of pix in the previous
 *  copy, first hit fh) into slot `slot` of target pixel tpix of eye teye. */
void write_sample(uint teye, uint tpix, uint slot, uint s, uint pix, uvec4 fh, bool visible)
{
    uint prev = sc_prev();
    if (scp.two_pass != 0u) {
        uint addr = s * sc_plane() + pix;
        atomicMax(sc_src[slot * sc_plane() + tpix],
                  (visible ? XS_SC_SRC_VISIBLE : 0u) | (addr + 1u));
    } else {
        sc_fh[sc_slot_at(scp.cur, slot, tpix)] = fh;
        uvec2 rad = scp.shade_cache != 0u ? sc_rad[sc_rad_at(prev, s, pix)] : uvec2(0u);
        sc_rad[sc_rad_at(scp.cur, slot, tpix)] = rad; /* the halves as they are */
        if (visible && !sc_is_background(fh) && scp.shade_mode == XS_SC_SHADE_ADAPTIVE)
            sc_count_importance(teye, xs_sc_importance(unpackHalf2x16(rad.y).y));
    }
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
    uint slot;
    if (!reserve_slot(sc_mask_at(scp.cur, tpix), true, slot))
        return;
    atomicOr(sc_foreign[sc_mask_at(scp.cur, tpix)], sc_obit(slot));
    write_sample(teye, tpix, slot, s, pix, fh, true);
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
        uint tmask = sc_mask_at(cur, tpix);
        if (sc_isrt()) {
            isrt_offer(s, pix, tpix, pos, visible, t);
            if (visible)
                update_depth_words(tpix, background, t, slope);
            continue;
        }

        /* Listing 2, write_sample */
        uint slot;
        if (!reserve_slot(tmask, visible, slot))
            continue;

        write_sample(eye, tpix, slot, s, pix, fh, visible);
        if (visible)
            update_depth_words(tpix, background, t, slope);
    }
    if (scp.cross_eye != 0u)
        send_copies(eye, pix, pm & ~(sc_foreign_bits(prev, pix) << XS_SC_MAX_SLOTS));
}
