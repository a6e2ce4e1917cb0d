// SPDX-License-Identifier: MIT
/**
 * @file u_device.h
 * @brief The Vulkan device selector, one rule for every place that picks a device: the
 *        plugin's context (xrsc_context_options.device, XRSC_DEVICE, `xrsc --device`) and
 *        host_sim's OpenXR runtime (XRSC_RT_DEVICE).
 *
 * A selector is NULL/"" (any device), "cpu" (CPU devices: lavapipe), "gpu" (every other
 * device), a number (that physical-device index) or any other text (devices whose name
 * contains it, ignoring case).
 */
#pragma once

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Whether physical device `index` (its name, whether it is a CPU device) matches selector. */
bool u_device_matches(const char *selector, uint32_t index, const char *name, bool is_cpu);

/**
 * Picks one of n devices: with a selector, the first (in enumeration order) that matches and
 * is usable; without one, the first usable non-CPU device, else the first usable CPU device.
 * Returns its index, or -1; *out_any_match (may be NULL) tells whether some device matched
 * the selector at all (so -1 with it set means the matches are not usable).
 */
int32_t u_device_select(const char *selector, uint32_t n, const char *const *names,
                        const bool *is_cpu, const bool *usable, bool *out_any_match);

#ifdef __cplusplus
}
#endif
