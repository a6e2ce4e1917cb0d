// SPDX-License-Identifier: MIT
/**
 * @file sc_shade_importance.comp
 * @brief Sample cache pass "shade", part 0 of variance-guided shading
 *        (XS_SC_SHADE_ADAPTIVE_VARIANCE): this frame's importance histogram.
 *
 * Count-based adaptive shading counts each sample's importance 1 / (1 + c_s) as it arrives
 * (reprojection, tracing). A sample's variance-guided importance v / (1 + c_s) depends on the
 * other samples of its pixel (v: sc_shade_candidates_variance), known only once the pixel's set of
 * visible samples is final, so this pass counts them after tracing, one invocation per pixel,
 * with the same buckets as sc_count_importance (§3.5: logarithmic buckets between the previous
 * frame's bounds). sc_shade_select.comp then walks the histogram as for count-based importance.
 *
 * The pixel's counts are summed in the invocation first: one atomic per run of samples in the
 * same bucket and one each for the count and the bounds, instead of four per sample (all
 * invocations of an eye add to the same words; on lavapipe each atomic is a per-lane loop and
 * they were most of this pass). Integer sums, minimum and maximum: the same words in any
 * order. The pixel's candidates (above the new-sample bits of plan.y), variance v (plan.z) and
 * its candidates' lowest and highest bucket (plan.w, XS_SC_PLAN_RANGE_*) are left for
 * sc_shade_select.comp, which restores plan.y and writes the shade bits to plan.z.
 */
#version 460
#extension GL_GOOGLE_include_directive : require
#define XS_NO_TLAS
#include "xs_bindings.glsl"
#include "xs_hitinfo.glsl"
#include "sc_common.glsl"

layout(local_size_x = XS_SC_GROUP, local_size_y = XS_SC_GROUP, local_size_z = 1) in;

/* The workgroup's share of both eyes' statistics (sc_work_item may hand it the other eye),
 * added to sc_stats once per workgroup: one pixel's atomics on a handful of global words
 * serialised on GPUs (3.3 ms of a 28 ms frame at 2 x 1440 x 1600 on an H200). */
shared uint s_hist[2][XS_SC_BUCKETS_STORED];
shared uint s_count[2], s_min_inv[2], s_max[2];

/** The importance buckets of pixel pix's candidates (variance v) into the workgroup's
 *  histogram; returns their range for sc_shade_select.comp (XS_SC_PLAN_RANGE_*). */
uint count_candidates(uint eye, uint pix, uint cand, float v)
{
    uint cur = scp.cur;
    float w_min, w_max;
    bool bounded = sc_prev_bounds(eye, w_min, w_max);
    uint n = 0u, run = 0u, run_bucket = 0u, bits_min = 0xFFFFFFFFu, bits_max = 0u;
    uint lo = XS_SC_BUCKETS, hi = 0u;
    for (uint b = cand; b != 0u; b &= b - 1u) {
        float c_s = sc_rad_load(sc_rad_at(cur, uint(findLSB(b)), pix)).w;
        float w = xs_sc_variance_importance(v, c_s);
        /* sc_count_importance: without previous bounds each sample is its own range */
        uint bucket = bounded ? xs_sc_bucket(w, w_min, w_max) : xs_sc_bucket(w, w, w);
        if (run > 0u && bucket != run_bucket) {
            atomicAdd(s_hist[eye][run_bucket], run);
            run = 0u;
        }
        run_bucket = bucket;
        run++;
        n++;
        lo = min(lo, bucket);
        hi = max(hi, bucket);
        bits_min = min(bits_min, floatBitsToUint(w));
        bits_max = max(bits_max, floatBitsToUint(w));
    }
    atomicAdd(s_hist[eye][run_bucket], run);
    atomicAdd(s_count[eye], n);
    atomicMax(s_min_inv[eye], ~bits_min);
    atomicMax(s_max[eye], bits_max);
    return XS_SC_PLAN_RANGE_SET | lo | (hi << XS_SC_PLAN_RANGE_HI_SHIFT);
}

/** Pixel g's candidates and variance into sc_plan, its samples' importance buckets into the
 *  workgroup's histogram. */
void count_pixel(uvec3 g)
{
    uint eye = g.z;
    uint pix = sc_pix(eye, g.xy);
    uint cur = scp.cur;
    float v;
    bool observed;
    uint cand = sc_shade_candidates_variance(cur, pix, v, observed);
    uint range = 0u; /* the candidates' buckets, lowest and highest (XS_SC_PLAN_RANGE_*) */
    if (cand != 0u)
        range = count_candidates(eye, pix, cand, v);
    if (scp.cover != 0u && cand != 0u && !observed) /* the cover rule's (XS_SC_PLAN_UNOBSERVED) */
        range |= XS_SC_PLAN_UNOBSERVED;
    /* for sc_shade_select.comp: the candidates above the new-sample bits, the variance, the
     * bucket range (plan.w's visible count was the density pass's, which has run) */
    sc_plan[pix].yzw = uvec3(sc_plan[pix].y | (cand << XS_SC_MAX_SLOTS), floatBitsToUint(v), range);
}

void main()
{
    uint lid = gl_LocalInvocationIndex;
    if (lid < 2u * XS_SC_BUCKETS_STORED)
        s_hist[lid / XS_SC_BUCKETS_STORED][lid % XS_SC_BUCKETS_STORED] = 0u;
    if (lid < 2u) {
        s_count[lid] = 0u;
        s_min_inv[lid] = 0u;
        s_max[lid] = 0u;
    }
    barrier();
    uvec3 g = gl_GlobalInvocationID;
    if (g.x < frame.width && g.y < frame.height)
        count_pixel(sc_work_item(g)); /* tests: the atomics in another order */
    barrier();
    if (lid < 2u * XS_SC_BUCKETS_STORED) {
        uint e = lid / XS_SC_BUCKETS_STORED, b = lid % XS_SC_BUCKETS_STORED;
        if (s_hist[e][b] != 0u)
            atomicAdd(sc_stats[sc_stats_at(scp.cur, e)].hist[b], s_hist[e][b]);
    }
    if (lid < 2u && s_count[lid] != 0u) {
        uint si = sc_stats_at(scp.cur, lid);
        atomicAdd(sc_stats[si].count, s_count[lid]);
        atomicMax(sc_stats[si].w_min_inv, s_min_inv[lid]);
        atomicMax(sc_stats[si].w_max, s_max[lid]);
    }
}
