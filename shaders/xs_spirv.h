// SPDX-License-Identifier: MIT
/**
 * @file xs_spirv.h
 * @brief Look-up of the SPIR-V modules embedded at build time (see cmake/XrscShaders.cmake).
 */
#pragma once

#include <stddef.h>
#include <stdint.h>

/** The embedded module compiled from shaders/<name> (e.g. "spp.rgen"), NULL if none; size in bytes. */
const uint32_t *xs_spirv_find(const char *name, size_t *out_size);
