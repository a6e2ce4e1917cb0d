// SPDX-License-Identifier: MIT
/**
 * @file hc_occupancy.comp
 * @brief The hash cache's occupancy (counter "hc_occupancy"): counts the entries whose
 *        last-access stamp lies within max_age of the last frame's stamp into
 *        hc_stats.occupied. Run on request only (mt_hctable_counters), never inside a frame.
 *
 * Each invocation scans XS_HC_SCAN_PER_INVOCATION consecutive entries; a workgroup sums in
 * shared memory and adds once to the global counter.
 */
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require

#include "xs_rng.glsl"
#include "xs_sampling.glsl"
#include "hc_table.glsl"

layout(local_size_x = XS_HC_SCAN_GROUP, local_size_y = 1, local_size_z = 1) in;

shared uint group_count;

void main()
{
    if (gl_LocalInvocationIndex == 0u)
        group_count = 0u;
    barrier();
    uint first = gl_GlobalInvocationID.x * XS_HC_SCAN_PER_INVOCATION;
    uint n = 0u;
    for (uint i = 0u; i < XS_HC_SCAN_PER_INVOCATION; i++) {
        uint e = first + i;
        if (e >= hcp.entries)
            break;
        uint stamp = hc_word_stamp(hc_words[e]);
        if (stamp != 0u && hcp.frame - stamp <= hcp.max_age)
            n++;
    }
    if (n > 0u)
        atomicAdd(group_count, n);
    barrier();
    if (gl_LocalInvocationIndex == 0u && group_count > 0u)
        atomicAdd(hc_stats.occupied, group_count);
}
