// SPDX-License-Identifier: MIT
/**
 * @file u_half.h
 * @brief IEEE 754 binary16 to float, for reading back half-float GPU data (sample-cache
 *        radiance, R16G16B16A16_SFLOAT swapchain images).
 */
#ifndef U_HALF_H
#define U_HALF_H

#include <math.h>
#include <stdint.h>
#include <string.h>

/** The float value of half h (exact: every half is a float; NaN and infinities kept). */
static inline float u_half_to_float(uint16_t h)
{
    uint32_t sign = (uint32_t)(h >> 15) << 31, exp = (h >> 10) & 0x1fu, man = h & 0x3ffu;
    uint32_t bits;
    if (exp == 0) {
        if (!man) {
            bits = sign;
        } else { /* subnormal: man x 2^-24 */
            float f = ldexpf((float)man, -24);
            return sign ? -f : f;
        }
    } else if (exp == 31) {
        bits = sign | 0x7f800000u | (man << 13);
    } else {
        bits = sign | ((exp + 112) << 23) | (man << 13);
    }
    float f;
    memcpy(&f, &bits, sizeof(f));
    return f;
}

#endif
