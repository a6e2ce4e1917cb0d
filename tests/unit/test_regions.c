// SPDX-License-Identifier: MIT
/**
 * @file test_regions.c
 * @brief Region masks, region error and recovery frames (xrsc_metrics.h, issue 9) on tiny
 *        hand-made views whose answers are counted by hand: a 16 x 16 eye with a 90 deg square
 *        field of view looking down -Z, a wall (instance 0) at depth 4 m (0.5 m per pixel) and a
 *        box (instance 1) at depth 2 m (0.25 m per pixel).
 */
#include "testing.h"
#include "xrsc/xrsc_metrics.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#define W 16u
#define H 16u
#define N (W * H)
#define WALL_M 4.0f
#define BOX_M 2.0f
#define MISS UINT32_MAX

/* One synthetic view: first-hit ids (x4 per pixel, as XRSC_OUTPUT_HIT_ID) and depth. */
typedef struct view {
    uint32_t id[N * 4];
    float depth[N];
} view;

/* Identity orientation at (x_m, 0, 0), fov +-45 deg: pixel x's centre sees eye-space
 * X = depth * (-1 + 2 (x + 0.5) / W). */
static xrsc_metrics_camera camera_at(double x_m)
{
    const float q = (float)(3.14159265358979323846 / 4.0);
    xrsc_metrics_camera c = {
        .pose = {{0, 0, 0, 1}, {(float)x_m, 0, 0}}, .fov = {-q, q, q, -q}, .width = W, .height = H};
    return c;
}

static void set(view *v, uint32_t x, uint32_t y, uint32_t id, float depth_m)
{
    const size_t p = (size_t)y * W + x;
    v->id[p * 4] = id;
    v->id[p * 4 + 1] = v->id[p * 4 + 2] = v->id[p * 4 + 3] = 0;
    v->depth[p] = depth_m;
}

/* The wall everywhere, the box over columns [bx, bx + 4) of rows [4, 8), `miss_rows` top rows
 * missing (background). */
static void make_view(view *v, int bx, uint32_t miss_rows)
{
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            bool box = (int)x >= bx && (int)x < bx + 4 && y >= 4 && y < 8;
            if (y < miss_rows)
                set(v, x, y, MISS, 0.0f);
            else
                set(v, x, y, box ? 1u : 0u, box ? BOX_M : WALL_M);
        }
}

static uint32_t count_bit(const uint8_t *mask, xrsc_region r)
{
    uint32_t n = 0;
    for (uint32_t p = 0; p < N; p++)
        n += (mask[p] & XRSC_REGION_BIT(r)) != 0;
    return n;
}

static bool in_bit(const uint8_t *mask, uint32_t x, uint32_t y, xrsc_region r)
{
    return (mask[y * W + x] & XRSC_REGION_BIT(r)) != 0;
}

static xrsc_region_input input_of(const view *v, double x_m)
{
    xrsc_region_input in = {
        .width = W, .height = H, .hit_id = v->id, .depth_m = v->depth, .camera = camera_at(x_m)};
    return in;
}

static void test_all_and_edge(void)
{
    static view v;
    make_view(&v, 4, 1);
    uint8_t mask[N];
    xrsc_region_input in = input_of(&v, 0.0);
    CHECK(xrsc_metrics_regions(&in, NULL, mask) == XRSC_OK);
    CHECK_EQ_INT(count_bit(mask, XRSC_REGION_ALL), N - W); /* all but the missing row 0 */
    /* Around the box: [3, 8] x [3, 8] less its 2 x 2 interior = 32; rows 0 and 1 along the
     * miss: 32. */
    CHECK_EQ_INT(count_bit(mask, XRSC_REGION_EDGE), 32 + 32);
    CHECK(in_bit(mask, 3, 3, XRSC_REGION_EDGE) && in_bit(mask, 8, 8, XRSC_REGION_EDGE));
    CHECK(!in_bit(mask, 5, 5, XRSC_REGION_EDGE) && !in_bit(mask, 9, 5, XRSC_REGION_EDGE));
    CHECK(in_bit(mask, 0, 0, XRSC_REGION_EDGE) && !in_bit(mask, 0, 0, XRSC_REGION_ALL));
    /* No flags, no previous frame, no other eye: those regions are empty. */
    for (int r = XRSC_REGION_OBJECT; r < XRSC_REGION_COUNT; r++)
        if (r != XRSC_REGION_EDGE)
            CHECK_EQ_INT(count_bit(mask, (xrsc_region)r), 0);
}

/* One instance whose depth steps from 4 to 6 m between columns 7 and 8 (a crease seen as a
 * depth discontinuity) and a slope of 2 % per column (one plane: no edge). */
static void test_edge_depth_step(void)
{
    static view v;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++)
            set(&v, x, y, 0u, (x < 8 ? 4.0f : 6.0f) * (1.0f + 0.02f * (float)x));
    uint8_t mask[N];
    xrsc_region_input in = input_of(&v, 0.0);
    CHECK(xrsc_metrics_regions(&in, NULL, mask) == XRSC_OK);
    CHECK_EQ_INT(count_bit(mask, XRSC_REGION_EDGE), 2 * H);
    CHECK(in_bit(mask, 7, 3, XRSC_REGION_EDGE) && in_bit(mask, 8, 3, XRSC_REGION_EDGE));
    CHECK(!in_bit(mask, 6, 3, XRSC_REGION_EDGE) && !in_bit(mask, 9, 3, XRSC_REGION_EDGE));
}

static void test_object_specular(void)
{
    static view v;
    make_view(&v, 4, 0);
    for (uint32_t x = 0; x < W; x++) /* instance 2 on row 15, instance 7 (no flags) on row 14 */
        set(&v, x, 15, 2u, WALL_M), set(&v, x, 14, 7u, WALL_M);
    const uint8_t flags[3] = {0, XRSC_INSTANCE_FLAG_OBJECT,
                              XRSC_INSTANCE_FLAG_SPECULAR | XRSC_INSTANCE_FLAG_OBJECT};
    uint8_t mask[N];
    xrsc_region_input in = input_of(&v, 0.0);
    in.instance_flags = flags;
    in.instance_count = 3;
    CHECK(xrsc_metrics_regions(&in, NULL, mask) == XRSC_OK);
    CHECK_EQ_INT(count_bit(mask, XRSC_REGION_OBJECT), 16 + W);
    CHECK_EQ_INT(count_bit(mask, XRSC_REGION_SPECULAR), W);
    CHECK(in_bit(mask, 5, 5, XRSC_REGION_OBJECT) && !in_bit(mask, 5, 5, XRSC_REGION_SPECULAR));
    CHECK(in_bit(mask, 3, 15, XRSC_REGION_SPECULAR) && !in_bit(mask, 3, 14, XRSC_REGION_OBJECT));
}

/* The box slid 2 px to the left since the last frame, camera still: the wall it uncovered
 * (columns 8, 9 of rows 4..7) and, the scene being taken as static, the box's leading columns
 * 4, 5 (wall there last frame) are uncovered. */
static void test_uncovered_moving_box(void)
{
    static view cur, prev;
    make_view(&cur, 4, 0);
    make_view(&prev, 6, 0);
    uint8_t mask[N];
    xrsc_region_input in = input_of(&cur, 0.0);
    in.prev_hit_id = prev.id;
    in.prev_depth_m = prev.depth;
    in.prev_camera = camera_at(0.0);
    CHECK(xrsc_metrics_regions(&in, NULL, mask) == XRSC_OK);
    CHECK_EQ_INT(count_bit(mask, XRSC_REGION_UNCOVERED), 16);
    CHECK(in_bit(mask, 8, 4, XRSC_REGION_UNCOVERED) && in_bit(mask, 9, 7, XRSC_REGION_UNCOVERED));
    CHECK(in_bit(mask, 4, 4, XRSC_REGION_UNCOVERED) && !in_bit(mask, 6, 4, XRSC_REGION_UNCOVERED));
    CHECK(!in_bit(mask, 10, 4, XRSC_REGION_UNCOVERED));
    /* The same frame twice: nothing uncovered. */
    in.prev_hit_id = cur.id;
    in.prev_depth_m = cur.depth;
    CHECK(xrsc_metrics_regions(&in, NULL, mask) == XRSC_OK);
    CHECK_EQ_INT(count_bit(mask, XRSC_REGION_UNCOVERED), 0);
}

/* The camera moved 1 m to the right over the wall alone (2 px at 4 m): the two right columns
 * were outside the last frame's image. A sub-pixel move uncovers nothing (landing points keep
 * their neighbours). */
static void test_uncovered_camera_move(void)
{
    static view v;
    make_view(&v, -100, 0);
    uint8_t mask[N];
    xrsc_region_input in = input_of(&v, 1.0);
    in.prev_hit_id = v.id;
    in.prev_depth_m = v.depth;
    in.prev_camera = camera_at(0.0);
    CHECK(xrsc_metrics_regions(&in, NULL, mask) == XRSC_OK);
    CHECK_EQ_INT(count_bit(mask, XRSC_REGION_UNCOVERED), 2 * H);
    CHECK(in_bit(mask, 14, 0, XRSC_REGION_UNCOVERED) &&
          !in_bit(mask, 13, 0, XRSC_REGION_UNCOVERED));
    in.camera = camera_at(0.2); /* 0.4 px: every landing point is within a pixel of a centre */
    CHECK(xrsc_metrics_regions(&in, NULL, mask) == XRSC_OK);
    CHECK_EQ_INT(count_bit(mask, XRSC_REGION_UNCOVERED), 0);
}

/* The other eye 1 m to the left: the wall moves 2 px right there, the box (2 m) 4 px, to
 * columns 8..11. Seen by this eye only: columns 14, 15 (outside the other image) and the wall
 * at columns 8, 9 of rows 4..7 (behind the box in the other eye). */
static void test_one_eye(void)
{
    static view eye, other;
    make_view(&eye, 4, 0);
    make_view(&other, 8, 0);
    uint8_t mask[N];
    xrsc_region_input in = input_of(&eye, 0.0);
    in.other_depth_m = other.depth;
    in.other_camera = camera_at(-1.0);
    CHECK(xrsc_metrics_regions(&in, NULL, mask) == XRSC_OK);
    CHECK_EQ_INT(count_bit(mask, XRSC_REGION_ONE_EYE), 2 * H + 8);
    CHECK(in_bit(mask, 8, 5, XRSC_REGION_ONE_EYE) && !in_bit(mask, 5, 5, XRSC_REGION_ONE_EYE));
    CHECK(!in_bit(mask, 10, 5, XRSC_REGION_ONE_EYE) && in_bit(mask, 15, 0, XRSC_REGION_ONE_EYE));
    /* With ids as well: the same answer here (depth already separates wall and box). */
    in.other_hit_id = other.id;
    CHECK(xrsc_metrics_regions(&in, NULL, mask) == XRSC_OK);
    CHECK_EQ_INT(count_bit(mask, XRSC_REGION_ONE_EYE), 2 * H + 8);
    /* Ids alone decide when depths agree: another instance at the wall's depth. */
    for (uint32_t p = 0; p < N; p++)
        if (other.id[p * 4] == 0u)
            other.id[p * 4] = 5u;
    CHECK(xrsc_metrics_regions(&in, NULL, mask) == XRSC_OK);
    CHECK_EQ_INT(count_bit(mask, XRSC_REGION_ONE_EYE), N - 16);
}

static void test_region_error(void)
{
    /* 2 x 2: errors 0.1 (ref 1), 0.2 (ref 0), 0 and 1 (ref 2) in every channel. */
    float test[16] = {1.1f, 1.1f, 1.1f, 1, 0.2f, 0.2f, 0.2f, 1, 3, 3, 3, 1, 3, 3, 3, 1};
    float ref[16] = {1, 1, 1, 1, 0, 0, 0, 1, 3, 3, 3, 1, 2, 2, 2, 1};
    const uint8_t mask[4] = {XRSC_REGION_BIT(XRSC_REGION_EDGE) | 1u,
                             XRSC_REGION_BIT(XRSC_REGION_EDGE), 1u, 1u};
    xrsc_error_metrics em;
    uint64_t count = 0;
    CHECK(xrsc_metrics_region_error(test, ref, mask, XRSC_REGION_EDGE, 2, 2, NULL, &em, &count) ==
          XRSC_OK);
    CHECK_EQ_INT(count, 2);
    CHECK_NEAR(em.mse, (0.01 + 0.04) / 2.0, 1e-7);
    CHECK_NEAR(em.relmse, (0.01 / 1.01 + 0.04 / 0.01) / 2.0, 1e-5);
    CHECK_NEAR(em.rmse, sqrt(0.025), 1e-6);
    CHECK(xrsc_metrics_region_error(test, ref, mask, XRSC_REGION_ALL, 2, 2, NULL, &em, &count) ==
          XRSC_OK);
    CHECK_EQ_INT(count, 3);
    CHECK_NEAR(em.mse, (0.01 + 0 + 1) / 3.0, 1e-6);
    CHECK_NEAR(em.relmse, (0.01 / 1.01 + 1.0 / 4.01) / 3.0, 1e-6);
    CHECK(xrsc_metrics_region_error(test, ref, mask, XRSC_REGION_OBJECT, 2, 2, NULL, &em, &count) ==
          XRSC_OK);
    CHECK(count == 0 && em.mse == 0.0 && em.relmse == 0.0);
}

static void test_recovery_frames(void)
{
    double e[20];
    for (int k = 0; k < 20; k++)
        e[k] = 1.0;
    e[10] = 1.1; /* the turn starts slowly */
    e[11] = 5.0;
    e[12] = 3.0;
    e[13] = 1.5;
    e[14] = 1.19;
    CHECK_EQ_INT(xrsc_metrics_recovery_frames(e, 20, 10, 0, 1.2), 4);
    CHECK_EQ_INT(xrsc_metrics_recovery_frames(e, 20, 10, 5, 1.2), 4);
    /* Baseline over the last 4 frames only, (1 + 1 + 3 + 3) / 4 = 2: back at frame 13. */
    e[8] = e[9] = 3.0;
    CHECK_EQ_INT(xrsc_metrics_recovery_frames(e, 20, 10, 4, 1.2), 3);
    e[8] = e[9] = 1.0;
    /* Unscored frames (NaN) are skipped: the next measured frame counts. */
    e[13] = e[14] = NAN;
    CHECK_EQ_INT(xrsc_metrics_recovery_frames(e, 20, 10, 0, 1.2), 5);
    /* Never back; no spike; no baseline. */
    for (int k = 11; k < 20; k++)
        e[k] = 2.0;
    CHECK_EQ_INT(xrsc_metrics_recovery_frames(e, 20, 10, 0, 1.2), UINT32_MAX);
    for (int k = 10; k < 20; k++)
        e[k] = 1.1;
    CHECK_EQ_INT(xrsc_metrics_recovery_frames(e, 20, 10, 0, 1.2), 0);
    CHECK_EQ_INT(xrsc_metrics_recovery_frames(e, 20, 0, 0, 1.2), UINT32_MAX);
    CHECK_EQ_INT(xrsc_metrics_recovery_frames(e, 20, 20, 0, 1.2), UINT32_MAX);
    CHECK_EQ_INT(xrsc_metrics_recovery_frames(NULL, 20, 10, 0, 1.2), UINT32_MAX);
}

/* A turn over frames 10..14 (end 15): baseline before 10, counted from 15. */
static void test_recovery_after(void)
{
    double e[24];
    for (int k = 0; k < 24; k++)
        e[k] = 1.0;
    const double turn[] = {5, 6, 7, 8, 9, 4, 2, 1.1};
    for (int i = 0; i < 8; i++)
        e[10 + i] = turn[i];
    CHECK_EQ_INT(xrsc_metrics_recovery_frames_after(e, 24, 10, 0, 15, 1.2), 2);
    CHECK_EQ_INT(xrsc_metrics_recovery_frames_after(e, 24, 10, 0, 10, 1.2), 7);
    CHECK_EQ_INT(xrsc_metrics_recovery_frames(e, 24, 10, 0, 1.2), 7);
    /* Back before the turn ends: 0 from the end. */
    for (int k = 12; k < 24; k++)
        e[k] = 1.0;
    CHECK_EQ_INT(xrsc_metrics_recovery_frames_after(e, 24, 10, 0, 15, 1.2), 0);
    CHECK_EQ_INT(xrsc_metrics_recovery_frames_after(e, 24, 10, 0, 9, 1.2), UINT32_MAX);
    CHECK_EQ_INT(xrsc_metrics_recovery_frames_after(e, 24, 10, 0, 24, 1.2), UINT32_MAX);
}

static void test_bad_input(void)
{
    static view v;
    make_view(&v, 4, 0);
    uint8_t mask[N];
    xrsc_region_input in = input_of(&v, 0.0);
    CHECK(xrsc_metrics_regions(NULL, NULL, mask) == XRSC_ERROR_INVALID_ARGUMENT);
    CHECK(xrsc_metrics_regions(&in, NULL, NULL) == XRSC_ERROR_INVALID_ARGUMENT);
    in.camera.width = W + 1;
    CHECK(xrsc_metrics_regions(&in, NULL, mask) == XRSC_ERROR_INVALID_ARGUMENT);
    in = input_of(&v, 0.0);
    in.prev_hit_id = v.id; /* prev_depth_m missing */
    in.prev_camera = camera_at(0.0);
    CHECK(xrsc_metrics_regions(&in, NULL, mask) == XRSC_ERROR_INVALID_ARGUMENT);
    in = input_of(&v, 0.0);
    v.depth[7] = NAN;
    CHECK(xrsc_metrics_regions(&in, NULL, mask) == XRSC_ERROR_NAN);
    float img[16] = {0};
    xrsc_error_metrics em;
    CHECK(xrsc_metrics_region_error(img, img, mask, XRSC_REGION_COUNT, 2, 2, NULL, &em, NULL) ==
          XRSC_ERROR_INVALID_ARGUMENT);
    CHECK(xrsc_metrics_region_error(img, img, NULL, XRSC_REGION_ALL, 2, 2, NULL, &em, NULL) ==
          XRSC_ERROR_INVALID_ARGUMENT);
    CHECK(strcmp(xrsc_region_name(XRSC_REGION_ONE_EYE), "one_eye") == 0);
    CHECK(strcmp(xrsc_region_name(XRSC_REGION_COUNT), "?") == 0);
}

int main(void)
{
    RUN(test_all_and_edge);
    RUN(test_edge_depth_step);
    RUN(test_object_specular);
    RUN(test_uncovered_moving_box);
    RUN(test_uncovered_camera_move);
    RUN(test_one_eye);
    RUN(test_region_error);
    RUN(test_recovery_frames);
    RUN(test_recovery_after);
    RUN(test_bad_input);
    return t_finish();
}
