// SPDX-License-Identifier: MIT
/**
 * @file hs_pose_stream.c
 * @brief Pose-stream parsing (canonical format and importers), saving, lookup and anchoring.
 *
 * The formats, the axis conversions and every rule applied here are specified in
 * poses/README.md; keep the two in step.
 */
#include "hs_pose_stream.h"

#include "u_diag.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

/** |(|q| - 1)| above this is XRSC_ERROR_QUAT_NOT_UNIT (poses/README.md, "Quaternions"). */
#define HS_QUAT_UNIT_TOLERANCE 1e-3
/** Quaternions off unit length by more than this (but within tolerance) are renormalised;
 *  below it they are kept bit for bit, so save -> load round trips exactly. */
#define HS_QUAT_RENORMALIZE_ABOVE 1e-6
/** Longest accepted field, in bytes (a double needs at most ~25 characters). */
#define HS_MAX_FIELD_CHARS 64
/** First sample array capacity; it doubles as needed. */
#define HS_INITIAL_CAPACITY 256
/** .NET ticks are 100 ns (System.DateTime.Ticks). */
#define HS_NS_PER_DOTNET_TICK 100
#define HS_NS_PER_SECOND 1e9
/** Largest ns span representable in int64 (as a double it rounds up to 2^63, so compare <). */
#define HS_MAX_SPAN_NS_DOUBLE 9223372036854775807.0

#define HS_CANONICAL_MAGIC "xrsc-poses"
#define HS_CANONICAL_VERSION 1
#define HS_PRED6DOF_HEADER "timestamp,x,y,z,qx,qy,qz,qw"
#define HS_360VIDEO_HEADER "timestamp viewpoint w x y z"

/** Canonical v1 columns; the order here is the semantic slot, not the file order. */
enum hs_col {
    HS_COL_T,
    HS_COL_PX,
    HS_COL_PY,
    HS_COL_PZ,
    HS_COL_QX,
    HS_COL_QY,
    HS_COL_QZ,
    HS_COL_QW,
    HS_COL_COUNT
};
static const char *const hs_col_names[HS_COL_COUNT] = {"t_ns", "px", "py", "pz",
                                                       "qx",   "qy", "qz", "qw"};
static const char *const hs_pred6dof_names[8] = {"timestamp", "x",  "y",  "z",
                                                 "qx",        "qy", "qz", "qw"};
static const char *const hs_360video_names[6] = {"timestamp", "viewpoint", "w", "x", "y", "z"};

/** Parser state over one in-memory buffer (which need not be NUL-terminated), or over a file
 *  read line by line into buf. */
typedef struct hs_parser {
    const char *name;
    const char *data;
    size_t size;
    size_t pos;
    FILE *file; /**< non-NULL: lines come from here (data unused) */
    char *buf;  /**< HS_POSE_MAX_LINE_CHARS: the file's current line */
    int line; /**< 1-based number of the line last returned by next_line */
    xrsc_diag *diag;
    hs_pose_stream *stream;
    size_t capacity;
    int64_t first_raw;                  /**< first timestamp in the file's own integer unit */
    int64_t last_raw;                   /**< previous sample's timestamp in that unit */
    double first_seconds, last_seconds; /**< the same for timestamps in seconds */
} hs_parser;

/** A field inside the current line: [begin, begin + len). */
typedef struct hs_field {
    const char *begin;
    size_t len;
} hs_field;

/* ---- lines and fields ------------------------------------------------------------------- */

/** A file's next line into p->buf (longer lines cut; a UTF-8 byte order mark dropped). */
static bool next_file_line(hs_parser *p, const char **out_begin, size_t *out_len)
{
    size_t n = 0;
    int c = EOF;
    bool any = false;
    while ((c = getc_unlocked(p->file)) != EOF) {
        any = true;
        if (c == '\n')
            break;
        if (n < HS_POSE_MAX_LINE_CHARS)
            p->buf[n++] = (char)c;
    }
    if (!any)
        return false;
    const char *begin = p->buf;
    if (p->line == 0 && n >= 3 && !memcmp(begin, "\xEF\xBB\xBF", 3)) {
        begin += 3;
        n -= 3;
    }
    if (n > 0 && begin[n - 1] == '\r')
        n--;
    p->line++;
    *out_begin = begin;
    *out_len = n;
    return true;
}

/** Returns false at end of data. Strips a trailing '\r'. */
static bool next_line(hs_parser *p, const char **out_begin, size_t *out_len)
{
    if (p->file)
        return next_file_line(p, out_begin, out_len);
    if (p->pos >= p->size)
        return false;
    const char *begin = p->data + p->pos;
    const char *nl = memchr(begin, '\n', p->size - p->pos);
    size_t len = nl ? (size_t)(nl - begin) : p->size - p->pos;
    p->pos += len + (nl ? 1 : 0);
    if (len > 0 && begin[len - 1] == '\r')
        len--;
    p->line++;
    *out_begin = begin;
    *out_len = len;
    return true;
}

static bool is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

static void trim(const char **begin, size_t *len)
{
    while (*len > 0 && is_space(**begin)) {
        (*begin)++;
        (*len)--;
    }
    while (*len > 0 && is_space((*begin)[*len - 1]))
        (*len)--;
}

static bool is_blank_or_comment(const char *begin, size_t len)
{
    trim(&begin, &len);
    return len == 0 || begin[0] == '#';
}

static bool line_equals(const char *begin, size_t len, const char *text)
{
    trim(&begin, &len);
    return len == strlen(text) && memcmp(begin, text, len) == 0;
}

/**
 * Splits a line on whitespace (sep == 0) or on commas (sep == ','), filling up to max fields.
 * Returns the number of fields found, which may exceed max (the extra ones are not stored).
 * With commas, fields are trimmed and one empty trailing field (a line ending in ", ") is
 * not counted.
 */
static size_t split_fields(const char *begin, size_t len, char sep, hs_field *out, size_t max)
{
    size_t n = 0;
    if (sep == 0) {
        size_t i = 0;
        while (i < len) {
            while (i < len && is_space(begin[i]))
                i++;
            if (i >= len)
                break;
            size_t start = i;
            while (i < len && !is_space(begin[i]))
                i++;
            if (n < max) {
                out[n].begin = begin + start;
                out[n].len = i - start;
            }
            n++;
        }
        return n;
    }
    size_t start = 0;
    for (size_t i = 0; i <= len; i++) {
        if (i < len && begin[i] != sep)
            continue;
        const char *fb = begin + start;
        size_t fl = i - start;
        trim(&fb, &fl);
        bool last = i == len;
        if (!(last && fl == 0 && n > 0)) { /* the quirk: a trailing ", " adds no field */
            if (n < max) {
                out[n].begin = fb;
                out[n].len = fl;
            }
            n++;
        }
        start = i + 1;
    }
    return n;
}

/** Copies a field into a NUL-terminated buffer; false if it is too long or holds a NUL. */
static bool field_to_cstr(hs_field f, char buf[HS_MAX_FIELD_CHARS + 1])
{
    if (f.len == 0 || f.len > HS_MAX_FIELD_CHARS || memchr(f.begin, '\0', f.len))
        return false;
    memcpy(buf, f.begin, f.len);
    buf[f.len] = '\0';
    return true;
}

/* ---- numbers ---------------------------------------------------------------------------- */

/** A number field; as_float: it is stored as a float, so beyond float range counts as inf. */
static xrsc_result parse_number(hs_parser *p, hs_field f, const char *field, bool as_float,
                                double *out)
{
    char buf[HS_MAX_FIELD_CHARS + 1];
    if (!field_to_cstr(f, buf))
        return u_diag_set(p->diag, XRSC_ERROR_BAD_NUMBER, p->name, p->line, field,
                          "empty or over-long field (limit %d characters)", HS_MAX_FIELD_CHARS);
    char *end = NULL;
    errno = 0;
    double v = strtod(buf, &end);
    if (end == buf || *end != '\0')
        return u_diag_set(p->diag, XRSC_ERROR_BAD_NUMBER, p->name, p->line, field,
                          "'%s' is not a number", buf);
    if (!isfinite(v) || (as_float && !isfinite((float)v)))
        return u_diag_set(p->diag, XRSC_ERROR_NAN, p->name, p->line, field,
                          "'%s' is NaN, infinite or out of float range", buf);
    *out = v;
    return XRSC_OK;
}

static xrsc_result parse_double(hs_parser *p, hs_field f, const char *field, double *out)
{
    return parse_number(p, f, field, true, out);
}

/** An integer field (timestamps in ns or ticks, viewpoint ids). */
/** Parses count fields f[i] (named names[i]) as doubles into out[i]. */
static xrsc_result parse_doubles(hs_parser *p, const hs_field *f, const char *const *names,
                                 int count, double *out)
{
    for (int i = 0; i < count; i++) {
        xrsc_result r = parse_double(p, f[i], names[i], &out[i]);
        if (r != XRSC_OK)
            return r;
    }
    return XRSC_OK;
}

static xrsc_result parse_int64(hs_parser *p, hs_field f, const char *field, int64_t *out)
{
    char buf[HS_MAX_FIELD_CHARS + 1];
    if (!field_to_cstr(f, buf))
        return u_diag_set(p->diag, XRSC_ERROR_BAD_NUMBER, p->name, p->line, field,
                          "empty or over-long field (limit %d characters)", HS_MAX_FIELD_CHARS);
    char *end = NULL;
    errno = 0;
    long long v = strtoll(buf, &end, 10);
    if (end == buf || *end != '\0' || errno == ERANGE) {
        /* Say NaN/inf when it is one, so the error class matches the float fields. */
        char *fend = NULL;
        double d = strtod(buf, &fend);
        if (fend != buf && *fend == '\0' && !isfinite(d))
            return u_diag_set(p->diag, XRSC_ERROR_NAN, p->name, p->line, field,
                              "'%s' is NaN or infinite", buf);
        return u_diag_set(p->diag, XRSC_ERROR_BAD_NUMBER, p->name, p->line, field,
                          "'%s' is not an integer in the int64 range", buf);
    }
    *out = (int64_t)v;
    return XRSC_OK;
}

/** out = a - b; false on int64 overflow. */
static bool sub_i64(int64_t a, int64_t b, int64_t *out)
{
    if ((b < 0 && a > INT64_MAX + b) || (b > 0 && a < INT64_MIN + b))
        return false;
    *out = a - b;
    return true;
}

/** A sample line with more fields than columns: the field is named "field N" (1-based). */
static xrsc_result extra_field(hs_parser *p, size_t ncols, size_t n)
{
    char field[32];
    snprintf(field, sizeof(field), "field %zu", ncols + 1);
    return u_diag_set(p->diag, XRSC_ERROR_UNKNOWN_COLUMN, p->name, p->line, field,
                      "%zu or more fields but %zu columns", n, ncols);
}

/* ---- samples ---------------------------------------------------------------------------- */

/** Checks |q| and renormalises within tolerance (poses/README.md, "Quaternions"). */
static xrsc_result check_quat(hs_parser *p, XrQuaternionf *q, const char *field)
{
    double n =
        sqrt((double)q->x * q->x + (double)q->y * q->y + (double)q->z * q->z + (double)q->w * q->w);
    double dev = fabs(n - 1.0);
    if (!(dev <= HS_QUAT_UNIT_TOLERANCE))
        return u_diag_set(p->diag, XRSC_ERROR_QUAT_NOT_UNIT, p->name, p->line, field,
                          "|q| = %.9g differs from 1 by more than %g", n, HS_QUAT_UNIT_TOLERANCE);
    if (dev > HS_QUAT_RENORMALIZE_ABOVE)
        *q = xrsc_quat_normalize(*q);
    return XRSC_OK;
}

/** Appends (time_ns, pose) to the array *samples of *count entries and *capacity slots,
 *  doubling it when full; out of memory is the parser's error at its current line. */
static xrsc_result append_sample(hs_parser *p, hs_pose_sample **samples, size_t *count,
                                 size_t *capacity, int64_t time_ns, XrPosef pose)
{
    if (*count == *capacity) {
        size_t cap = *capacity ? *capacity * 2 : HS_INITIAL_CAPACITY;
        hs_pose_sample *n = realloc(*samples, cap * sizeof(*n));
        if (!n)
            return u_diag_set(p->diag, XRSC_ERROR_OUT_OF_MEMORY, p->name, p->line, "",
                              "cannot grow a pose sample array to %zu samples", cap);
        *samples = n;
        *capacity = cap;
    }
    (*samples)[*count] = (hs_pose_sample){.time_ns = time_ns, .pose = pose};
    (*count)++;
    return XRSC_OK;
}

/**
 * Appends a sample whose time (relative to the first sample) is time_ns; the caller has
 * already checked it against the previous sample. Equal times: the later sample replaces the
 * earlier one.
 */
static xrsc_result push_sample(hs_parser *p, int64_t time_ns, XrPosef pose)
{
    hs_pose_stream *s = p->stream;
    if (s->count > 0 && s->samples[s->count - 1].time_ns == time_ns) {
        s->samples[s->count - 1].pose = pose;
        s->dropped_duplicates++;
        return XRSC_OK;
    }
    return append_sample(p, &s->samples, &s->count, &p->capacity, time_ns, pose);
}

/**
 * Converts a timestamp in the file's integer unit (ns_per_unit nanoseconds) into ns since the
 * first sample, rejecting times earlier than the previous sample's.
 */
static xrsc_result time_from_raw(hs_parser *p, int64_t raw, int64_t ns_per_unit, const char *field,
                                 int64_t *out_ns)
{
    if (p->stream->count == 0) {
        p->first_raw = raw;
        p->last_raw = raw;
        *out_ns = 0;
        return XRSC_OK;
    }
    if (raw < p->last_raw)
        return u_diag_set(p->diag, XRSC_ERROR_TIME_BACKWARDS, p->name, p->line, field,
                          "timestamp %" PRId64 " is earlier than the previous sample's %" PRId64,
                          raw, p->last_raw);
    int64_t rel;
    if (!sub_i64(raw, p->first_raw, &rel) || rel > INT64_MAX / ns_per_unit)
        return u_diag_set(p->diag, XRSC_ERROR_BAD_NUMBER, p->name, p->line, field,
                          "timestamp %" PRId64 " is too far from the first sample's "
                          "(int64 nanoseconds overflow)",
                          raw);
    p->last_raw = raw;
    *out_ns = rel * ns_per_unit;
    return XRSC_OK;
}

/** Appends a sample whose timestamp is raw in the file's unit (see time_from_raw). */
static xrsc_result push_raw_sample(hs_parser *p, int64_t raw, int64_t ns_per_unit,
                                   const char *field, XrPosef pose)
{
    int64_t t_ns = 0;
    xrsc_result r = time_from_raw(p, raw, ns_per_unit, field, &t_ns);
    if (r != XRSC_OK)
        return r;
    return push_sample(p, t_ns, pose);
}

/* ---- canonical format ------------------------------------------------------------------- */

/** Reads the `columns` line: col_of_slot[slot] = field index, or -1 when absent. */
static xrsc_result parse_columns(hs_parser *p, const char *begin, size_t len,
                                 int col_of_slot[HS_COL_COUNT], size_t *out_ncols,
                                 int slot_of_col[HS_COL_COUNT])
{
    hs_field f[HS_COL_COUNT + 2];
    size_t n = split_fields(begin, len, 0, f, HS_COL_COUNT + 2);
    for (int i = 0; i < HS_COL_COUNT; i++)
        col_of_slot[i] = -1;
    /* More than HS_COL_COUNT names always hold an unknown or a repeated one, reported below. */
    size_t stored = n < HS_COL_COUNT + 2 ? n : HS_COL_COUNT + 2;
    for (size_t i = 1; i < stored; i++) {
        int slot = -1;
        for (int k = 0; k < HS_COL_COUNT; k++) {
            if (f[i].len == strlen(hs_col_names[k]) &&
                memcmp(f[i].begin, hs_col_names[k], f[i].len) == 0)
                slot = k;
        }
        char name[HS_MAX_FIELD_CHARS + 1] = "";
        if (!field_to_cstr(f[i], name))
            snprintf(name, sizeof(name), "column %zu", i);
        if (slot < 0)
            return u_diag_set(p->diag, XRSC_ERROR_UNKNOWN_COLUMN, p->name, p->line, name,
                              "unknown column (v1 knows t_ns px py pz qx qy qz qw)");
        if (col_of_slot[slot] >= 0)
            return u_diag_set(p->diag, XRSC_ERROR_BAD_HEADER, p->name, p->line, name,
                              "column named twice");
        if (i - 1 >= HS_COL_COUNT) /* unreachable by the pigeonhole argument above */
            return u_diag_set(p->diag, XRSC_ERROR_UNKNOWN_COLUMN, p->name, p->line, name,
                              "more than %d columns", HS_COL_COUNT);
        col_of_slot[slot] = (int)(i - 1);
        slot_of_col[i - 1] = slot;
    }
    static const int required[] = {HS_COL_T, HS_COL_QX, HS_COL_QY, HS_COL_QZ, HS_COL_QW};
    for (size_t k = 0; k < sizeof(required) / sizeof(required[0]); k++) {
        if (col_of_slot[required[k]] < 0)
            return u_diag_set(p->diag, XRSC_ERROR_BAD_HEADER, p->name, p->line,
                              hs_col_names[required[k]], "required column is missing");
    }
    int npos = (col_of_slot[HS_COL_PX] >= 0) + (col_of_slot[HS_COL_PY] >= 0) +
               (col_of_slot[HS_COL_PZ] >= 0);
    if (npos != 0 && npos != 3) {
        for (int k = HS_COL_PX; k <= HS_COL_PZ; k++) {
            if (col_of_slot[k] < 0)
                return u_diag_set(p->diag, XRSC_ERROR_BAD_HEADER, p->name, p->line, hs_col_names[k],
                                  "px, py and pz must be all present or all absent");
        }
    }
    *out_ncols = n - 1;
    return XRSC_OK;
}

static xrsc_result parse_canonical(hs_parser *p)
{
    const char *line;
    size_t len;
    bool have_header = false, have_columns = false;
    int col_of_slot[HS_COL_COUNT], slot_of_col[HS_COL_COUNT];
    size_t ncols = 0;
    xrsc_result r;
    while (next_line(p, &line, &len)) {
        if (is_blank_or_comment(line, len))
            continue;
        hs_field f[HS_COL_COUNT + 1];
        size_t n = split_fields(line, len, 0, f, HS_COL_COUNT + 1);
        if (!have_header) {
            if (f[0].len != strlen(HS_CANONICAL_MAGIC) ||
                memcmp(f[0].begin, HS_CANONICAL_MAGIC, f[0].len) != 0)
                return u_diag_set(p->diag, XRSC_ERROR_BAD_HEADER, p->name, p->line, "header",
                                  "expected '%s %d'", HS_CANONICAL_MAGIC, HS_CANONICAL_VERSION);
            if (n != 2 || f[1].len != 1 || f[1].begin[0] != '0' + HS_CANONICAL_VERSION)
                return u_diag_set(p->diag, XRSC_ERROR_BAD_HEADER, p->name, p->line, "version",
                                  "unsupported version (this reader knows version %d)",
                                  HS_CANONICAL_VERSION);
            have_header = true;
            continue;
        }
        if (f[0].len == strlen("columns") && memcmp(f[0].begin, "columns", f[0].len) == 0) {
            if (have_columns)
                return u_diag_set(p->diag, XRSC_ERROR_BAD_HEADER, p->name, p->line, "columns",
                                  "a second 'columns' line");
            r = parse_columns(p, line, len, col_of_slot, &ncols, slot_of_col);
            if (r != XRSC_OK)
                return r;
            p->stream->orientation_only = col_of_slot[HS_COL_PX] < 0;
            have_columns = true;
            continue;
        }
        if (!have_columns)
            return u_diag_set(p->diag, XRSC_ERROR_BAD_HEADER, p->name, p->line, "columns",
                              "a 'columns' line must come before the first sample");
        if (n < ncols)
            return u_diag_set(p->diag, XRSC_ERROR_TRUNCATED_LINE, p->name, p->line,
                              hs_col_names[slot_of_col[n]], "%zu of %zu fields", n, ncols);
        if (n > ncols)
            return extra_field(p, ncols, n);
        double v[HS_COL_COUNT] = {0, 0, 0, 0, 0, 0, 0, 1};
        int64_t t_raw = 0;
        for (size_t i = 0; i < ncols; i++) {
            int slot = slot_of_col[i];
            r = slot == HS_COL_T ? parse_int64(p, f[i], hs_col_names[slot], &t_raw)
                                 : parse_double(p, f[i], hs_col_names[slot], &v[slot]);
            if (r != XRSC_OK)
                return r;
        }
        XrPosef pose;
        pose.position.x = (float)v[HS_COL_PX];
        pose.position.y = (float)v[HS_COL_PY];
        pose.position.z = (float)v[HS_COL_PZ];
        pose.orientation.x = (float)v[HS_COL_QX];
        pose.orientation.y = (float)v[HS_COL_QY];
        pose.orientation.z = (float)v[HS_COL_QZ];
        pose.orientation.w = (float)v[HS_COL_QW];
        r = check_quat(p, &pose.orientation, "qx qy qz qw");
        if (r != XRSC_OK)
            return r;
        r = push_raw_sample(p, t_raw, 1, "t_ns", pose);
        if (r != XRSC_OK)
            return r;
    }
    if (!have_header)
        return u_diag_set(p->diag, XRSC_ERROR_EMPTY_FILE, p->name, 0, "",
                          "no header and no samples");
    return XRSC_OK;
}

/* ---- importers -------------------------------------------------------------------------- */

/** Skips blank lines; returns false at end of data. */
static bool next_content_line(hs_parser *p, const char **line, size_t *len)
{
    while (next_line(p, line, len)) {
        const char *b = *line;
        size_t l = *len;
        trim(&b, &l);
        if (l > 0)
            return true;
    }
    return false;
}

/** The first content line must be the importer's fixed header. */
static xrsc_result expect_header(hs_parser *p, const char *header)
{
    const char *line;
    size_t len;
    if (!next_content_line(p, &line, &len))
        return u_diag_set(p->diag, XRSC_ERROR_EMPTY_FILE, p->name, 0, "", "empty file");
    if (!line_equals(line, len, header))
        return u_diag_set(p->diag, XRSC_ERROR_BAD_HEADER, p->name, p->line, "header",
                          "expected '%s'", header);
    return XRSC_OK;
}

/** A sample line of a fixed-column importer holds exactly ncols fields; names[i] names field i. */
static xrsc_result check_field_count(hs_parser *p, size_t n, size_t ncols, const char *const *names)
{
    if (n < ncols)
        return u_diag_set(p->diag, XRSC_ERROR_TRUNCATED_LINE, p->name, p->line, names[n],
                          "%zu of %zu fields", n, ncols);
    if (n > ncols)
        return extra_field(p, ncols, n);
    return XRSC_OK;
}

/** The pred6dof HoloLens CSV (poses/README.md, "Importer: pred6dof"). */
static xrsc_result parse_pred6dof(hs_parser *p)
{
    const char *line;
    size_t len;
    xrsc_result r = expect_header(p, HS_PRED6DOF_HEADER);
    if (r != XRSC_OK)
        return r;
    while (next_content_line(p, &line, &len)) {
        hs_field f[9];
        size_t n = split_fields(line, len, ',', f, 9);
        r = check_field_count(p, n, 8, hs_pred6dof_names);
        if (r != XRSC_OK)
            return r;
        int64_t ticks;
        r = parse_int64(p, f[0], "timestamp", &ticks);
        if (r != XRSC_OK)
            return r;
        double v[8];
        r = parse_doubles(p, &f[1], &hs_pred6dof_names[1], 7, &v[1]);
        if (r != XRSC_OK)
            return r;
        /* Left-handed, +Z forward (Unity) -> OpenXR: mirror z; the rotation's x and y
         * components change sign (poses/README.md). */
        XrPosef pose;
        pose.position.x = (float)v[1];
        pose.position.y = (float)v[2];
        pose.position.z = (float)-v[3];
        pose.orientation.x = (float)-v[4];
        pose.orientation.y = (float)-v[5];
        pose.orientation.z = (float)v[6];
        pose.orientation.w = (float)v[7];
        r = check_quat(p, &pose.orientation, "qx qy qz qw");
        if (r != XRSC_OK)
            return r;
        r = push_raw_sample(p, ticks, HS_NS_PER_DOTNET_TICK, "timestamp", pose);
        if (r != XRSC_OK)
            return r;
    }
    return XRSC_OK;
}

/** The 360-video orientation trace (poses/README.md, "Importer: 360video"). */
static xrsc_result parse_360video(hs_parser *p)
{
    const char *line;
    size_t len;
    xrsc_result r = expect_header(p, HS_360VIDEO_HEADER);
    if (r != XRSC_OK)
        return r;
    p->stream->orientation_only = true;
    while (next_content_line(p, &line, &len)) {
        hs_field f[7];
        size_t n = split_fields(line, len, 0, f, 7);
        r = check_field_count(p, n, 6, hs_360video_names);
        if (r != XRSC_OK)
            return r;
        double seconds;
        r = parse_number(p, f[0], "timestamp", false, &seconds);
        if (r != XRSC_OK)
            return r;
        int64_t viewpoint;
        r = parse_int64(p, f[1], "viewpoint", &viewpoint);
        if (r != XRSC_OK)
            return r;
        double q[4]; /* w x y z */
        r = parse_doubles(p, &f[2], &hs_360video_names[2], 4, q);
        if (r != XRSC_OK)
            return r;
        /* The trace is right-handed with x forward, y left, z up; OpenXR's x (right) is -y,
         * its y (up) is z and its z (back) is -x. A proper rotation of the axes maps the
         * quaternion's vector part the same way (poses/README.md). */
        XrPosef pose = xrsc_pose_identity();
        pose.orientation.x = (float)-q[2];
        pose.orientation.y = (float)q[3];
        pose.orientation.z = (float)-q[1];
        pose.orientation.w = (float)q[0];
        r = check_quat(p, &pose.orientation, "w x y z");
        if (r != XRSC_OK)
            return r;
        int64_t t_ns = 0;
        if (p->stream->count == 0) {
            p->first_seconds = seconds;
        } else {
            if (seconds < p->last_seconds)
                return u_diag_set(p->diag, XRSC_ERROR_TIME_BACKWARDS, p->name, p->line, "timestamp",
                                  "%.17g s is earlier than the previous %.17g s", seconds,
                                  p->last_seconds);
            double rel_ns = (seconds - p->first_seconds) * HS_NS_PER_SECOND;
            if (!(rel_ns < HS_MAX_SPAN_NS_DOUBLE))
                return u_diag_set(p->diag, XRSC_ERROR_BAD_NUMBER, p->name, p->line, "timestamp",
                                  "%.17g s is too far from the first sample (int64 ns)", seconds);
            t_ns = (int64_t)llround(rel_ns);
        }
        p->last_seconds = seconds;
        r = push_sample(p, t_ns, pose);
        if (r != XRSC_OK)
            return r;
    }
    return XRSC_OK;
}

/* ---- importer: librnr ------------------------------------------------------------------- */

/** librnr `v` body fields after "timestamp type path" (poses/README.md, "Importer: librnr"). */
static const char *const hs_librnr_v_names[13] = {"ox", "oy", "oz",   "ow",   "px",    "py",   "pz",
                                                  "up", "right", "down", "left", "type", "index"};
static const char *const hs_librnr_s_names[8] = {"ox", "oy", "oz", "ow",
                                                 "px", "py", "pz", "basespace"};
static const char *const hs_librnr_head_names[3] = {"timestamp", "type", "path"};
/** XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, the only view configuration imported. */
#define HS_LIBRNR_STEREO_TYPE 2
/** |FOV angle| must stay below a right angle (tan is taken of it). */
#define HS_LIBRNR_MAX_FOV_RAD 1.5707
/** Longest path / space name kept for comparisons. */
#define HS_LIBRNR_MAX_NAME 256

static bool field_equals(hs_field f, const char *text)
{
    return f.len == strlen(text) && memcmp(f.begin, text, f.len) == 0;
}

/** A head pose recorded as a space: the VIEW reference space or a /user/head path. */
static bool librnr_is_head_space(hs_field path)
{
    static const char head[] = "/user/head";
    return field_equals(path, "XR_REFERENCE_SPACE_TYPE_VIEW") ||
           (path.len >= sizeof(head) - 1 && memcmp(path.begin, head, sizeof(head) - 1) == 0);
}

/** Remembers the first name seen in *keep; true if f equals it (or is the first). */
static bool librnr_same_name(char keep[HS_LIBRNR_MAX_NAME], hs_field f)
{
    size_t n = f.len < HS_LIBRNR_MAX_NAME - 1 ? f.len : HS_LIBRNR_MAX_NAME - 1;
    if (keep[0] == '\0') {
        memcpy(keep, f.begin, n);
        keep[n] = '\0';
        return true;
    }
    return strlen(keep) == n && memcmp(keep, f.begin, n) == 0;
}

/** Parses the 7 pose numbers ox oy oz ow px py pz starting at f[0]. */
static xrsc_result librnr_pose(hs_parser *p, const hs_field *f, const char *const *names,
                               XrPosef *out)
{
    double v[7];
    xrsc_result r = parse_doubles(p, f, names, 7, v);
    if (r != XRSC_OK)
        return r;
    out->orientation = (XrQuaternionf){(float)v[0], (float)v[1], (float)v[2], (float)v[3]};
    out->position = (XrVector3f){(float)v[4], (float)v[5], (float)v[6]};
    return check_quat(p, &out->orientation, "ox oy oz ow");
}

/** Appends (or, at an equal time, replaces) a sample with its eye views. */
static xrsc_result librnr_push_views(hs_parser *p, int64_t raw, const hs_view_sample *views,
                                     size_t *views_capacity)
{
    hs_pose_stream *s = p->stream;
    /* Head pose: the eyes' midpoint, the orientation halfway between them. */
    XrPosef head;
    head.position.x = 0.5f * (views->pose[0].position.x + views->pose[1].position.x);
    head.position.y = 0.5f * (views->pose[0].position.y + views->pose[1].position.y);
    head.position.z = 0.5f * (views->pose[0].position.z + views->pose[1].position.z);
    head.orientation = xrsc_quat_normalize(
        xrsc_quat_slerp(views->pose[0].orientation, views->pose[1].orientation, 0.5f));
    xrsc_result r = push_raw_sample(p, raw, 1, "timestamp", head);
    if (r != XRSC_OK)
        return r;
    if (*views_capacity < p->capacity) {
        hs_view_sample *n = realloc(s->views, p->capacity * sizeof(*n));
        if (!n)
            return u_diag_set(p->diag, XRSC_ERROR_OUT_OF_MEMORY, p->name, p->line, "",
                              "cannot grow the view array to %zu samples", p->capacity);
        s->views = n;
        *views_capacity = p->capacity;
    }
    s->views[s->count - 1] = *views;
    return XRSC_OK;
}

/** State of one librnr import (parse_librnr). */
typedef struct hs_librnr {
    char view_space[HS_LIBRNR_MAX_NAME]; /**< the space whose `v` records are used */
    char head_base[HS_LIBRNR_MAX_NAME];  /**< the base space of the `s` head records used */
    size_t views_capacity;
    /** The pair of `v` records being collected: both eyes share one timestamp. */
    hs_view_sample pending;
    int64_t pending_time, last_view_time, last_head_time;
    bool have[2];
    /** `s` head records, kept aside: used only when the file has no stereo `v` pairs. */
    hs_pose_sample *heads;
    size_t head_count, head_capacity;
    uint32_t skipped, incomplete;
} hs_librnr;

/** Appends an `s` head record to the ones kept aside. */
static xrsc_result librnr_keep_head(hs_parser *p, hs_librnr *st, int64_t t, XrPosef pose)
{
    if (t < st->last_head_time)
        return u_diag_set(p->diag, XRSC_ERROR_TIME_BACKWARDS, p->name, p->line, "timestamp",
                          "timestamp %" PRId64 " is earlier than the previous head "
                          "record's %" PRId64,
                          t, st->last_head_time);
    st->last_head_time = t;
    return append_sample(p, &st->heads, &st->head_count, &st->head_capacity, t, pose);
}

/** An `s` (space) record of n fields at time t: kept when it is the head's. */
static xrsc_result librnr_space_record(hs_parser *p, hs_librnr *st, const hs_field *f, size_t n,
                                       int64_t t)
{
    if (n < 11)
        return u_diag_set(p->diag, XRSC_ERROR_TRUNCATED_LINE, p->name, p->line,
                          hs_librnr_s_names[n - 3], "%zu of 11 fields", n);
    if (n > 11)
        return extra_field(p, 11, n);
    XrPosef pose;
    xrsc_result r = librnr_pose(p, &f[3], hs_librnr_s_names, &pose);
    if (r != XRSC_OK)
        return r;
    if (!librnr_is_head_space(f[2]) || !librnr_same_name(st->head_base, f[10])) {
        st->skipped++;
        return XRSC_OK;
    }
    return librnr_keep_head(p, st, t, pose);
}

/** The field of view of a `v` record: up right down left, in the file's order, into a. */
static xrsc_result librnr_fov(hs_parser *p, const hs_field *f, double a[4])
{
    for (int i = 0; i < 4; i++) {
        xrsc_result r = parse_double(p, f[10 + i], hs_librnr_v_names[7 + i], &a[i]);
        if (r != XRSC_OK)
            return r;
        if (fabs(a[i]) >= HS_LIBRNR_MAX_FOV_RAD)
            return u_diag_set(p->diag, XRSC_ERROR_BAD_NUMBER, p->name, p->line,
                              hs_librnr_v_names[7 + i],
                              "%.9g rad is not a field-of-view angle (|angle| < pi/2)", a[i]);
    }
    if (!(a[0] > a[2]) || !(a[1] > a[3]))
        return u_diag_set(p->diag, XRSC_ERROR_BAD_NUMBER, p->name, p->line, "up right down left",
                          "empty field of view (needs up > down and right > left)");
    return XRSC_OK;
}

/** The view configuration type and eye index of a `v` record: PRIMARY_STEREO, 0 or 1. */
static xrsc_result librnr_view_index(hs_parser *p, const hs_field *f, int64_t *out_index)
{
    int64_t vtype, index;
    xrsc_result r;
    if ((r = parse_int64(p, f[14], "type", &vtype)) != XRSC_OK ||
        (r = parse_int64(p, f[15], "index", &index)) != XRSC_OK)
        return r;
    if (vtype != HS_LIBRNR_STEREO_TYPE)
        return u_diag_set(p->diag, XRSC_ERROR_UNKNOWN_COLUMN, p->name, p->line, "type",
                          "view configuration type %" PRId64 " is not imported (only %d, "
                          "PRIMARY_STEREO)",
                          vtype, HS_LIBRNR_STEREO_TYPE);
    if (index != 0 && index != 1)
        return u_diag_set(p->diag, XRSC_ERROR_BAD_NUMBER, p->name, p->line, "index",
                          "view index %" PRId64 " of a stereo pair (0 left, 1 right)", index);
    *out_index = index;
    return XRSC_OK;
}

/** A `v` (view) record of n fields at time t: one eye; a complete pair becomes a sample. */
static xrsc_result librnr_view_record(hs_parser *p, hs_librnr *st, const hs_field *f, size_t n,
                                      int64_t t)
{
    if (n < 16)
        return u_diag_set(p->diag, XRSC_ERROR_TRUNCATED_LINE, p->name, p->line,
                          hs_librnr_v_names[n - 3], "%zu of 16 fields", n);
    if (n > 16)
        return extra_field(p, 16, n);
    XrPosef pose;
    double a[4]; /* up right down left, in the file's order */
    int64_t index = 0;
    xrsc_result r;
    if ((r = librnr_pose(p, &f[3], hs_librnr_v_names, &pose)) != XRSC_OK ||
        (r = librnr_fov(p, f, a)) != XRSC_OK || (r = librnr_view_index(p, f, &index)) != XRSC_OK)
        return r;
    if (!librnr_same_name(st->view_space, f[2])) {
        st->skipped++;
        return XRSC_OK;
    }
    if (t < st->last_view_time)
        return u_diag_set(p->diag, XRSC_ERROR_TIME_BACKWARDS, p->name, p->line, "timestamp",
                          "timestamp %" PRId64 " is earlier than the previous view's %" PRId64, t,
                          st->last_view_time);
    st->last_view_time = t;
    if (t != st->pending_time || (!st->have[0] && !st->have[1])) {
        if (st->have[0] != st->have[1])
            st->incomplete++;
        st->have[0] = st->have[1] = false;
        st->pending_time = t;
    }
    st->pending.pose[index] = pose;
    st->pending.fov[index] = (XrFovf){.angleLeft = (float)a[3],
                                      .angleRight = (float)a[1],
                                      .angleUp = (float)a[0],
                                      .angleDown = (float)a[2]};
    st->have[index] = true;
    if (st->have[0] && st->have[1])
        return librnr_push_views(p, t, &st->pending, &st->views_capacity);
    return XRSC_OK;
}

/** A librnr record type: s, v, b or f (strchr alone would also accept the string's NUL). */
static bool is_librnr_type(char c)
{
    return c != '\0' && strchr("svbf", c) != NULL;
}

/** One content line: the timestamp and record type, then the record by type. */
static xrsc_result librnr_record(hs_parser *p, hs_librnr *st, const char *line, size_t len)
{
    hs_field f[17];
    size_t n = split_fields(line, len, 0, f, 17);
    if (n < 3)
        return u_diag_set(p->diag, XRSC_ERROR_TRUNCATED_LINE, p->name, p->line,
                          hs_librnr_head_names[n], "%zu of at least 3 fields", n);
    int64_t t;
    xrsc_result r = parse_int64(p, f[0], "timestamp", &t);
    if (r != XRSC_OK)
        return r;
    if (f[1].len != 1 || !is_librnr_type(f[1].begin[0]))
        return u_diag_set(p->diag, XRSC_ERROR_UNKNOWN_COLUMN, p->name, p->line, "type",
                          "unknown record type '%.*s' (librnr has s, v, b and f)",
                          (int)(f[1].len < 16 ? f[1].len : 16), f[1].begin);
    char type = f[1].begin[0];
    if (type == 'b' || type == 'f')
        return XRSC_OK; /* input actions: not poses */
    if (type == 's')
        return librnr_space_record(p, st, f, n, t);
    return librnr_view_record(p, st, f, n, t);
}

/** After the last line: the head records when there are no view pairs, then the summary. */
static xrsc_result librnr_finish(hs_parser *p, hs_librnr *st)
{
    if (p->stream->count == 0) {
        for (size_t i = 0; i < st->head_count; i++) {
            xrsc_result r =
                push_raw_sample(p, st->heads[i].time_ns, 1, "timestamp", st->heads[i].pose);
            if (r != XRSC_OK)
                return r;
        }
    }
    if (p->stream->count == 0)
        return u_diag_set(p->diag, XRSC_ERROR_EMPTY_FILE, p->name, 0, "",
                          "no head poses: no stereo pair of `v` records and no `s` record of "
                          "/user/head or XR_REFERENCE_SPACE_TYPE_VIEW");
    if (st->skipped > 0 || st->incomplete > 0)
        U_LOG_W("%s: librnr import used the %s records of '%s'; skipped %u records of other "
                "spaces or devices and %u incomplete eye pairs",
                p->name, p->stream->views ? "view" : "head space",
                p->stream->views ? st->view_space : st->head_base, st->skipped, st->incomplete);
    return XRSC_OK;
}

/** librnr's OpenXR record text (poses/README.md, "Importer: librnr"). */
static xrsc_result parse_librnr(hs_parser *p)
{
    const char *line;
    size_t len;
    xrsc_result r = XRSC_OK;
    hs_librnr st = {.last_view_time = INT64_MIN, .last_head_time = INT64_MIN};
    bool any = false;
    while (r == XRSC_OK && next_content_line(p, &line, &len)) {
        any = true;
        r = librnr_record(p, &st, line, len);
    }
    if (r == XRSC_OK) {
        if (st.have[0] != st.have[1])
            st.incomplete++;
        if (!any)
            r = u_diag_set(p->diag, XRSC_ERROR_EMPTY_FILE, p->name, 0, "", "empty file");
        else
            r = librnr_finish(p, &st);
    }
    free(st.heads);
    return r;
}

/** What the first lines of a source hold (detect_format). */
typedef enum hs_head_kind {
    HS_HEAD_BLANK,    /**< nothing but whitespace */
    HS_HEAD_COMMENTS, /**< comments, no content line */
    HS_HEAD_CONTENT,  /**< a content line (q->line is its number) */
} hs_head_kind;

/** The first line that is neither blank nor a comment decides the format; reads no further. */
static hs_pose_format detect_format(hs_parser *q, hs_head_kind *kind)
{
    const char *line;
    size_t len;
    *kind = HS_HEAD_BLANK;
    while (next_line(q, &line, &len)) {
        if (is_blank_or_comment(line, len)) {
            trim(&line, &len);
            if (len > 0)
                *kind = HS_HEAD_COMMENTS;
            continue;
        }
        *kind = HS_HEAD_CONTENT;
        trim(&line, &len);
        size_t magic = strlen(HS_CANONICAL_MAGIC);
        if (len >= magic && memcmp(line, HS_CANONICAL_MAGIC, magic) == 0 &&
            (len == magic || is_space(line[magic])))
            return HS_POSE_FORMAT_XRSC;
        if (line_equals(line, len, HS_PRED6DOF_HEADER))
            return HS_POSE_FORMAT_PRED6DOF;
        if (line_equals(line, len, HS_360VIDEO_HEADER))
            return HS_POSE_FORMAT_360VIDEO;
        /* librnr has no header: its first record is "<integer> <s|v|b|f> <path> ...". */
        hs_field f[3];
        if (split_fields(line, len, 0, f, 3) >= 3 && f[1].len == 1 &&
            is_librnr_type(f[1].begin[0])) {
            size_t i = f[0].begin[0] == '-' ? 1 : 0;
            bool digits = f[0].len > i;
            for (; i < f[0].len && digits; i++)
                digits = f[0].begin[i] >= '0' && f[0].begin[i] <= '9';
            if (digits)
                return HS_POSE_FORMAT_LIBRNR;
        }
        return HS_POSE_FORMAT_AUTO;
    }
    return HS_POSE_FORMAT_AUTO;
}


/* ---- import by columns (poses/README.md, "Import by columns") --------------------------- */

static const struct {
    const char *name;
    hs_pose_col_role role;
} hs_role_names[] = {
    {"_", HS_POSE_COL_SKIP},  {"skip", HS_POSE_COL_SKIP}, {"t", HS_POSE_COL_T},
    {"time", HS_POSE_COL_T},  {"x", HS_POSE_COL_X},       {"px", HS_POSE_COL_X},
    {"y", HS_POSE_COL_Y},     {"py", HS_POSE_COL_Y},      {"z", HS_POSE_COL_Z},
    {"pz", HS_POSE_COL_Z},    {"qx", HS_POSE_COL_QX},     {"qy", HS_POSE_COL_QY},
    {"qz", HS_POSE_COL_QZ},   {"qw", HS_POSE_COL_QW},
};
static const char *const hs_role_label[HS_POSE_COL_ROLE_COUNT] = {"skip", "t",  "x",  "y", "z",
                                                                  "qx",   "qy", "qz", "qw"};
/** Nanoseconds per unit of hs_pose_time_unit. */
static const double hs_ns_per_unit[] = {1e9, 1e6, 1e3, 1.0, HS_NS_PER_DOTNET_TICK};

xrsc_result hs_pose_columns_parse(const char *spec, const char *time_unit,
                                  const char *handedness, hs_pose_columns *out, xrsc_diag *diag)
{
    memset(out, 0, sizeof(*out));
    if (!spec || !*spec)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--pose-columns",
                          "empty column list (e.g. t,x,y,z,qx,qy,qz,qw)");
    int seen[HS_POSE_COL_ROLE_COUNT] = {0};
    const char *p = spec;
    for (;;) {
        const char *end = strchr(p, ',');
        size_t len = end ? (size_t)(end - p) : strlen(p);
        trim(&p, &len);
        if (out->count >= HS_POSE_MAX_COLUMNS)
            return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--pose-columns",
                              "more than %d columns", HS_POSE_MAX_COLUMNS);
        int role = -1;
        for (size_t i = 0; i < sizeof(hs_role_names) / sizeof(hs_role_names[0]); i++)
            if (strlen(hs_role_names[i].name) == len &&
                strncasecmp(p, hs_role_names[i].name, len) == 0)
                role = (int)hs_role_names[i].role;
        if (role < 0)
            return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--pose-columns",
                              "column %u '%.*s' is not one of t, x, y, z, qx, qy, qz, qw, _",
                              out->count + 1, (int)(len > 32 ? 32 : len), p);
        if (role != HS_POSE_COL_SKIP && seen[role]++)
            return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--pose-columns",
                              "'%s' is named twice", hs_role_label[role]);
        out->role[out->count++] = (uint8_t)role;
        if (!end)
            break;
        p = end + 1;
    }
    int pos = seen[HS_POSE_COL_X] + seen[HS_POSE_COL_Y] + seen[HS_POSE_COL_Z];
    if (!seen[HS_POSE_COL_T] || !seen[HS_POSE_COL_QX] || !seen[HS_POSE_COL_QY] ||
        !seen[HS_POSE_COL_QZ] || !seen[HS_POSE_COL_QW] || (pos != 0 && pos != 3))
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--pose-columns",
                          "needs t, qx, qy, qz, qw and either all or none of x, y, z");
    static const char *const units[] = {"s", "ms", "us", "ns", "ticks"};
    if (time_unit && *time_unit) {
        int u = -1;
        for (int i = 0; i < 5; i++)
            if (!strcmp(time_unit, units[i]))
                u = i;
        if (u < 0)
            return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--pose-time-unit",
                              "'%s' is not s, ms, us, ns or ticks", time_unit);
        out->time_unit = (hs_pose_time_unit)u;
    }
    if (handedness && *handedness) {
        if (!strcmp(handedness, "right"))
            out->handedness = HS_POSE_RIGHT;
        else if (!strcmp(handedness, "left-unity"))
            out->handedness = HS_POSE_LEFT_UNITY;
        else
            return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--pose-handedness",
                              "'%s' is not right or left-unity", handedness);
    }
    return XRSC_OK;
}

/** Delimiter of a delimited line: tab, ';', ',' in that order, else 0 (runs of spaces). */
static char detect_delimiter(const char *line, size_t len)
{
    static const char seps[] = {'\t', ';', ','};
    for (size_t i = 0; i < sizeof(seps); i++)
        if (memchr(line, seps[i], len))
            return seps[i];
    return 0;
}

/** True when some field of the line is not a number (a header line). */
static bool is_header_line(const hs_field *f, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        char buf[HS_MAX_FIELD_CHARS + 1];
        if (!field_to_cstr(f[i], buf))
            return true;
        char *end = NULL;
        strtod(buf, &end);
        if (end == buf || *end != '\0')
            return true;
    }
    return false;
}

/** Time of one sample in ns since the first: integer units exactly, decimal ones rounded. */
static xrsc_result columns_time(hs_parser *p, const hs_pose_columns *c, hs_field f,
                                const char *field, int64_t *out_ns)
{
    if (c->time_unit == HS_POSE_TIME_NS || c->time_unit == HS_POSE_TIME_TICKS) {
        int64_t raw;
        xrsc_result r = parse_int64(p, f, field, &raw);
        return r != XRSC_OK ? r
                            : time_from_raw(p, raw, (int64_t)hs_ns_per_unit[c->time_unit], field,
                                            out_ns);
    }
    double t;
    xrsc_result r = parse_number(p, f, field, false, &t);
    if (r != XRSC_OK)
        return r;
    if (p->stream->count == 0)
        p->first_seconds = p->last_seconds = t;
    if (t < p->last_seconds)
        return u_diag_set(p->diag, XRSC_ERROR_TIME_BACKWARDS, p->name, p->line, field,
                          "time %.17g is earlier than the previous sample's %.17g", t,
                          p->last_seconds);
    double ns = (t - p->first_seconds) * hs_ns_per_unit[c->time_unit];
    if (!(ns < HS_MAX_SPAN_NS_DOUBLE))
        return u_diag_set(p->diag, XRSC_ERROR_BAD_NUMBER, p->name, p->line, field,
                          "time %.17g is too far from the first sample's", t);
    p->last_seconds = t;
    *out_ns = (int64_t)llround(ns);
    return XRSC_OK;
}

static xrsc_result parse_by_columns(hs_parser *p, const hs_pose_columns *c)
{
    const char *line;
    size_t len;
    char sep = 0;
    bool first = true;
    size_t skip = 0; /* leading index column */
    while (next_content_line(p, &line, &len)) {
        if (is_blank_or_comment(line, len))
            continue;
        hs_field f[HS_POSE_MAX_COLUMNS + 2];
        if (first)
            sep = detect_delimiter(line, len);
        size_t n = split_fields(line, len, sep, f, HS_POSE_MAX_COLUMNS + 2);
        size_t stored = n < HS_POSE_MAX_COLUMNS + 2 ? n : HS_POSE_MAX_COLUMNS + 2;
        if (first) {
            first = false;
            skip = n == c->count + 1 ? 1 : 0;
            if (is_header_line(f, stored))
                continue;
        }
        char field[48];
        if (n < c->count + skip) {
            uint32_t missing = (uint32_t)(n >= skip ? n - skip : 0);
            snprintf(field, sizeof(field), "%s (column %zu)", hs_role_label[c->role[missing]],
                     missing + skip + 1);
            return u_diag_set(p->diag, XRSC_ERROR_TRUNCATED_LINE, p->name, p->line, field,
                              "%zu fields, --pose-columns names %u%s", n, c->count,
                              skip ? " after an index column" : "");
        }
        if (n > c->count + skip)
            return extra_field(p, c->count + skip, n);
        double v[HS_POSE_COL_ROLE_COUNT] = {0};
        int64_t t_ns = 0;
        int t_col = -1;
        for (uint32_t i = 0; i < c->count; i++) {
            int role = c->role[i];
            snprintf(field, sizeof(field), "%s (column %zu)", hs_role_label[role], i + skip + 1);
            if (role == HS_POSE_COL_SKIP)
                continue;
            if (role == HS_POSE_COL_T) {
                t_col = (int)i;
                continue;
            }
            xrsc_result r = parse_double(p, f[i + skip], field, &v[role]);
            if (r != XRSC_OK)
                return r;
        }
        snprintf(field, sizeof(field), "t (column %zu)", (size_t)t_col + skip + 1);
        xrsc_result r = columns_time(p, c, f[t_col + (int)skip], field, &t_ns);
        if (r != XRSC_OK)
            return r;
        double zs = c->handedness == HS_POSE_LEFT_UNITY ? -1.0 : 1.0; /* as pred6dof */
        XrPosef pose;
        pose.position.x = (float)v[HS_POSE_COL_X];
        pose.position.y = (float)v[HS_POSE_COL_Y];
        pose.position.z = (float)(zs * v[HS_POSE_COL_Z]);
        pose.orientation.x = (float)(zs * v[HS_POSE_COL_QX]);
        pose.orientation.y = (float)(zs * v[HS_POSE_COL_QY]);
        pose.orientation.z = (float)v[HS_POSE_COL_QZ];
        pose.orientation.w = (float)v[HS_POSE_COL_QW];
        if ((r = check_quat(p, &pose.orientation, "qx qy qz qw")) != XRSC_OK)
            return r;
        if ((r = push_sample(p, t_ns, pose)) != XRSC_OK)
            return r;
    }
    return XRSC_OK;
}

/* ---- public API ------------------------------------------------------------------------- */

const char *hs_pose_format_name(hs_pose_format format)
{
    switch (format) {
    case HS_POSE_FORMAT_AUTO:
        return "auto";
    case HS_POSE_FORMAT_XRSC:
        return "xrsc";
    case HS_POSE_FORMAT_PRED6DOF:
        return "pred6dof";
    case HS_POSE_FORMAT_360VIDEO:
        return "360video";
    case HS_POSE_FORMAT_LIBRNR:
        return "librnr";
    case HS_POSE_FORMAT_COLUMNS:
        return "columns";
    }
    return "unknown";
}

bool hs_pose_format_from_name(const char *name, hs_pose_format *out)
{
    static const hs_pose_format named[] = {HS_POSE_FORMAT_AUTO, HS_POSE_FORMAT_XRSC,
                                           HS_POSE_FORMAT_PRED6DOF, HS_POSE_FORMAT_360VIDEO,
                                           HS_POSE_FORMAT_LIBRNR};
    for (size_t k = 0; k < sizeof(named) / sizeof(named[0]); k++)
        if (!strcmp(name, hs_pose_format_name(named[k]))) {
            *out = named[k];
            return true;
        }
    return false;
}

static xrsc_result parse_any(const char *name, const char *data, size_t size,
                             hs_pose_format format, const hs_pose_columns *columns,
                             hs_pose_stream **out, xrsc_diag *diag);

xrsc_result hs_pose_stream_parse(const char *name, const char *data, size_t size,
                                 hs_pose_format format, hs_pose_stream **out, xrsc_diag *diag)
{
    if (format == HS_POSE_FORMAT_COLUMNS)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, name ? name : "(memory)", 0, "",
                          "the columns format needs hs_pose_stream_parse_columns");
    return parse_any(name, data, size, format, NULL, out, diag);
}

xrsc_result hs_pose_stream_parse_columns(const char *name, const char *data, size_t size,
                                         const hs_pose_columns *columns, hs_pose_stream **out,
                                         xrsc_diag *diag)
{
    if (!columns || columns->count == 0 || columns->count > HS_POSE_MAX_COLUMNS) {
        if (out)
            *out = NULL;
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, name ? name : "(memory)", 0,
                          "--pose-columns", "no column list");
    }
    return parse_any(name, data, size, HS_POSE_FORMAT_COLUMNS, columns, out, diag);
}

/* The format of src (AUTO: detected from its first content line, reading no further; a file
 * is then rewound), else the error that says why there is none. */
static xrsc_result source_format(const hs_parser *src, hs_pose_format *format, xrsc_diag *diag)
{
    if (*format != HS_POSE_FORMAT_AUTO)
        return XRSC_OK;
    hs_parser q = *src;
    hs_head_kind kind;
    *format = detect_format(&q, &kind);
    if (kind == HS_HEAD_BLANK)
        return u_diag_set(diag, XRSC_ERROR_EMPTY_FILE, src->name, 0, "", "empty file");
    if (kind == HS_HEAD_COMMENTS)
        return u_diag_set(diag, XRSC_ERROR_EMPTY_FILE, src->name, 0, "",
                          "only comments, no header and no samples");
    if (*format == HS_POSE_FORMAT_AUTO)
        return u_diag_set(diag, XRSC_ERROR_BAD_HEADER, src->name, q.line, "header",
                          "unknown format: expected '%s %d', '%s', '%s' or librnr "
                          "records ('<t_ns> <s|v|b|f> <path> ...'); for another CSV or "
                          "TSV export name its columns with --pose-columns "
                          "(poses/README.md)",
                          HS_CANONICAL_MAGIC, HS_CANONICAL_VERSION, HS_PRED6DOF_HEADER,
                          HS_360VIDEO_HEADER);
    if (src->file && fseek(src->file, 0, SEEK_SET) != 0)
        return u_diag_set(diag, XRSC_ERROR_IO, src->name, 0, "", "cannot seek: %s",
                          strerror(errno));
    return XRSC_OK;
}

/* Parses every line of src (a buffer, or a file at its start) in format. */
static xrsc_result parse_source(const hs_parser *src, hs_pose_format format,
                                const hs_pose_columns *columns, hs_pose_stream **out,
                                xrsc_diag *diag)
{
    const char *name = src->name;
    xrsc_result r = source_format(src, &format, diag);
    if (r != XRSC_OK)
        return r;
    hs_pose_stream *s = calloc(1, sizeof(*s));
    if (!s)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, name, 0, "", "out of memory");
    s->format = format;
    hs_parser p = *src;
    p.diag = diag;
    p.stream = s;
    switch (format) {
    case HS_POSE_FORMAT_XRSC:
        r = parse_canonical(&p);
        break;
    case HS_POSE_FORMAT_PRED6DOF:
        r = parse_pred6dof(&p);
        break;
    case HS_POSE_FORMAT_360VIDEO:
        r = parse_360video(&p);
        break;
    case HS_POSE_FORMAT_LIBRNR:
        r = parse_librnr(&p);
        break;
    case HS_POSE_FORMAT_COLUMNS:
        r = parse_by_columns(&p, columns);
        s->orientation_only = true;
        for (uint32_t i = 0; i < columns->count; i++)
            s->orientation_only &= columns->role[i] != HS_POSE_COL_X;
        break;
    default:
        r = u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, name, 0, "", "unknown format %d",
                       (int)format);
        break;
    }
    if (r == XRSC_OK && src->file && ferror(src->file))
        r = u_diag_set(diag, XRSC_ERROR_IO, name, p.line, "", "read failed: %s", strerror(errno));
    if (r == XRSC_OK && s->count == 0)
        r = u_diag_set(diag, XRSC_ERROR_EMPTY_FILE, name, 0, "", "no samples");
    if (r != XRSC_OK) {
        hs_pose_stream_destroy(&s);
        return r;
    }
    if (s->dropped_duplicates > 0)
        U_LOG_W("%s: %u samples with a repeated timestamp were replaced by the later one", name,
                s->dropped_duplicates);
    *out = s;
    return XRSC_OK;
}

static xrsc_result parse_any(const char *name, const char *data, size_t size,
                             hs_pose_format format, const hs_pose_columns *columns,
                             hs_pose_stream **out, xrsc_diag *diag)
{
    if (!name)
        name = "(memory)";
    if (!out || (!data && size > 0))
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, name, 0, "", "NULL argument");
    *out = NULL;
    if (size > HS_POSE_MAX_FILE_BYTES)
        return u_diag_set(diag, XRSC_ERROR_FILE_TOO_LARGE, name, 0, "",
                          "%zu bytes, more than the limit of %llu", size,
                          (unsigned long long)HS_POSE_MAX_FILE_BYTES);
    /* A UTF-8 byte order mark is ignored. */
    static const char bom[3] = {'\xEF', '\xBB', '\xBF'};
    if (size >= 3 && memcmp(data, bom, 3) == 0) {
        data += 3;
        size -= 3;
    }
    bool content = false;
    for (size_t i = 0; i < size && !content; i++)
        content = !is_space(data[i]) && data[i] != '\n';
    if (!content)
        return u_diag_set(diag, XRSC_ERROR_EMPTY_FILE, name, 0, "", "empty file");
    const hs_parser src = {.name = name, .data = data, .size = size};
    return parse_source(&src, format, columns, out, diag);
}

xrsc_result hs_pose_stream_load(const char *path, hs_pose_format format, hs_pose_stream **out,
                                xrsc_diag *diag)
{
    const hs_pose_load_options opt = {.format = format};
    return hs_pose_stream_load_with(path, &opt, out, diag);
}

xrsc_result hs_pose_stream_load_columns(const char *path, const hs_pose_columns *columns,
                                        hs_pose_stream **out, xrsc_diag *diag)
{
    if (!columns || columns->count == 0) {
        if (out)
            *out = NULL;
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, path ? path : "", 0,
                          "--pose-columns", "no column list");
    }
    const hs_pose_load_options opt = {.columns = columns};
    return hs_pose_stream_load_with(path, &opt, out, diag);
}

/* Opens path as a regular file no larger than max_bytes (checked before anything is read). */
static xrsc_result open_checked(const char *path, uint64_t max_bytes, FILE **out, xrsc_diag *diag)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "cannot open: %s", strerror(errno));
    struct stat st;
    xrsc_result r = XRSC_OK;
    if (fstat(fileno(f), &st) == 0 && S_ISDIR(st.st_mode))
        r = u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "is a folder, not a pose file");
    else if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode))
        r = u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "not a readable regular file");
    else if ((unsigned long long)st.st_size > max_bytes)
        r = u_diag_set(diag, XRSC_ERROR_FILE_TOO_LARGE, path, 0, "",
                       "%lld bytes, more than the limit of %llu (--max-pose-bytes)",
                       (long long)st.st_size, (unsigned long long)max_bytes);
    else if (st.st_size == 0)
        r = u_diag_set(diag, XRSC_ERROR_EMPTY_FILE, path, 0, "", "empty file");
    if (r != XRSC_OK) {
        fclose(f);
        return r;
    }
    *out = f;
    return XRSC_OK;
}

xrsc_result hs_pose_stream_load_with(const char *path, const hs_pose_load_options *opt,
                                     hs_pose_stream **out, xrsc_diag *diag)
{
    if (out)
        *out = NULL;
    if (!path || !out || !opt)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, path ? path : "", 0, "",
                          "NULL argument");
    if ((opt->columns && (opt->columns->count == 0 || opt->columns->count > HS_POSE_MAX_COLUMNS)) ||
        (!opt->columns && opt->format == HS_POSE_FORMAT_COLUMNS))
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, path, 0, "--pose-columns",
                          "no column list");
    FILE *f = NULL;
    xrsc_result r = open_checked(path, opt->max_bytes ? opt->max_bytes : HS_POSE_MAX_FILE_BYTES,
                                 &f, diag);
    if (r != XRSC_OK)
        return r;
    char *buf = malloc(HS_POSE_MAX_LINE_CHARS);
    if (!buf) {
        fclose(f);
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, path, 0, "", "line buffer");
    }
    const hs_parser src = {.name = path, .file = f, .buf = buf};
    r = parse_source(&src, opt->columns ? HS_POSE_FORMAT_COLUMNS : opt->format, opt->columns,
                     out, diag);
    free(buf);
    fclose(f);
    return r;
}

xrsc_result hs_pose_stream_save(const hs_pose_stream *stream, const char *path, xrsc_diag *diag)
{
    if (!stream || !path || (stream->count > 0 && !stream->samples))
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, path ? path : "", 0, "",
                          "NULL argument");
    FILE *f = fopen(path, "wb");
    if (!f)
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "cannot create: %s", strerror(errno));
    fprintf(f, "%s %d\n", HS_CANONICAL_MAGIC, HS_CANONICAL_VERSION);
    fprintf(f, "# OpenXR axes (right-handed, +Y up, -Z forward), metres, t_ns in nanoseconds;"
               " spec: poses/README.md\n");
    fprintf(f, "# %zu samples%s\n", stream->count,
            stream->orientation_only ? ", orientation only" : "");
    fprintf(f, stream->orientation_only ? "columns t_ns qx qy qz qw\n"
                                        : "columns t_ns px py pz qx qy qz qw\n");
    for (size_t i = 0; i < stream->count; i++) {
        const hs_pose_sample *s = &stream->samples[i];
        const XrQuaternionf *q = &s->pose.orientation;
        /* %.9g prints every float so that strtod + (float) gives it back bit for bit. */
        fprintf(f, "%" PRId64, s->time_ns);
        if (!stream->orientation_only)
            fprintf(f, " %.9g %.9g %.9g", s->pose.position.x, s->pose.position.y,
                    s->pose.position.z);
        fprintf(f, " %.9g %.9g %.9g %.9g\n", q->x, q->y, q->z, q->w);
    }
    bool bad = ferror(f) != 0;
    if (fclose(f) != 0 || bad)
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "write failed");
    return XRSC_OK;
}

void hs_pose_stream_destroy(hs_pose_stream **stream)
{
    if (!stream || !*stream)
        return;
    free((*stream)->samples);
    free((*stream)->views);
    free(*stream);
    *stream = NULL;
}

int64_t hs_pose_stream_duration_ns(const hs_pose_stream *stream)
{
    if (!stream || stream->count == 0)
        return 0;
    return stream->samples[stream->count - 1].time_ns;
}

hs_lookup hs_pose_stream_sample(const hs_pose_stream *stream, int64_t time_ns, XrPosef *out_pose)
{
    XrPosef pose = xrsc_pose_identity();
    hs_lookup kind = HS_LOOKUP_CLAMPED;
    if (stream && stream->count > 0) {
        const hs_pose_sample *s = stream->samples;
        size_t n = stream->count;
        if (time_ns <= s[0].time_ns) {
            pose = s[0].pose;
            kind = time_ns == s[0].time_ns ? HS_LOOKUP_EXACT : HS_LOOKUP_CLAMPED;
        } else if (time_ns >= s[n - 1].time_ns) {
            pose = s[n - 1].pose;
            kind = time_ns == s[n - 1].time_ns ? HS_LOOKUP_EXACT : HS_LOOKUP_CLAMPED;
        } else {
            /* Invariant: s[lo].time_ns <= time_ns < s[hi].time_ns. */
            size_t lo = 0, hi = n - 1;
            while (hi - lo > 1) {
                size_t mid = lo + (hi - lo) / 2;
                if (s[mid].time_ns <= time_ns)
                    lo = mid;
                else
                    hi = mid;
            }
            if (s[lo].time_ns == time_ns) {
                pose = s[lo].pose;
                kind = HS_LOOKUP_EXACT;
            } else {
                double t = ((double)time_ns - (double)s[lo].time_ns) /
                           ((double)s[hi].time_ns - (double)s[lo].time_ns);
                pose = xrsc_pose_interpolate(s[lo].pose, s[hi].pose, (float)t);
                kind = HS_LOOKUP_INTERPOLATED;
            }
        }
    }
    if (out_pose)
        *out_pose = pose;
    return kind;
}

void hs_pose_stream_anchor(hs_pose_stream *stream, XrPosef viewpoint)
{
    if (!stream || stream->count == 0)
        return;
    XrPosef delta = xrsc_pose_mul(viewpoint, xrsc_pose_inverse(stream->samples[0].pose));
    for (size_t i = 0; i < stream->count; i++) {
        XrPosef *p = &stream->samples[i].pose;
        *p = xrsc_pose_mul(delta, *p);
        p->orientation = xrsc_quat_normalize(p->orientation);
        if (stream->orientation_only)
            p->position = viewpoint.position;
        for (int e = 0; stream->views && e < 2; e++) {
            XrPosef *v = &stream->views[i].pose[e];
            *v = xrsc_pose_mul(delta, *v);
            v->orientation = xrsc_quat_normalize(v->orientation);
        }
    }
}

static XrFovf fov_lerp(XrFovf a, XrFovf b, float t)
{
    return (XrFovf){.angleLeft = a.angleLeft + (b.angleLeft - a.angleLeft) * t,
                    .angleRight = a.angleRight + (b.angleRight - a.angleRight) * t,
                    .angleUp = a.angleUp + (b.angleUp - a.angleUp) * t,
                    .angleDown = a.angleDown + (b.angleDown - a.angleDown) * t};
}

hs_lookup hs_pose_stream_sample_views(const hs_pose_stream *stream, int64_t time_ns,
                                      hs_view_sample *out_views)
{
    if (!stream || !stream->views || stream->count == 0 || !out_views)
        return HS_LOOKUP_CLAMPED;
    const hs_pose_sample *s = stream->samples;
    const hs_view_sample *v = stream->views;
    size_t n = stream->count;
    if (time_ns <= s[0].time_ns) {
        *out_views = v[0];
        return time_ns == s[0].time_ns ? HS_LOOKUP_EXACT : HS_LOOKUP_CLAMPED;
    }
    if (time_ns >= s[n - 1].time_ns) {
        *out_views = v[n - 1];
        return time_ns == s[n - 1].time_ns ? HS_LOOKUP_EXACT : HS_LOOKUP_CLAMPED;
    }
    size_t lo = 0, hi = n - 1; /* s[lo].time_ns <= time_ns < s[hi].time_ns */
    while (hi - lo > 1) {
        size_t mid = lo + (hi - lo) / 2;
        if (s[mid].time_ns <= time_ns)
            lo = mid;
        else
            hi = mid;
    }
    if (s[lo].time_ns == time_ns) {
        *out_views = v[lo];
        return HS_LOOKUP_EXACT;
    }
    float t = (float)(((double)time_ns - (double)s[lo].time_ns) /
                      ((double)s[hi].time_ns - (double)s[lo].time_ns));
    for (int e = 0; e < 2; e++) {
        out_views->pose[e] = xrsc_pose_interpolate(v[lo].pose[e], v[hi].pose[e], t);
        out_views->fov[e] = fov_lerp(v[lo].fov[e], v[hi].fov[e], t);
    }
    return HS_LOOKUP_INTERPOLATED;
}

hs_lookup hs_pose_stream_eyes(const hs_pose_stream *stream, const xrsc_headset *headset,
                              int64_t time_ns, hs_view_sample *out_eyes)
{
    XrPosef head;
    hs_lookup kind = hs_pose_stream_sample(stream, time_ns, &head);
    if (stream && stream->views && stream->count > 0) {
        hs_pose_stream_sample_views(stream, time_ns, out_eyes);
        return kind;
    }
    xrsc_headset_eye_poses(headset, head, out_eyes->pose);
    out_eyes->fov[0] = headset->fov[0];
    out_eyes->fov[1] = headset->fov[1];
    return kind;
}
