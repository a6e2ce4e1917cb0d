// SPDX-License-Identifier: MIT
/**
 * @file hs_opt.h
 * @brief One option table per command: each row names an option, its argument, its help text,
 *        the field it sets and the parser that sets it. The command line is read with glibc's
 *        getopt_long from the table, `--help` is printed from it, and the value options that
 *        `--config` files and run.conf need (hs_args.h, hs_run.h) are listed from it.
 */
#pragma once

#include <stddef.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct hs_opt hs_opt;

/** What a row's parser gets: the command (for errors), its row, the value as typed (NULL for a
 *  flag), its field (target + row->offset) and the whole target struct. */
typedef struct hs_opt_arg {
    const char *cmd;
    const hs_opt *opt;
    const char *value;
    void *field;
    void *target;
} hs_opt_arg;

/** Sets the field from the value; returns 0, or the exit status of hs_bad_arg (printed). */
typedef int (*hs_opt_fn)(const hs_opt_arg *a);

/**
 * One row. name NULL: a text row, help (if any) printed as it is in --help (headings, notes);
 * with a parser it also takes the arguments that are not options (value: each in turn; at most
 * one such row; without one such an argument is an error). Else an
 * option: name with its dashes ("--frames"), arg the value's placeholder ("N"; NULL: a flag,
 * which takes no value), help its lines without indentation ('\n' between them; NULL: not
 * listed), parse its parser (NULL: the value is stored as const char *, a flag sets a bool
 * true), offset its field in the target struct, data what the parser needs besides.
 */
struct hs_opt {
    const char *name;
    const char *arg;
    const char *help;
    hs_opt_fn parse;
    size_t offset;
    const void *data;
};

/** Most option rows a table may have. */
#define HS_OPT_MAX 128

/** hs_opt_parse's result after -h or --help (the caller prints its help, exits 0). */
#define HS_OPT_HELP (-3)

/**
 * Reads argv[first..argc) with getopt_long ("--opt value", "--opt=value", no abbreviations, no
 * argument that is not an option): every option's parser into target. An unknown option, a
 * flag given a value, a value option without one or an argument that is not an option prints
 * "CMD: error: --OPT: WHY" (hs_bad_arg) and returns its exit status. Returns HS_ARG_NEXT (-1,
 * hs_args.h) when all was read, HS_OPT_HELP at -h/--help.
 */
int hs_opt_parse(const char *cmd, const hs_opt *t, size_t n, int argc, char **argv, int first,
                 void *target);

/** The names of the options with a value (for hs_args_spec and run.conf) into out[cap];
 *  returns how many. */
size_t hs_opt_value_names(const hs_opt *t, size_t n, const char **out, size_t cap);

/** Prints the table as --help lines: text rows as they are, options as "  --name ARG" and
 *  their help in a column (continuation lines aligned). */
void hs_opt_print_help(FILE *f, const hs_opt *t, size_t n);

/* Parsers for common fields. A number's row data is an hs_opt_num: bounds and the error text. */
typedef struct hs_opt_num {
    double min, max;
    const char *why; /**< e.g. "expected 1..4096" */
} hs_opt_num;
/** uint32_t field: a whole unsigned number in [min, max]. */
int hs_opt_u32(const hs_opt_arg *a);
/** float field: a number in [min, max]. */
int hs_opt_float(const hs_opt_arg *a);
/** float field: a number in (0, max] with hs_opt_num.why, or "expected a number in (0, MAX]". */
int hs_opt_positive(const hs_opt_arg *a);
/** double field: a number in [min, max]. */
int hs_opt_double(const hs_opt_arg *a);
/** bool field: "on" or "off". */
int hs_opt_on_off(const hs_opt_arg *a);

/** An enum-like int field: data is a NULL-terminated list of hs_opt_name, the first row's
 *  `why` text (e.g. "expected single, multi or adaptive") used for every other value. */
typedef struct hs_opt_name {
    const char *name;
    int value;
    const char *why;
} hs_opt_name;
int hs_opt_enum(const hs_opt_arg *a);
/** The name of value in names (as typed, e.g. for run.conf), or NULL when none has it. */
const char *hs_opt_enum_name(const hs_opt_name *names, int value);

#ifdef __cplusplus
}
#endif
