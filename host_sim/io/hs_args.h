// SPDX-License-Identifier: MIT
/**
 * @file hs_args.h
 * @brief Command-line helpers shared by `xrsc`, `xrsc metrics` and `xrsc bench`: whole-string
 *        number parsing, option-list lookup, the one format of a bad-argument error, and the
 *        creation of output folders.
 */
#pragma once

#include "xrsc/result.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** The exit code of a bad command line. */
#define HS_EXIT_BAD_ARGS 2
/** Exit status of a run that finished but that the Vulkan validation layer (`--validation`)
 *  found errors in: the images exist, but a GPU may not render them the same. */
#define HS_EXIT_VALIDATION 3

/**
 * Prints "CMD: error: FLAG[ VALUE]: WHY (see CMD --help)" to stderr (value may be NULL) and
 * returns HS_EXIT_BAD_ARGS. cmd is the command as typed, e.g. "xrsc" or "xrsc bench".
 */
int hs_bad_arg(const char *cmd, const char *flag, const char *value, const char *why);

/** A decimal unsigned 32-bit integer, the whole of s (no sign); *out is set only on success. */
bool hs_parse_u32(const char *s, uint32_t *out);

/** A byte count: a decimal integer >= 1 with an optional binary suffix K, M or G (KiB, MiB,
 *  GiB), the whole of s; *out is set only on success. */
bool hs_parse_bytes(const char *s, uint64_t *out);

/** A number (strtod), the whole of s, not NaN; infinities pass (callers bound the value). *out
 *  is set only on success. */
bool hs_parse_f(const char *s, double *out);

/** "WxH", each in [min, max]; *w, *h set only on success. */
bool hs_parse_size(const char *s, unsigned min, unsigned max, unsigned *w, unsigned *h);

/** "on" (true) or "off" (false); *out is set only on success. */
bool hs_parse_on_off(const char *s, bool *out);

/** "R,G,B", each >= 0; out set only on success. */
bool hs_parse_rgb(const char *s, float out[3]);

/* A parse's result besides an exit status (>= 0): all was read, go on (hs_opt_parse). */
#define HS_ARG_NEXT (-1)

/** Whether flag is one of the count options in list. */
bool hs_arg_in(const char *flag, const char *const *list, size_t count);

/** Most arguments a command line and its config files may add up to. */
#define HS_ARGS_MAX 1024
/** Largest total size of the config files of one command line, bytes. */
#define HS_ARGS_CONFIG_MAX 65536

/** What hs_args_prepare needs to know of a command. */
typedef struct hs_args_spec {
    const char *cmd;                   /**< as typed, for errors: "xrsc", "xrsc bench" */
    const char *const *value_options;  /**< the options that take a value, e.g. "--frames" */
    size_t value_count;
    bool config;                       /**< --config FILE is read (else it is left as typed) */
    /** Not NULL: the only flags a config file may hold, any other key without a value is an
     *  error naming file, line and key; NULL: such keys are kept for the option table. */
    const char *const *flag_options;
    size_t flag_count;
    /** Options ("--key", "value", ...) put before the lines of a config file that is a run's
     *  record (run.conf: its first line starts with HS_ARGS_RECORD_HEAD and holds
     *  HS_ARGS_RECORD_MARK): the settings that older builds' run.conf did not name, at the
     *  values those builds used, so an old run.conf repeats its run; the file's lines win. */
    const char *const *record_defaults;
    size_t record_default_count;
} hs_args_spec;

/** How a run's record (run.conf, hs_run.h) starts: "# xrsc VERSION, run started TIME: ...". */
#define HS_ARGS_RECORD_HEAD "# xrsc "
#define HS_ARGS_RECORD_MARK ", run started "

/**
 * A command line after hs_args_prepare: argv[0..argc) (argv[argc] is NULL) points into the
 * original argv and into text (the config files' values). Large (about 72 KiB): one lives on
 * the stack of a command's main function, as long as the options that point into it.
 */
typedef struct hs_args {
    int argc;
    char *argv[HS_ARGS_MAX + 1];
    char text[2 * HS_ARGS_CONFIG_MAX]; /**< keys get "--" and a terminator: at most twice */
    size_t text_used;
} hs_args;

/**
 * The --config expansion of `xrsc replay`, before its option table is read (hs_opt_parse;
 * run.conf records the result): argv[1..] is copied into out with
 *  - "--name=value" split into "--name" "value" when --name is in spec->value_options; any
 *    other "--name=..." is an error naming --name (a flag takes no value, or it is unknown);
 *  - with spec->config, "--config FILE" (or --config=FILE) replaced by the options of FILE, in
 *    place, so options after it override it: one per line, "key = value", "key value",
 *    "--key value", "--key=value", or a flag alone ("key" / "--key"); blank lines and lines
 *    starting with '#' are skipped, a value may be double-quoted (\" and \\ escapes). A key
 *    that takes no value given one, a value option without one, a nested --config, or a file
 *    over HS_ARGS_CONFIG_MAX is an error naming the file, line and key (xrsc_diag format).
 * The value after a value option is never split or expanded, as with getopt_long. Returns 0,
 * or HS_EXIT_BAD_ARGS after printing the error to stderr.
 */
int hs_args_prepare(hs_args *out, const hs_args_spec *spec, int argc, char **argv);

/**
 * The config-file part of hs_args_prepare on text in memory (terminated; changed in place):
 * appends its options to out (copies: text may go afterwards). Errors fill diag with path,
 * line and key: XRSC_ERROR_INVALID_ARGUMENT, nothing printed.
 */
xrsc_result hs_args_config_text(hs_args *out, const hs_args_spec *spec, const char *path,
                                char *text, xrsc_diag *diag);

/**
 * mkdir -p path (folders that exist already are fine). Errors name `field` (the option that gave
 * the path, e.g. "--out") in diag: XRSC_ERROR_INVALID_ARGUMENT for an empty path or one of 1024
 * bytes or more, XRSC_ERROR_IO (diag.file: the folder) for a folder that cannot be created.
 */
xrsc_result hs_make_dirs(const char *path, const char *field, xrsc_diag *diag);

#ifdef __cplusplus
}
#endif
