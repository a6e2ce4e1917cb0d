// SPDX-License-Identifier: MIT
/**
 * @file deform.comp
 * @brief Pass "skin": poses one deformed mesh (glTF skin and morph targets) into vertices[],
 *        the buffer its BLAS is built from, and keeps the last frame's positions in prev[].
 *
 * Morph targets first, then the skin (glTF 2.0 §3.7.3.3: p' = sum_i w_i M_i (p + sum_k w_k dp_k)),
 * with the joint matrices blended before they are applied, in the order of the CPU reference
 * sc_scene_posed_vertex. The weights are used as the file gives them (the spec asks files to
 * normalise them). One invocation per vertex.
 */
#version 460
#extension GL_GOOGLE_include_directive : require
#include "xrsc_shared.h"

layout(local_size_x = XS_DEFORM_GROUP_SIZE) in;

layout(std430, set = 0, binding = XS_DEFORM_BIND_VERTICES) buffer Vertices { xs_vertex vertices[]; };
layout(std430, set = 0, binding = XS_DEFORM_BIND_REST) readonly buffer Rest { xs_vertex rest[]; };
layout(std430, set = 0, binding = XS_DEFORM_BIND_INFLUENCES) readonly buffer Influences
{
    xs_skin_influence influences[];
};
layout(std430, set = 0, binding = XS_DEFORM_BIND_DELTAS) readonly buffer Deltas { xs_morph_delta deltas[]; };
layout(std430, set = 0, binding = XS_DEFORM_BIND_MATRICES) readonly buffer Matrices { mat4 matrices[]; };
layout(std430, set = 0, binding = XS_DEFORM_BIND_WEIGHTS) readonly buffer Weights { float weights[]; };
layout(std430, set = 0, binding = XS_DEFORM_BIND_PREV) buffer Prev { vec4 prev[]; };

layout(push_constant) uniform Push { xs_deform_push pc; };

/** The blended joint matrix of vertex i (sum over every set of w_i M_i). */
mat4 skin_matrix(uint i)
{
    mat4 m = mat4(0.0);
    for (uint s = 0u; s < pc.skin_sets; s++) {
        xs_skin_influence in_ = influences[pc.first_influence + s * pc.vertex_count + i];
        for (int c = 0; c < 4; c++)
            if (in_.weights[c] != 0.0)
                m += in_.weights[c] * matrices[pc.first_matrix + in_.joints[c]];
    }
    return m;
}

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.vertex_count)
        return;
    xs_vertex r = rest[pc.rest_base + i];
    vec3 p = r.position_u.xyz, n = r.normal_v.xyz, t = r.tangent.xyz;
    for (uint k = 0u; k < pc.target_count; k++) {
        float w = weights[pc.first_weight + k];
        xs_morph_delta d = deltas[pc.first_delta + k * pc.vertex_count + i];
        p += w * d.position.xyz;
        n += w * d.normal.xyz;
        t += w * d.tangent.xyz;
    }
    if (pc.skin_sets > 0u) {
        mat4 m = skin_matrix(i);
        p = (m * vec4(p, 1.0)).xyz;
        n = mat3(m) * n;
        t = mat3(m) * t;
    }
    /* unit normal; tangent orthonormal to it (as the loader leaves the rest pose) */
    float nl = length(n);
    n = nl > 0.0 ? n / nl : r.normal_v.xyz;
    t -= dot(n, t) * n;
    float tl = length(t);
    t = tl > 0.0 ? t / tl : r.tangent.xyz;
    uint v = pc.first_vertex + i;
    prev[v] = pc.keep_prev != 0u ? vec4(vertices[v].position_u.xyz, 1.0) : vec4(p, 1.0);
    vertices[v].position_u.xyz = p;
    vertices[v].normal_v.xyz = n;
    vertices[v].tangent.xyz = t;
}
