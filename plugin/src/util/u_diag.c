// SPDX-License-Identifier: MIT
/**
 * @file u_diag.c
 * @brief Result names, diagnostics and logging.
 */
#include "u_diag.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *xrsc_result_name(xrsc_result result)
{
    switch (result) {
#define XRSC_X_NAME(name, value, text)                                                             \
    case name:                                                                                     \
        return #name;
        XRSC_RESULT_LIST(XRSC_X_NAME)
#undef XRSC_X_NAME
    }
    return "XRSC_RESULT_UNKNOWN";
}

const char *xrsc_result_text(xrsc_result result)
{
    switch (result) {
#define XRSC_X_TEXT(name, value, text)                                                             \
    case name:                                                                                     \
        return text;
        XRSC_RESULT_LIST(XRSC_X_TEXT)
#undef XRSC_X_TEXT
    }
    return "unknown result";
}

xrsc_result u_diag_set(xrsc_diag *diag, xrsc_result code, const char *file, int line,
                       const char *field, const char *fmt, ...)
{
    if (!diag)
        return code;
    memset(diag, 0, sizeof(*diag));
    diag->code = code;
    diag->line = line;
    snprintf(diag->file, sizeof(diag->file), "%s", file ? file : "");
    snprintf(diag->field, sizeof(diag->field), "%s", field ? field : "");
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(diag->message, sizeof(diag->message), fmt, ap);
    va_end(ap);
    return code;
}

char *xrsc_diag_format(const xrsc_diag *diag, char *buf, unsigned long buf_size)
{
    if (!buf || buf_size == 0)
        return buf;
    if (!diag) {
        buf[0] = '\0';
        return buf;
    }
    char where[640] = "";
    if (diag->file[0] && diag->line > 0)
        snprintf(where, sizeof(where), "%s:%d: ", diag->file, diag->line);
    else if (diag->file[0])
        snprintf(where, sizeof(where), "%s: ", diag->file);
    char field[112] = "";
    if (diag->field[0])
        snprintf(field, sizeof(field), "%s: ", diag->field);
    snprintf(buf, buf_size, "%s%s%s [%s]", where, field,
             diag->message[0] ? diag->message : xrsc_result_text(diag->code),
             xrsc_result_name(diag->code));
    return buf;
}

static u_log_level log_threshold(void)
{
    const char *env = getenv("XRSC_LOG");
    if (!env)
        return U_LOG_INFO;
    if (!strcmp(env, "debug"))
        return U_LOG_DEBUG;
    if (!strcmp(env, "warn"))
        return U_LOG_WARN;
    if (!strcmp(env, "error") || !strcmp(env, "quiet"))
        return U_LOG_ERROR;
    return U_LOG_INFO;
}

void u_log(u_log_level level, const char *fmt, ...)
{
    if (level < log_threshold())
        return;
    static const char *const prefix[] = {"debug", "info", "warning", "error"};
    fprintf(stderr, "xrsc: %s: ", prefix[level]);
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}
