// SPDX-License-Identifier: MIT
/**
 * @file hs_scene_cmd.h
 * @brief The `xrsc scene info FILE` subcommand: what a user asks first about a glTF file
 *        (clips and their durations, triangles, materials, textures, lights, cameras, nodes,
 *        skins, morph targets, extensions), read on the CPU without a Vulkan device.
 */
#pragma once

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Runs `xrsc scene`; argv[0] is "scene", the subcommand and its options follow (see its
 * --help). Prints to stdout, errors to stderr. Returns the process exit code: 0 success, 1 the
 * file could not be read (or --animation names no clip of it), 2 bad arguments.
 */
int hs_scene_main(int argc, char **argv);

#ifdef __cplusplus
}
#endif
