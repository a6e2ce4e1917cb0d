// SPDX-License-Identifier: MIT
/**
 * @file fuzz_headsets.c
 * @brief libFuzzer target: bytes → hs_headsets_parse (the headset profile file of
 *        `xrsc --headsets`), then a lookup and the listing of what parsed.
 */
#include "hs_headset.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* hs_headset.c refers to the embedded built-in file; the target parses only its input. */
const char hs_headsets_builtin[] = "";

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (!text)
        return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    hs_headset_table t;
    xrsc_diag diag;
    if (hs_headsets_parse(text, "fuzz.txt", &t, &diag) == XRSC_OK) {
        const hs_headset_profile *p = NULL;
        (void)hs_headsets_select(&t, "quest3", &p, &diag);
        FILE *devnull = fopen("/dev/null", "w");
        if (devnull) {
            hs_headsets_print(&t, devnull);
            fclose(devnull);
        }
        hs_headsets_free(&t);
    }
    free(text);
    return 0;
}
