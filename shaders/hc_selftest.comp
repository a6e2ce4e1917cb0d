// SPDX-License-Identifier: MIT
/**
 * @file hc_selftest.comp
 * @brief Device self-test of hc_table.glsl (tests only): one hc_lookup per record of
 *        xs_hc_selftest_io with a key given by the test, storing or reading a known value, so a
 *        test can check that a lookup never returns a value stored for another key.
 */
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require

#include "xs_rng.glsl"
#include "xs_sampling.glsl"
#include "hc_table.glsl"

layout(local_size_x = XS_HC_SELFTEST_GROUP, local_size_y = 1, local_size_z = 1) in;

layout(set = 0, binding = XS_HC_BIND_SELFTEST, std430) buffer XsHcSelftestBlock
{
    xs_hc_selftest_io io[];
};

layout(push_constant) uniform XsHcSelftestPush
{
    uint count;
};

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= count)
        return;
    xs_hc_selftest_io r = io[i];
    hc_key k;
    k.c = ivec3(int(r.cx), int(r.cy), int(r.cz));
    k.lod = int(r.lod);
    k.axis = r.axis6 >> 1u;
    k.neg = r.axis6 & 1u;
    bool store = r.mode == XS_HC_SELFTEST_STORE;
    hc_slot s = hc_lookup(k, store);
    io[i].found = s.entry >= 0 ? 1u : 0u;
    io[i].reserved = s.reserved ? 1u : 0u;
    if (store) {
        if (s.reserved)
            hc_store(s, vec3(r.value));
    } else {
        vec4 v = hc_read(s);
        io[i].read = v.x;
        io[i].read_count = v.w;
    }
    hc_stats_flush();
}
