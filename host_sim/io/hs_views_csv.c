// SPDX-License-Identifier: MIT
/**
 * @file hs_views_csv.c
 * @brief views.csv writer and reader (hs_views_csv.h).
 */
#include "hs_views_csv.h"

#include "u_diag.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

/** Longest line read, terminator included. */
#define LINE_CHARS 4096
/** Most columns of a line. */
#define MAX_COLUMNS 64
/** A field of view's angles must lie strictly within +-90 degrees. */
#define HALF_PI 1.5707963267948966

void hs_views_csv_header(FILE *f)
{
    fputs(HS_VIEWS_CSV_HEADER "\n", f);
}

void hs_views_csv_row(FILE *f, uint32_t frame, uint32_t eye, int64_t display_time_ns,
                      const XrPosef *pose, const XrFovf *fov, uint32_t width, uint32_t height)
{
    /* %.9g: a float's shortest exact round trip, so the reader gets the rendered camera. */
    fprintf(f, "%u,%s,%lld,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%u,%u\n", frame,
            eye ? "right" : "left", (long long)display_time_ns, pose->position.x, pose->position.y,
            pose->position.z, pose->orientation.x, pose->orientation.y, pose->orientation.z,
            pose->orientation.w, fov->angleLeft, fov->angleRight, fov->angleUp, fov->angleDown,
            width, height);
}

/* The columns the reader uses, by index into a row's values. */
enum {
    COL_FRAME,
    COL_EYE,
    COL_PX,
    COL_PY,
    COL_PZ,
    COL_QX,
    COL_QY,
    COL_QZ,
    COL_QW,
    COL_LEFT,
    COL_RIGHT,
    COL_UP,
    COL_DOWN,
    COL_WIDTH, /* optional from here */
    COL_HEIGHT,
    COL_COUNT,
    COL_REQUIRED = COL_WIDTH
};
static const char *const col_name[COL_COUNT] = {
    "frame", "eye",        "px",          "py",       "pz",         "qx",    "qy",    "qz",
    "qw",    "angle_left", "angle_right", "angle_up", "angle_down", "width", "height"};

/* Splits line in place at commas (spaces and CR/LF trimmed); returns the field count. */
static int split(char *line, char *field[MAX_COLUMNS])
{
    int n = 0;
    for (char *p = line; n < MAX_COLUMNS;) {
        while (*p == ' ' || *p == '\t')
            p++;
        field[n++] = p;
        char *end = p + strcspn(p, ",\r\n");
        char sep = *end;
        char *t = end;
        while (t > p && (t[-1] == ' ' || t[-1] == '\t'))
            t--;
        *t = '\0';
        if (sep != ',')
            break;
        p = end + 1;
    }
    return n;
}

typedef struct reader {
    const char *path;
    int line;
    int at[COL_COUNT]; /* field index of each column, -1 when absent */
    xrsc_diag *diag;
} reader;

static xrsc_result field_error(const reader *rd, xrsc_result code, int col, const char *why)
{
    return u_diag_set(rd->diag, code, rd->path, rd->line, col_name[col], "%s", why);
}

/* The header: every required column present. */
static xrsc_result read_header(reader *rd, char *line)
{
    char *f[MAX_COLUMNS];
    int n = split(line, f);
    for (int c = 0; c < COL_COUNT; c++) {
        rd->at[c] = -1;
        for (int i = 0; i < n && rd->at[c] < 0; i++)
            if (!strcmp(f[i], col_name[c]))
                rd->at[c] = i;
        if (rd->at[c] < 0 && c < COL_REQUIRED)
            return field_error(rd, XRSC_ERROR_UNKNOWN_COLUMN, c,
                               "the header has no such column (views.csv needs frame, eye, "
                               "px..pz, qx..qw, angle_left/right/up/down)");
    }
    return XRSC_OK;
}

/* A field as a finite number; whole: a whole number in [0, UINT32_MAX]. */
static xrsc_result number(const reader *rd, char *const *f, int n, int col, bool whole, double *out)
{
    if (rd->at[col] >= n)
        return field_error(rd, XRSC_ERROR_TRUNCATED_LINE, col, "the line ends before this column");
    const char *s = f[rd->at[col]];
    char *end = NULL;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end != '\0')
        return field_error(rd, XRSC_ERROR_BAD_NUMBER, col, "not a number");
    if (!isfinite(v))
        return field_error(rd, XRSC_ERROR_NAN, col, "NaN or infinite");
    if (whole && (v < 0.0 || v > 4294967295.0 || v != floor(v)))
        return field_error(rd, XRSC_ERROR_BAD_NUMBER, col, "expected a whole number >= 0");
    *out = v;
    return XRSC_OK;
}

/* The row's values checked: the eye's name, a unit quaternion, a frustum. */
static xrsc_result read_row(const reader *rd, char *line, hs_view_row *out)
{
    char *f[MAX_COLUMNS];
    int n = split(line, f);
    double v[COL_COUNT] = {0};
    xrsc_result res = XRSC_OK;
    for (int c = 0; c < COL_COUNT && res == XRSC_OK; c++)
        if (c != COL_EYE && rd->at[c] >= 0)
            res = number(rd, f, n, c, c == COL_FRAME || c >= COL_WIDTH, &v[c]);
    if (res != XRSC_OK)
        return res;
    const char *eye = f[rd->at[COL_EYE]];
    if (strcmp(eye, "left") && strcmp(eye, "right"))
        return field_error(rd, XRSC_ERROR_BAD_NUMBER, COL_EYE, "expected left or right");
    double qlen = sqrt(v[COL_QX] * v[COL_QX] + v[COL_QY] * v[COL_QY] + v[COL_QZ] * v[COL_QZ] +
                       v[COL_QW] * v[COL_QW]);
    if (fabs(qlen - 1.0) > HS_VIEWS_QUAT_TOLERANCE)
        return field_error(rd, XRSC_ERROR_QUAT_NOT_UNIT, COL_QW, "the quaternion is not unit");
    for (int c = COL_LEFT; c <= COL_DOWN; c++)
        if (!(fabs(v[c]) < HALF_PI))
            return field_error(rd, XRSC_ERROR_INVALID_ARGUMENT, c,
                               "a field-of-view angle must lie within +-pi/2 radians");
    if (!(v[COL_LEFT] < v[COL_RIGHT]) || !(v[COL_DOWN] < v[COL_UP]))
        return field_error(rd, XRSC_ERROR_INVALID_ARGUMENT, COL_RIGHT,
                           "the field of view needs angle_left < angle_right and angle_down < "
                           "angle_up");
    out->frame = (uint32_t)v[COL_FRAME];
    out->eye = strcmp(eye, "left") ? 1u : 0u;
    out->camera.pose.position = (XrVector3f){(float)v[COL_PX], (float)v[COL_PY], (float)v[COL_PZ]};
    out->camera.pose.orientation =
        (XrQuaternionf){(float)v[COL_QX], (float)v[COL_QY], (float)v[COL_QZ], (float)v[COL_QW]};
    out->camera.fov =
        (XrFovf){(float)v[COL_LEFT], (float)v[COL_RIGHT], (float)v[COL_UP], (float)v[COL_DOWN]};
    out->camera.width = (uint32_t)v[COL_WIDTH];
    out->camera.height = (uint32_t)v[COL_HEIGHT];
    return XRSC_OK;
}

static int row_order(const void *a, const void *b)
{
    const hs_view_row *x = a, *y = b;
    if (x->frame != y->frame)
        return x->frame < y->frame ? -1 : 1;
    return (int)x->eye - (int)y->eye;
}

/* Appends a row, growing the array. */
static bool push(hs_views_table *t, uint32_t *cap, const hs_view_row *row)
{
    if (t->count == *cap) {
        uint32_t c = *cap ? 2 * *cap : 64;
        hs_view_row *r = realloc(t->rows, c * sizeof(*r));
        if (!r)
            return false;
        t->rows = r;
        *cap = c;
    }
    t->rows[t->count++] = *row;
    return true;
}

/* Reads the lines after the header; sorts them and refuses duplicates. */
static xrsc_result read_rows(reader *rd, FILE *f, char *line, hs_views_table *out)
{
    uint32_t cap = 0;
    while (fgets(line, LINE_CHARS, f)) {
        rd->line++;
        if (line[0] == '#' || line[strspn(line, " \t\r\n")] == '\0')
            continue;
        if (out->count >= HS_VIEWS_MAX_ROWS)
            return u_diag_set(rd->diag, XRSC_ERROR_FILE_TOO_LARGE, rd->path, rd->line, "",
                              "more than %u rows", HS_VIEWS_MAX_ROWS);
        hs_view_row row;
        xrsc_result res = read_row(rd, line, &row);
        if (res != XRSC_OK)
            return res;
        if (!push(out, &cap, &row))
            return u_diag_set(rd->diag, XRSC_ERROR_OUT_OF_MEMORY, rd->path, rd->line, "", "rows");
    }
    if (out->count == 0)
        return u_diag_set(rd->diag, XRSC_ERROR_EMPTY_FILE, rd->path, rd->line, "",
                          "no rows after the header");
    qsort(out->rows, out->count, sizeof(*out->rows), row_order);
    for (uint32_t i = 1; i < out->count; i++)
        if (row_order(&out->rows[i - 1], &out->rows[i]) == 0)
            return u_diag_set(rd->diag, XRSC_ERROR_INVALID_ARGUMENT, rd->path, 0, "frame",
                              "frame %u, eye %s is given twice", out->rows[i].frame,
                              out->rows[i].eye ? "right" : "left");
    return XRSC_OK;
}

xrsc_result hs_views_csv_read(const char *path, hs_views_table *out, xrsc_diag *diag)
{
    memset(out, 0, sizeof(*out));
    FILE *f = fopen(path, "r");
    if (!f)
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "cannot be opened: %s",
                          strerror(errno));
    char *line = malloc(LINE_CHARS);
    reader rd = {.path = path, .diag = diag};
    xrsc_result res =
        line ? XRSC_OK : u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, path, 0, "", "line buffer");
    bool header = false;
    while (res == XRSC_OK && !header && fgets(line, LINE_CHARS, f)) {
        rd.line++;
        if (line[0] == '#' || line[strspn(line, " \t\r\n")] == '\0')
            continue;
        res = read_header(&rd, line);
        header = true;
    }
    if (res == XRSC_OK && !header)
        res = u_diag_set(diag, XRSC_ERROR_EMPTY_FILE, path, rd.line, "", "no header line");
    if (res == XRSC_OK)
        res = read_rows(&rd, f, line, out);
    free(line);
    fclose(f);
    if (res != XRSC_OK)
        hs_views_table_free(out);
    return res;
}

const hs_view_row *hs_views_find(const hs_views_table *t, uint32_t frame, uint32_t eye)
{
    hs_view_row key = {.frame = frame, .eye = eye};
    return t->count ? bsearch(&key, t->rows, t->count, sizeof(key), row_order) : NULL;
}

void hs_views_table_free(hs_views_table *t)
{
    free(t->rows);
    t->rows = NULL;
    t->count = 0;
}
