// SPDX-License-Identifier: MIT
/**
 * @file shadow.rmiss
 * @brief Miss shader of shadow rays (miss index XS_MISS_INDEX_SHADOW): marks them unoccluded.
 *
 * Shadow rays are traced with TerminateOnFirstHit | SkipClosestHitShader | Opaque and the
 * payload set to 0, so only a miss changes it.
 */
#version 460
#extension GL_EXT_ray_tracing : require
#extension GL_GOOGLE_include_directive : require

#include "xrsc_shared.h"

layout(location = XS_PAYLOAD_SHADOW) rayPayloadInEXT uint shadow_visible;

void main()
{
    shadow_visible = 1u;
}
