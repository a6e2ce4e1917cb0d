// SPDX-License-Identifier: MIT
/**
 * @file hit.rchit
 * @brief The one closest-hit shader: reports which triangle was hit and where (xs_hit).
 *
 * Shading happens in the raygen shaders (xs_hitinfo.glsl rebuilds the surface from this).
 */
#version 460
#extension GL_EXT_ray_tracing : require
#extension GL_GOOGLE_include_directive : require

#include "xrsc_shared.h"

layout(location = XS_PAYLOAD_PRIMARY) rayPayloadInEXT xs_hit payload;
hitAttributeEXT vec2 hit_bary;

void main()
{
    payload.instance = uint(gl_InstanceCustomIndexEXT);
    payload.primitive = uint(gl_PrimitiveID);
    payload.bary_u = hit_bary.x;
    payload.bary_v = hit_bary.y;
    payload.t = gl_HitTEXT;
    payload.front_face = gl_HitKindEXT == gl_HitKindFrontFacingTriangleEXT ? 1u : 0u;
}
