// SPDX-License-Identifier: MIT
/**
 * @file primary.rmiss
 * @brief Miss shader of camera and bounce rays (miss index XS_MISS_INDEX_PRIMARY).
 */
#version 460
#extension GL_EXT_ray_tracing : require
#extension GL_GOOGLE_include_directive : require

#include "xrsc_shared.h"

layout(location = XS_PAYLOAD_PRIMARY) rayPayloadInEXT xs_hit payload;

void main()
{
    payload.instance = XS_MISS_INSTANCE;
    payload.t = -1.0;
}
