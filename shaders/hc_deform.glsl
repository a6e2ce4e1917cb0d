// SPDX-License-Identifier: MIT
/**
 * @file hc_deform.glsl
 * @brief The hash cache on deforming (skinned, morphed) surfaces (issue 21 item 3): the
 *        last-frame world position of a first hit, from which `hashcache` and `hybrid` carry a
 *        voxel's running mean to the voxel the surface has moved into (xs_hashcache.h).
 *
 * Include after hc_table.glsl (HC_SET) and the scene's bindings (instances, indices, vertices).
 */
#ifndef HC_DEFORM_GLSL
#define HC_DEFORM_GLSL

layout(set = HC_SET, binding = XS_HC_BIND_PREV_POS, std430) readonly buffer XsHcPrevPos
{
    vec4 hc_prev_pos[];
};

/** World position on the last frame of the hit (instance, primitive, barycentrics): the
 *  triangle's last-frame posed vertices (hc_prev_pos) through the instance's last-frame
 *  transform. moved: the posed object-space point differs from this frame's (deformation). */
vec3 hc_prev_point(uint instance, uint primitive, vec2 b, out bool moved)
{
    xs_instance inst = instances[instance];
    uint base = inst.first_index + 3u * primitive;
    vec3 w = vec3(1.0 - b.x - b.y, b.x, b.y), prev = vec3(0.0), d = vec3(0.0);
    for (uint c = 0u; c < 3u; c++) {
        uint vi = indices[base + c];
        prev += w[c] * hc_prev_pos[vi].xyz;
        d += w[c] * (hc_prev_pos[vi].xyz - vertices[vi].position_u.xyz);
    }
    moved = d != vec3(0.0);
    return (inst.prev_object_to_world * vec4(prev, 1.0)).xyz;
}

#endif
