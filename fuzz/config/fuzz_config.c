// SPDX-License-Identifier: MIT
/**
 * @file fuzz_config.c
 * @brief libFuzzer target of the `--config FILE` parser (hs_args_config_text): any text either
 *        becomes options or an error naming a line, never a crash; every option it makes is a
 *        terminated string inside the hs_args, a value option always followed by its value.
 */
#include "hs_args.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static const char *const values[] = {"--frames", "--out", "--scene", "--resolution"};

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > HS_ARGS_CONFIG_MAX)
        return 0;
    const hs_args_spec spec = {.cmd = "xrsc",
                               .value_options = values,
                               .value_count = sizeof(values) / sizeof(values[0]),
                               .config = true};
    char *text = malloc(size + 1);
    hs_args *a = calloc(1, sizeof(*a));
    if (!text || !a) {
        free(text);
        free(a);
        return 0;
    }
    memcpy(text, data, size);
    text[size] = '\0';
    xrsc_diag diag;
    if (hs_args_config_text(a, &spec, "fuzz.conf", text, &diag) == XRSC_OK) {
        if (a->argc > HS_ARGS_MAX || a->text_used > sizeof(a->text))
            abort();
        for (int i = 0; i < a->argc; i++) {
            const char *s = a->argv[i];
            if (s < a->text || s >= a->text + a->text_used || strncmp(s, "--", 2) != 0)
                abort();
            if (hs_arg_in(s, values, sizeof(values) / sizeof(values[0])) && ++i >= a->argc)
                abort();
        }
    } else if (diag.line < 1 || strcmp(diag.file, "fuzz.conf") != 0) {
        abort();
    }
    free(text);
    free(a);
    return 0;
}
