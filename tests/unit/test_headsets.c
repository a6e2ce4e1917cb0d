// SPDX-License-Identifier: MIT
/**
 * @file test_headsets.c
 * @brief Headset profiles (hs_headset.h): the built-in file loads with every profile the issue
 *        names and sane values, unknown names are refused with the list of names, and broken
 *        profile files fail with the documented error ID on the right line and field.
 */
#include "hs_headset.h"
#include "testing.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define RAD_PER_DEG (3.14159265358979323846 / 180.0)

static void test_builtin_profiles(void)
{
    hs_headset_table t;
    xrsc_diag diag = {0};
    CHECK_EQ_INT(hs_headsets_load(NULL, &t, &diag), XRSC_OK);
    CHECK(t.count >= 6);
    static const char *const wanted[] = {"quest3",     "quest2", "index",
                                         "vision-pro", "pico4",  "hololens2"};
    for (size_t i = 0; i < sizeof(wanted) / sizeof(wanted[0]); i++)
        CHECK_MSG(hs_headsets_find(&t, wanted[i]) != NULL, "%s missing", wanted[i]);
    for (uint32_t i = 0; i < t.count; i++) {
        const hs_headset_profile *p = &t.items[i];
        const xrsc_headset *h = &p->headset;
        CHECK_MSG(h->width_px >= 8 && h->height_px >= 8, "%s size", p->name);
        CHECK_MSG(h->refresh_hz >= 1.0f && p->refresh_mode_count >= 1, "%s refresh", p->name);
        CHECK_MSG(h->ipd_m > 0.04f && h->ipd_m < 0.08f, "%s ipd", p->name);
        CHECK_MSG(p->title[0] && p->source[0], "%s title/source", p->name);
        for (int e = 0; e < 2; e++) {
            const XrFovf *f = &h->fov[e];
            CHECK_MSG(f->angleLeft < 0 && f->angleRight > 0 && f->angleUp > 0 && f->angleDown < 0,
                      "%s eye %d fov signs", p->name, e);
        }
        /* Outer side wider or equal: left eye's left, right eye's right (mirror images). */
        CHECK_MSG(-h->fov[0].angleLeft >= h->fov[0].angleRight - 1e-6f, "%s asymmetry", p->name);
        CHECK_NEAR(h->fov[0].angleLeft, -h->fov[1].angleRight, 0.02);
    }
    const hs_headset_profile *q = hs_headsets_find(&t, "quest3");
    if (q) {
        CHECK_EQ_INT(q->headset.width_px, 2064);
        CHECK_EQ_INT(q->headset.height_px, 2208);
        CHECK_NEAR(q->headset.ipd_m, 0.063, 1e-6);
        CHECK_EQ_INT(q->refresh_mode_count, 3);
        CHECK_NEAR(q->refresh_modes_hz[0], 72.0, 0);
        CHECK_NEAR(q->refresh_modes_hz[2], 120.0, 0);
        CHECK(q->headset.fov[0].angleLeft != -q->headset.fov[0].angleRight); /* asymmetric */
    }
    const hs_headset_profile *ix = hs_headsets_find(&t, "index");
    if (ix) {
        CHECK_EQ_INT(ix->headset.width_px, 1440);
        CHECK_EQ_INT(ix->headset.height_px, 1600);
        bool has144 = false;
        for (uint32_t m = 0; m < ix->refresh_mode_count; m++)
            has144 = has144 || ix->refresh_modes_hz[m] == 144.0f;
        CHECK(has144);
    }
    const hs_headset_profile *vp = hs_headsets_find(&t, "vision-pro");
    if (vp)
        CHECK_EQ_INT(vp->headset.width_px, 3660);
    hs_headsets_free(&t);
    CHECK(t.items == NULL && t.count == 0);
    hs_headsets_free(&t); /* twice, and on an empty table */
}

static void test_unknown_name_lists_names(void)
{
    hs_headset_table t;
    xrsc_diag diag = {0};
    CHECK_EQ_INT(hs_headsets_load(NULL, &t, &diag), XRSC_OK);
    const hs_headset_profile *p = (const hs_headset_profile *)1;
    CHECK_EQ_INT(hs_headsets_select(&t, "quest9", &p, &diag), XRSC_ERROR_INVALID_ARGUMENT);
    CHECK(p == NULL);
    CHECK(strcmp(diag.field, "--headset") == 0);
    CHECK(strstr(diag.message, "quest3") && strstr(diag.message, "vision-pro"));
    CHECK_EQ_INT(hs_headsets_select(&t, "index", &p, &diag), XRSC_OK);
    CHECK(p && strcmp(p->name, "index") == 0);
    hs_headsets_free(&t);
}

static const char *const good = "# comment\n"
                                "[tiny]\n"
                                "title = Tiny\n"
                                "resolution = 64x32\n"
                                "refresh_hz = 60\n"
                                "refresh_modes_hz = 60 75\n"
                                "ipd_mm = 60\n"
                                "fov_left_deg = -50 40 45 -45.5\n"
                                "fov_right_deg = -40 50 45 -45.5\n"
                                "source = test\n";

static void test_parse_values(void)
{
    hs_headset_table t;
    xrsc_diag diag = {0};
    CHECK_EQ_INT(hs_headsets_parse(good, "mem", &t, &diag), XRSC_OK);
    CHECK_EQ_INT(t.count, 1);
    if (t.count == 1) {
        const xrsc_headset *h = &t.items[0].headset;
        CHECK_EQ_INT(h->width_px, 64);
        CHECK_EQ_INT(h->height_px, 32);
        CHECK_NEAR(h->refresh_hz, 60.0, 0);
        CHECK_NEAR(h->ipd_m, 0.060, 1e-7);
        CHECK_NEAR(h->fov[0].angleLeft, -50 * RAD_PER_DEG, 1e-6);
        CHECK_NEAR(h->fov[0].angleDown, -45.5 * RAD_PER_DEG, 1e-6);
        CHECK_NEAR(h->fov[1].angleRight, 50 * RAD_PER_DEG, 1e-6);
        CHECK_EQ_INT(t.items[0].refresh_mode_count, 2);
    }
    hs_headsets_free(&t);
}

/* Replaces the line starting with `key` in `good` by `line` ("" drops it). */
static const char *with_line(const char *key, const char *line)
{
    static char buf[2048];
    buf[0] = '\0';
    for (const char *p = good; *p;) {
        const char *nl = strchr(p, '\n');
        size_t len = (size_t)(nl - p) + 1;
        if (strncmp(p, key, strlen(key)) == 0)
            strcat(buf, line);
        else
            strncat(buf, p, len);
        p += len;
    }
    return buf;
}

static void expect_error(const char *text, xrsc_result code, int line, const char *field)
{
    hs_headset_table t;
    xrsc_diag diag = {0};
    xrsc_result r = hs_headsets_parse(text, "broken.txt", &t, &diag);
    CHECK_MSG(r == code, "got %s, want %s (%s)", xrsc_result_name(r), xrsc_result_name(code),
              diag.message);
    CHECK_MSG(diag.line == line, "line %d, want %d", diag.line, line);
    CHECK_MSG(strcmp(diag.field, field) == 0, "field '%s', want '%s'", diag.field, field);
    CHECK(strcmp(diag.file, "broken.txt") == 0);
    CHECK(t.items == NULL && t.count == 0);
}

static void test_parse_errors(void)
{
    expect_error("", XRSC_ERROR_EMPTY_FILE, 0, "");
    expect_error("# only comments\n\n", XRSC_ERROR_EMPTY_FILE, 0, "");
    expect_error(with_line("ipd_mm", "ipd_mm = wide\n"), XRSC_ERROR_BAD_NUMBER, 7, "ipd_mm");
    expect_error(with_line("ipd_mm", "ipd_mm = 300\n"), XRSC_ERROR_BAD_NUMBER, 7, "ipd_mm");
    expect_error(with_line("resolution", "resolution = 64*32\n"), XRSC_ERROR_BAD_NUMBER, 4,
                 "resolution");
    expect_error(with_line("fov_left", "fov_left_deg = -50 40 45\n"), XRSC_ERROR_BAD_NUMBER, 8,
                 "fov_left_deg");
    expect_error(with_line("fov_left", "fov_left_deg = 50 -40 45 -45\n"), XRSC_ERROR_BAD_NUMBER, 8,
                 "fov_left_deg");
    expect_error(with_line("fov_right", "fov_right_deg = -40 95 45 -45\n"), XRSC_ERROR_BAD_NUMBER,
                 9, "fov_right_deg");
    expect_error(with_line("source", "colour = red\n"), XRSC_ERROR_UNKNOWN_COLUMN, 10, "colour");
    expect_error(with_line("source", "just words\n"), XRSC_ERROR_UNKNOWN_COLUMN, 10, "");
    expect_error(with_line("source", ""), XRSC_ERROR_INVALID_ARGUMENT, 2, "source");
    expect_error(with_line("refresh_modes", "refresh_modes_hz = 72 90\n"), XRSC_ERROR_BAD_NUMBER, 2,
                 "refresh_modes_hz");
    expect_error(with_line("[tiny]", "[Tiny One]\n"), XRSC_ERROR_INVALID_ARGUMENT, 2, "name");
    expect_error(with_line("title", "title = A\ntitle = B\n"), XRSC_ERROR_INVALID_ARGUMENT, 4,
                 "title");
    expect_error("title = orphan\n", XRSC_ERROR_INVALID_ARGUMENT, 1, "title");
    char twice[4096];
    snprintf(twice, sizeof(twice), "%s%s", good, good);
    expect_error(twice, XRSC_ERROR_INVALID_ARGUMENT, 12, "name");
}

static void test_load_file(void)
{
    hs_headset_table t;
    xrsc_diag diag = {0};
    const char *path = t_temp_file("headsets.txt", good);
    CHECK_EQ_INT(hs_headsets_load(path, &t, &diag), XRSC_OK);
    CHECK(hs_headsets_find(&t, "tiny") != NULL);
    CHECK(hs_headsets_find(&t, "quest3") == NULL); /* a file replaces the built-in list */
    hs_headsets_free(&t);
    remove(path);
    path = t_temp_file("broken-headsets.txt", "[x]\nipd_mm = 63 64\n");
    CHECK_EQ_INT(hs_headsets_load(path, &t, &diag), XRSC_ERROR_BAD_NUMBER);
    CHECK(strcmp(diag.file, path) == 0 && diag.line == 2);
    remove(path);
    CHECK_EQ_INT(hs_headsets_load("/nonexistent/headsets.txt", &t, &diag), XRSC_ERROR_IO);
}

int main(void)
{
    RUN(test_builtin_profiles);
    RUN(test_unknown_name_lists_names);
    RUN(test_parse_values);
    RUN(test_parse_errors);
    RUN(test_load_file);
    return t_finish();
}
