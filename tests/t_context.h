// SPDX-License-Identifier: MIT
/**
 * @file t_context.h
 * @brief The GPU tests' shared context: opened under the Vulkan validation layer, and closed
 *        with a case failure when the layer reported any error.
 */
#pragma once

#include "testing.h"
#include "xrsc/xrsc.h"

#include <stdio.h>

/** A context with validation on; NULL (after printing why) when none can be made. */
static inline xrsc_context *t_context_open(void)
{
    xrsc_context_options o = {.validation = true};
    xrsc_context *ctx = NULL;
    xrsc_diag diag;
    char buf[1024];
    if (xrsc_context_create(&o, &ctx, &diag) != XRSC_OK) {
        fprintf(stderr, "no context: %s\n", xrsc_diag_format(&diag, buf, sizeof(buf)));
        return NULL;
    }
    return ctx;
}

/** Destroys *ctx (NULL afterwards); the validation layer's errors over its life fail a case. */
static inline void t_context_close(xrsc_context **ctx)
{
    uint32_t errors = xrsc_context_validation_errors(*ctx);
    xrsc_context_destroy(ctx);
    CHECK_MSG(errors == 0, "%u validation errors", errors);
    if (errors)
        t_g.cases_failed++;
}
