// SPDX-License-Identifier: MIT
/**
 * @file fuzz_gltf.c
 * @brief libFuzzer target: bytes → sc_scene_load_memory (GLB when they start with "glTF",
 * else JSON), then animation evaluation. No file is ever read (base_dir NULL). Inputs of odd
 * length are named "fuzz.glb" so that the GLB-magic check (a .glb that is not GLB) is reached
 * too.
 */
#include "sc_scene.h"

#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    setenv("XRSC_LOG", "quiet", 1); /* warnings about ignored features on every input */
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sc_scene *scene = NULL;
    xrsc_diag diag;
    const char *name = size % 2 ? "fuzz.glb" : "fuzz.gltf";
    if (sc_scene_load_memory(name, data, size, NULL, NULL, &scene, &diag) == XRSC_OK) {
        sc_scene_evaluate(scene, 0.37);
        sc_scene_evaluate(scene, 1e6);
        sc_scene_evaluate(scene, -2.5);
    }
    sc_scene_destroy(&scene);
    return 0;
}
