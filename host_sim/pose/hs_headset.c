// SPDX-License-Identifier: MIT
/**
 * @file hs_headset.c
 * @brief Parser of the headset profile file (hs_headset.h; format at the top of headsets.txt).
 */
#include "hs_headset.h"

#include "u_diag.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

/* The generated hs_headsets_data.c: host_sim/headsets.txt's bytes, NUL-terminated. */
extern const char hs_headsets_builtin[];

#define DEG_TO_RAD (3.14159265358979323846 / 180.0)
/** Limits shared with xrsc's --resolution, --refresh and --ipd. */
#define SIDE_MIN_PX 8
#define SIDE_MAX_PX 8192
#define REFRESH_MIN_HZ 1.0
#define REFRESH_MAX_HZ 1000.0
#define IPD_MAX_MM 200.0
/** A frustum side must stay short of 90 degrees (its tangent is finite). */
#define FOV_MAX_DEG 89.9
/** Longest line the parser reads. */
#define LINE_MAX_CHARS 1024
/** Largest profile file hs_headsets_load reads. */
#define FILE_MAX_BYTES (1u << 20)

/* Keys of a profile; the bit of each in a profile's "seen" mask. */
enum key_id {
    K_TITLE,
    K_RESOLUTION,
    K_REFRESH,
    K_MODES,
    K_IPD,
    K_FOV_L,
    K_FOV_R,
    K_SOURCE,
    K_COUNT
};
static const char *const key_names[K_COUNT] = {
    "title",  "resolution",   "refresh_hz",    "refresh_modes_hz",
    "ipd_mm", "fov_left_deg", "fov_right_deg", "source"};
#define REQUIRED_KEYS (((1u << K_COUNT) - 1u) & ~(1u << K_MODES))

const char *hs_headsets_builtin_text(void)
{
    return hs_headsets_builtin;
}

static char *trim(char *s)
{
    while (isspace((unsigned char)*s))
        s++;
    size_t n = strlen(s);
    while (n > 0 && isspace((unsigned char)s[n - 1]))
        s[--n] = '\0';
    return s;
}

/* Reads up to max floats separated by spaces; returns how many, or -1 on a non-number. */
static int parse_floats(const char *v, double *out, int max)
{
    int n = 0;
    while (*v) {
        while (isspace((unsigned char)*v))
            v++;
        if (!*v)
            break;
        if (n == max)
            return -1;
        char *end;
        errno = 0;
        double d = strtod(v, &end);
        if (end == v || errno || !isfinite(d) || (*end && !isspace((unsigned char)*end)))
            return -1;
        out[n++] = d;
        v = end;
    }
    return n;
}

typedef struct parse_ctx {
    const char *origin;
    int line;
    xrsc_diag *diag;
} parse_ctx;

static xrsc_result bad(const parse_ctx *pc, xrsc_result code, const char *field, const char *why,
                       const char *value)
{
    return u_diag_set(pc->diag, code, pc->origin, pc->line, field, "%s ('%s')", why, value);
}

static xrsc_result parse_fov(const parse_ctx *pc, const char *key, const char *v, XrFovf *out)
{
    double a[4];
    if (parse_floats(v, a, 4) != 4)
        return bad(pc, XRSC_ERROR_BAD_NUMBER, key, "expected 4 angles: left right up down", v);
    for (int i = 0; i < 4; i++)
        if (fabs(a[i]) >= FOV_MAX_DEG)
            return bad(pc, XRSC_ERROR_BAD_NUMBER, key, "each angle must be within +-89.9 deg", v);
    if (!(a[0] < a[1]) || !(a[3] < a[2]))
        return bad(pc, XRSC_ERROR_BAD_NUMBER, key,
                   "expected left < right and down < up (OpenXR: left and down negative)", v);
    out->angleLeft = (float)(a[0] * DEG_TO_RAD);
    out->angleRight = (float)(a[1] * DEG_TO_RAD);
    out->angleUp = (float)(a[2] * DEG_TO_RAD);
    out->angleDown = (float)(a[3] * DEG_TO_RAD);
    return XRSC_OK;
}

static xrsc_result parse_value(const parse_ctx *pc, enum key_id k, const char *v,
                               hs_headset_profile *p)
{
    double d[HS_HEADSET_MAX_MODES];
    int n;
    switch (k) {
    case K_TITLE:
    case K_SOURCE: {
        char *dst = k == K_TITLE ? p->title : p->source;
        size_t cap = k == K_TITLE ? sizeof(p->title) : sizeof(p->source);
        if (!*v || strlen(v) >= cap)
            return bad(pc, XRSC_ERROR_INVALID_ARGUMENT, key_names[k], "empty or too long", v);
        memcpy(dst, v, strlen(v) + 1);
        return XRSC_OK;
    }
    case K_RESOLUTION: {
        unsigned w = 0, h = 0;
        char tail;
        if (sscanf(v, "%ux%u%c", &w, &h, &tail) != 2 || w < SIDE_MIN_PX || h < SIDE_MIN_PX ||
            w > SIDE_MAX_PX || h > SIDE_MAX_PX)
            return bad(pc, XRSC_ERROR_BAD_NUMBER, key_names[k], "expected WxH, each 8..8192", v);
        p->headset.width_px = w;
        p->headset.height_px = h;
        return XRSC_OK;
    }
    case K_REFRESH:
    case K_MODES:
        n = parse_floats(v, d, k == K_REFRESH ? 1 : HS_HEADSET_MAX_MODES);
        if (n < 1)
            return bad(pc, XRSC_ERROR_BAD_NUMBER, key_names[k],
                       k == K_REFRESH ? "expected one rate in Hz" : "expected 1..8 rates in Hz", v);
        for (int i = 0; i < n; i++)
            if (!(d[i] >= REFRESH_MIN_HZ && d[i] <= REFRESH_MAX_HZ))
                return bad(pc, XRSC_ERROR_BAD_NUMBER, key_names[k], "rates must be 1..1000 Hz", v);
        if (k == K_REFRESH) {
            p->headset.refresh_hz = (float)d[0];
        } else {
            for (int i = 0; i < n; i++)
                p->refresh_modes_hz[i] = (float)d[i];
            p->refresh_mode_count = (uint32_t)n;
        }
        return XRSC_OK;
    case K_IPD:
        if (parse_floats(v, d, 1) != 1 || !(d[0] >= 0.0 && d[0] <= IPD_MAX_MM))
            return bad(pc, XRSC_ERROR_BAD_NUMBER, key_names[k], "expected millimetres 0..200", v);
        p->headset.ipd_m = (float)(d[0] * 1e-3);
        return XRSC_OK;
    case K_FOV_L:
    case K_FOV_R:
        return parse_fov(pc, key_names[k], v, &p->headset.fov[k == K_FOV_L ? 0 : 1]);
    default:
        return XRSC_ERROR_INVALID_ARGUMENT;
    }
}

/* Checks a finished profile: every required key, and refresh_hz among the listed modes. */
static xrsc_result finish_profile(const parse_ctx *pc, int section_line, uint32_t seen,
                                  hs_headset_profile *p)
{
    for (int k = 0; k < K_COUNT; k++)
        if ((REQUIRED_KEYS & (1u << k)) && !(seen & (1u << k)))
            return u_diag_set(pc->diag, XRSC_ERROR_INVALID_ARGUMENT, pc->origin, section_line,
                              key_names[k], "profile [%s] has no %s", p->name, key_names[k]);
    if (p->refresh_mode_count == 0) {
        p->refresh_modes_hz[0] = p->headset.refresh_hz;
        p->refresh_mode_count = 1;
    }
    for (uint32_t i = 0; i < p->refresh_mode_count; i++)
        if (p->refresh_modes_hz[i] == p->headset.refresh_hz)
            return XRSC_OK;
    return u_diag_set(pc->diag, XRSC_ERROR_BAD_NUMBER, pc->origin, section_line, "refresh_modes_hz",
                      "profile [%s]: refresh_hz %g is not among them", p->name,
                      (double)p->headset.refresh_hz);
}

static bool valid_name(const char *s, size_t n)
{
    if (n == 0 || n >= sizeof(((hs_headset_profile *)0)->name))
        return false;
    for (size_t i = 0; i < n; i++)
        if (!(islower((unsigned char)s[i]) || isdigit((unsigned char)s[i]) || s[i] == '-'))
            return false;
    return true;
}

/* Starts a profile at "[name]"; grows the table. */
static xrsc_result begin_profile(const parse_ctx *pc, char *s, hs_headset_table *t)
{
    size_t n = strlen(s);
    if (n < 2 || s[n - 1] != ']' || !valid_name(s + 1, n - 2))
        return bad(pc, XRSC_ERROR_INVALID_ARGUMENT, "name",
                   "expected [name] of lower-case letters, digits and '-' (at most 31)", s);
    s[n - 1] = '\0';
    if (hs_headsets_find(t, s + 1))
        return bad(pc, XRSC_ERROR_INVALID_ARGUMENT, "name", "profile defined twice", s + 1);
    hs_headset_profile *items = realloc(t->items, (t->count + 1) * sizeof(*items));
    if (!items)
        return u_diag_set(pc->diag, XRSC_ERROR_OUT_OF_MEMORY, pc->origin, pc->line, "", "profiles");
    t->items = items;
    hs_headset_profile *p = &items[t->count++];
    memset(p, 0, sizeof(*p));
    memcpy(p->name, s + 1, n - 1);
    return XRSC_OK;
}

/* One "key = value" line of the current profile. */
static xrsc_result parse_line(const parse_ctx *pc, char *s, hs_headset_table *t, uint32_t *seen)
{
    char *eq = strchr(s, '=');
    if (!eq)
        return bad(pc, XRSC_ERROR_UNKNOWN_COLUMN, "", "expected [name] or key = value", s);
    *eq = '\0';
    char *key = trim(s), *value = trim(eq + 1);
    int k = 0;
    while (k < K_COUNT && strcmp(key, key_names[k]) != 0)
        k++;
    if (k == K_COUNT)
        return bad(pc, XRSC_ERROR_UNKNOWN_COLUMN, key, "unknown key", key);
    if (t->count == 0)
        return bad(pc, XRSC_ERROR_INVALID_ARGUMENT, key, "key before the first [name]", key);
    if (*seen & (1u << k))
        return bad(pc, XRSC_ERROR_INVALID_ARGUMENT, key, "key given twice in one profile", key);
    *seen |= 1u << k;
    return parse_value(pc, (enum key_id)k, value, &t->items[t->count - 1]);
}

xrsc_result hs_headsets_parse(const char *text, const char *origin, hs_headset_table *out,
                              xrsc_diag *diag)
{
    memset(out, 0, sizeof(*out));
    parse_ctx pc = {.origin = origin ? origin : "", .line = 0, .diag = diag};
    uint32_t seen = 0;
    int section_line = 0;
    xrsc_result res = XRSC_OK;
    char buf[LINE_MAX_CHARS];
    for (const char *p = text; res == XRSC_OK && p && *p;) {
        const char *nl = strchr(p, '\n');
        size_t len = nl ? (size_t)(nl - p) : strlen(p);
        pc.line++;
        if (len >= sizeof(buf)) {
            res = u_diag_set(diag, XRSC_ERROR_FILE_TOO_LARGE, pc.origin, pc.line, "",
                             "line longer than %d characters", LINE_MAX_CHARS - 1);
            break;
        }
        memcpy(buf, p, len);
        buf[len] = '\0';
        p = nl ? nl + 1 : NULL;
        char *s = trim(buf);
        if (*s == '\0' || *s == '#')
            continue;
        if (*s == '[') {
            if (out->count > 0)
                res = finish_profile(&pc, section_line, seen, &out->items[out->count - 1]);
            if (res == XRSC_OK)
                res = begin_profile(&pc, s, out);
            seen = 0;
            section_line = pc.line;
        } else {
            res = parse_line(&pc, s, out, &seen);
        }
    }
    if (res == XRSC_OK && out->count > 0)
        res = finish_profile(&pc, section_line, seen, &out->items[out->count - 1]);
    if (res == XRSC_OK && out->count == 0)
        res = u_diag_set(diag, XRSC_ERROR_EMPTY_FILE, pc.origin, 0, "",
                         "no headset profile ([name]) defined");
    if (res != XRSC_OK)
        hs_headsets_free(out);
    return res;
}

xrsc_result hs_headsets_load(const char *path, hs_headset_table *out, xrsc_diag *diag)
{
    if (!path)
        return hs_headsets_parse(hs_headsets_builtin, "headsets.txt (built in)", out, diag);
    memset(out, 0, sizeof(*out));
    FILE *f = fopen(path, "rb");
    if (!f)
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "--headsets", "cannot open: %s",
                          strerror(errno));
    char *text = malloc(FILE_MAX_BYTES + 1);
    size_t n = text ? fread(text, 1, FILE_MAX_BYTES + 1, f) : 0;
    bool read_error = ferror(f) != 0;
    fclose(f);
    if (!text)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, path, 0, "", "out of memory");
    xrsc_result res;
    if (read_error)
        res = u_diag_set(diag, XRSC_ERROR_IO, path, 0, "--headsets", "read error");
    else if (n > FILE_MAX_BYTES)
        res = u_diag_set(diag, XRSC_ERROR_FILE_TOO_LARGE, path, 0, "--headsets",
                         "larger than %u bytes", FILE_MAX_BYTES);
    else if (memchr(text, '\0', n))
        res = u_diag_set(diag, XRSC_ERROR_BAD_HEADER, path, 0, "--headsets",
                         "not a text file (contains NUL bytes)");
    else {
        text[n] = '\0';
        res = hs_headsets_parse(text, path, out, diag);
    }
    free(text);
    return res;
}

void hs_headsets_free(hs_headset_table *t)
{
    if (!t)
        return;
    free(t->items);
    t->items = NULL;
    t->count = 0;
}

const hs_headset_profile *hs_headsets_find(const hs_headset_table *t, const char *name)
{
    for (uint32_t i = 0; t && name && i < t->count; i++)
        if (strcmp(t->items[i].name, name) == 0)
            return &t->items[i];
    return NULL;
}

xrsc_result hs_headsets_select(const hs_headset_table *t, const char *name,
                               const hs_headset_profile **out, xrsc_diag *diag)
{
    *out = hs_headsets_find(t, name);
    if (*out)
        return XRSC_OK;
    char names[400] = "";
    size_t len = 0;
    for (uint32_t i = 0; i < t->count && len < sizeof(names); i++)
        len += (size_t)snprintf(names + len, sizeof(names) - len, "%s%s", i ? ", " : "",
                                t->items[i].name);
    return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--headset",
                      "unknown headset '%s' (known: %s; --headset list describes them)",
                      name ? name : "", names);
}

static void print_fov(FILE *f, const char *eye, const XrFovf *v)
{
    const double r = 1.0 / DEG_TO_RAD;
    fprintf(f, " %s %.4g %.4g %.4g %.4g", eye, v->angleLeft * r, v->angleRight * r, v->angleUp * r,
            v->angleDown * r);
}

void hs_headsets_print(const hs_headset_table *t, FILE *f)
{
    for (uint32_t i = 0; i < t->count; i++) {
        const hs_headset_profile *p = &t->items[i];
        fprintf(f, "%-12s %s: %ux%u per eye, %g Hz (", p->name, p->title, p->headset.width_px,
                p->headset.height_px, (double)p->headset.refresh_hz);
        for (uint32_t m = 0; m < p->refresh_mode_count; m++)
            fprintf(f, "%s%g", m ? "/" : "", (double)p->refresh_modes_hz[m]);
        fprintf(f, " Hz offered), IPD %g mm, FOV deg (left right up down):",
                (double)p->headset.ipd_m * 1e3);
        print_fov(f, "L", &p->headset.fov[0]);
        print_fov(f, " R", &p->headset.fov[1]);
        fprintf(f, "\n             source: %s\n", p->source);
    }
}
