// SPDX-License-Identifier: MIT
/**
 * @file u_exr_common.c
 * @brief The OpenEXR reader's and writer's shared error handling and planes (u_exr_common.h).
 */
#include "u_exr_common.h"

#include "u_diag.h"

#include <stdio.h>
#include <string.h>

void u_exr_on_error(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    void *ud = NULL;
    if (exr_get_user_data(ctxt, &ud) == EXR_ERR_SUCCESS && ud)
        snprintf(((u_exr_msg *)ud)->text, sizeof(((u_exr_msg *)ud)->text), "%s (%s)",
                 msg ? msg : "", exr_get_error_code_as_string(code));
}

xrsc_result u_exr_fail(xrsc_diag *diag, xrsc_result code, const char *name, const char *what,
                       exr_result_t rv, const u_exr_msg *msg)
{
    return u_diag_set(diag, code, name, 0, "exr", "%s: %s", what,
                      msg->text[0] ? msg->text : exr_get_default_error_message(rv));
}

const u_exr_plane *u_exr_find_plane(const u_exr_plane *p, int n, const char *name)
{
    for (int i = 0; i < n; i++)
        if (p[i].base && strcmp(p[i].name, name) == 0)
            return &p[i];
    return NULL;
}
