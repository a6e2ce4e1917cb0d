// SPDX-License-Identifier: MIT
/**
 * @file sc_selftest.comp
 * @brief Runs the sample cache's scalar formulas (xs_sc_math.h: Listing 1, Eq. 1, Eq. 2) on
 *        the device over an array of xs_sc_selftest_io records, so tests can compare them
 *        with the C build of the same source. One invocation per record (push constant: count).
 */
#version 460
#extension GL_GOOGLE_include_directive : require
#include "xs_samplecache.h"
#include "xs_sc_math.h"

layout(local_size_x = 64) in;

layout(push_constant) uniform XsScSelftestPush
{
    uint count;
};

layout(set = 0, binding = XS_SC_BIND_SELFTEST, std430) buffer XsScSelftestBlock
{
    xs_sc_selftest_io io[];
};

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= count)
        return;
    xs_sc_selftest_io r = io[i];
    r.packed = uvec4(xs_sc_pack_x(r.bary_u, r.material), xs_sc_pack_y(r.bary_v, r.material),
                     r.primitive, r.instance);
    r.out_u = xs_sc_unpack_bary(r.packed.x);
    r.out_v = xs_sc_unpack_bary(r.packed.y);
    r.out_primitive = r.packed.z;
    r.out_instance = r.packed.w;
    r.out_material = xs_sc_unpack_material(r.packed.x, r.packed.y);
    r.out_delta = xs_sc_slope(r.t, r.cos_theta, r.phi);
    r.out_consistent = xs_sc_consistent(r.t_min, r.t_max, r.out_delta, r.eps1) ? 1u : 0u;
    io[i] = r;
}
