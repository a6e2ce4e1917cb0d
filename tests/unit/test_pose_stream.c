// SPDX-License-Identifier: MIT
/**
 * @file test_pose_stream.c
 * @brief Unit tests of pose streams: canonical round trip, importers on the real captures,
 *        lookup, anchoring, the bundled stream and every bad-input class (poses/README.md).
 */
#include "hs_pose_stream.h"
#include "testing.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#define PI_D 3.14159265358979323846
#define DEG (PI_D / 180.0)

static const XrVector3f AY = {0, 1, 0};

static double quat_dist(XrQuaternionf q, XrQuaternionf r)
{
    double d1 = fabs(q.x - r.x) + fabs(q.y - r.y) + fabs(q.z - r.z) + fabs(q.w - r.w);
    double d2 = fabs(q.x + r.x) + fabs(q.y + r.y) + fabs(q.z + r.z) + fabs(q.w + r.w);
    return d1 < d2 ? d1 : d2;
}

static double quat_len(XrQuaternionf q)
{
    return sqrt((double)q.x * q.x + (double)q.y * q.y + (double)q.z * q.z + (double)q.w * q.w);
}

static xrsc_result parse_text(const char *text, hs_pose_format format, hs_pose_stream **out,
                              xrsc_diag *diag)
{
    return hs_pose_stream_parse("mem.txt", text, strlen(text), format, out, diag);
}

/** Samples, duplicates and flags of two streams are identical bit for bit. */
static void check_streams_equal(const hs_pose_stream *a, const hs_pose_stream *b)
{
    CHECK_EQ_INT(a->count, b->count);
    CHECK_EQ_INT(a->orientation_only, b->orientation_only);
    if (a->count != b->count)
        return;
    for (size_t i = 0; i < a->count; i++) {
        CHECK_EQ_INT(a->samples[i].time_ns, b->samples[i].time_ns);
        CHECK(memcmp(&a->samples[i].pose, &b->samples[i].pose, sizeof(XrPosef)) == 0);
    }
}

static void test_round_trip(void)
{
    /* Awkward values: many digits, negative zero, tiny numbers, non-zero start time. */
    const char *text = "# leading comment\n"
                       "\n"
                       "xrsc-poses 1\n"
                       "columns t_ns px py pz qx qy qz qw\n"
                       "1000 0.1 -0.2 1e-7 0 0 0 1\n"
                       "12111111 0.123456789 2.5 -3 0.0270707835 -0.5 0.1 0.8599\n"
                       "22222222 -1e-30 0 0 0.70710678 0 0 0.70710678\n";
    hs_pose_stream *s = NULL, *t = NULL;
    xrsc_diag diag;
    CHECK_EQ_INT(parse_text(text, HS_POSE_FORMAT_AUTO, &s, &diag), XRSC_OK);
    if (!s)
        return;
    CHECK_EQ_INT(s->format, HS_POSE_FORMAT_XRSC);
    CHECK_EQ_INT(s->count, 3);
    CHECK_EQ_INT(s->samples[0].time_ns, 0); /* relative to the first sample */
    CHECK_EQ_INT(s->samples[1].time_ns, 12110111);
    CHECK_NEAR(s->samples[1].pose.position.x, 0.123456789, 1e-8);
    for (size_t i = 0; i < s->count; i++)
        CHECK_NEAR(quat_len(s->samples[i].pose.orientation), 1.0, 1e-6);
    const char *path = t_temp_file("round.xrpose", "");
    CHECK_EQ_INT(hs_pose_stream_save(s, path, &diag), XRSC_OK);
    CHECK_EQ_INT(hs_pose_stream_load(path, HS_POSE_FORMAT_AUTO, &t, &diag), XRSC_OK);
    if (t)
        check_streams_equal(s, t);
    hs_pose_stream_destroy(&t);

    /* Columns in another order, CRLF line ends: same stream. */
    const char *reordered = "xrsc-poses 1\r\n"
                            "columns qw qx qy qz t_ns pz py px\r\n"
                            "1 0 0 0 1000 1e-7 -0.2 0.1\r\n"
                            "0.8599 0.0270707835 -0.5 0.1 12111111 -3 2.5 0.123456789\r\n"
                            "0.70710678 0.70710678 0 0 22222222 0 0 -1e-30\r\n";
    CHECK_EQ_INT(parse_text(reordered, HS_POSE_FORMAT_XRSC, &t, &diag), XRSC_OK);
    if (t)
        check_streams_equal(s, t);
    hs_pose_stream_destroy(&t);
    hs_pose_stream_destroy(&s);
    CHECK(s == NULL);
    hs_pose_stream_destroy(&s); /* NULL is accepted */
    hs_pose_stream_destroy(NULL);

    /* Orientation only: no position columns, round trips with the flag. */
    const char *ori = "xrsc-poses 1\ncolumns t_ns qx qy qz qw\n0 0 0 0 1\n5 0 0.6 0 0.8\n";
    CHECK_EQ_INT(parse_text(ori, HS_POSE_FORMAT_AUTO, &s, &diag), XRSC_OK);
    if (!s)
        return;
    CHECK(s->orientation_only);
    path = t_temp_file("ori.xrpose", "");
    CHECK_EQ_INT(hs_pose_stream_save(s, path, &diag), XRSC_OK);
    CHECK_EQ_INT(hs_pose_stream_load(path, HS_POSE_FORMAT_XRSC, &t, &diag), XRSC_OK);
    if (t)
        check_streams_equal(s, t);
    hs_pose_stream_destroy(&t);
    hs_pose_stream_destroy(&s);
}

/** Reads data line `n` (1-based, header is line 1) of a file into buf. */
static int read_line(const char *path, int n, char *buf, size_t size)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return 0;
    int ok = 0;
    for (int i = 1; i <= n && fgets(buf, (int)size, f); i++)
        ok = i == n;
    fclose(f);
    return ok;
}

static void check_monotonic_unit(const hs_pose_stream *s)
{
    int bad_time = 0, bad_quat = 0;
    for (size_t i = 0; i < s->count; i++) {
        if (i > 0 && s->samples[i].time_ns <= s->samples[i - 1].time_ns)
            bad_time++;
        if (fabs(quat_len(s->samples[i].pose.orientation) - 1.0) > 1e-6)
            bad_quat++;
    }
    CHECK_EQ_INT(bad_time, 0);
    CHECK_EQ_INT(bad_quat, 0);
}

static void test_import_pred6dof(void)
{
    const char *path = t_shared_path("poses/pred6dof-hololens/1.csv");
    hs_pose_stream *s = NULL;
    xrsc_diag diag;
    xrsc_result r = hs_pose_stream_load(path, HS_POSE_FORMAT_AUTO, &s, &diag);
    CHECK_EQ_INT(r, XRSC_OK);
    if (!s)
        return;
    CHECK_EQ_INT(s->format, HS_POSE_FORMAT_PRED6DOF);
    CHECK(!s->orientation_only);
    CHECK_EQ_INT(s->count, 4664);
    CHECK_EQ_INT(s->dropped_duplicates, 0);
    check_monotonic_unit(s);

    /* First and second data lines by hand: ticks x100 -> ns from the first; p = (x, y, -z),
     * q = (-qx, -qy, qz, qw). */
    char l2[512], l3[512];
    CHECK(read_line(path, 2, l2, sizeof(l2)));
    CHECK(read_line(path, 3, l3, sizeof(l3)));
    long long t0, t1;
    double v[7], w[7];
    CHECK_EQ_INT(sscanf(l2, "%lld, %lf, %lf, %lf, %lf, %lf, %lf, %lf", &t0, &v[0], &v[1], &v[2],
                        &v[3], &v[4], &v[5], &v[6]),
                 8);
    CHECK_EQ_INT(sscanf(l3, "%lld, %lf, %lf, %lf, %lf, %lf, %lf, %lf", &t1, &w[0], &w[1], &w[2],
                        &w[3], &w[4], &w[5], &w[6]),
                 8);
    const XrPosef p = s->samples[0].pose;
    CHECK_EQ_INT(s->samples[0].time_ns, 0);
    CHECK_NEAR(p.position.x, v[0], 1e-7);
    CHECK_NEAR(p.position.y, v[1], 1e-7);
    CHECK_NEAR(p.position.z, -v[2], 1e-7);
    CHECK_NEAR(p.orientation.x, -v[3], 1e-6);
    CHECK_NEAR(p.orientation.y, -v[4], 1e-6);
    CHECK_NEAR(p.orientation.z, v[5], 1e-6);
    CHECK_NEAR(p.orientation.w, v[6], 1e-6);
    CHECK_EQ_INT(s->samples[1].time_ns, (t1 - t0) * 100);
    CHECK_NEAR(s->samples[1].pose.position.z, -w[2], 1e-7);
    /* 77.7 s in all (poses/README.md of shared/). */
    CHECK_NEAR(hs_pose_stream_duration_ns(s) / 1e9, 77.70028, 1e-5);
    /* The conversion keeps the rotation proper: the head's up axis stays near +Y. */
    double up = 0;
    for (size_t i = 0; i < s->count; i++)
        up += xrsc_quat_rotate(s->samples[i].pose.orientation, AY).y;
    CHECK(up / (double)s->count > 0.9);
    hs_pose_stream_destroy(&s);
}

static void test_import_360video(void)
{
    const char *path = t_shared_path("poses/360video-orientation/user1_quaternion.txt");
    hs_pose_stream *s = NULL;
    xrsc_diag diag;
    CHECK_EQ_INT(hs_pose_stream_load(path, HS_POSE_FORMAT_AUTO, &s, &diag), XRSC_OK);
    if (!s)
        return;
    CHECK_EQ_INT(s->format, HS_POSE_FORMAT_360VIDEO);
    CHECK(s->orientation_only);
    CHECK_EQ_INT(s->count + s->dropped_duplicates, 16053);
    check_monotonic_unit(s);
    char l2[512], l3[512];
    CHECK(read_line(path, 2, l2, sizeof(l2)));
    CHECK(read_line(path, 3, l3, sizeof(l3)));
    double t0, t1, q[4], q1[4];
    int vp;
    CHECK_EQ_INT(sscanf(l2, "%lf %d %lf %lf %lf %lf", &t0, &vp, &q[0], &q[1], &q[2], &q[3]), 6);
    CHECK_EQ_INT(sscanf(l3, "%lf %d %lf %lf %lf %lf", &t1, &vp, &q1[0], &q1[1], &q1[2], &q1[3]), 6);
    /* Trace axes x forward, y left, z up -> OpenXR: (qx, qy, qz, qw) = (-y, z, -x, w). */
    const XrPosef p = s->samples[0].pose;
    CHECK_NEAR(p.orientation.x, -q[2], 1e-6);
    CHECK_NEAR(p.orientation.y, q[3], 1e-6);
    CHECK_NEAR(p.orientation.z, -q[1], 1e-6);
    CHECK_NEAR(p.orientation.w, q[0], 1e-6);
    CHECK_EQ_INT(p.position.x == 0 && p.position.y == 0 && p.position.z == 0, 1);
    CHECK_EQ_INT(s->samples[1].time_ns, llround((t1 - t0) * 1e9));
    CHECK_NEAR(hs_pose_stream_duration_ns(s) / 1e9, 272.056, 1e-3);
    /* The conversion puts the viewer's up near +Y (a 360-video viewer looks around the
     * horizon); with the raw axes the mean would be near 0. */
    double up = 0;
    int flips = 0;
    for (size_t i = 0; i < s->count; i++) {
        up += xrsc_quat_rotate(s->samples[i].pose.orientation, AY).y;
        if (i > 0) {
            XrQuaternionf a = s->samples[i - 1].pose.orientation,
                          b = s->samples[i].pose.orientation;
            flips += a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w < 0;
        }
    }
    CHECK(up / (double)s->count > 0.9);
    CHECK(flips > 0); /* the sign flips are kept: lookup must handle them */
    /* Lookups between sign-flipped neighbours stay on the short arc. */
    int long_way = 0;
    for (size_t i = 1; i < s->count; i++) {
        XrQuaternionf a = s->samples[i - 1].pose.orientation, b = s->samples[i].pose.orientation;
        if (a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w >= 0)
            continue;
        int64_t mid =
            s->samples[i - 1].time_ns + (s->samples[i].time_ns - s->samples[i - 1].time_ns) / 2;
        XrPosef m;
        hs_pose_stream_sample(s, mid, &m);
        double ab = xrsc_quat_angle_between(a, b);
        if (xrsc_quat_angle_between(a, m.orientation) > 0.5 * ab + 1e-3)
            long_way++;
    }
    CHECK_EQ_INT(long_way, 0);
    hs_pose_stream_destroy(&s);
}

static void test_lookup(void)
{
    /* 0: identity at origin; 1 s: yaw 90 deg at (1,2,3); 2 s: the same rotation sign-flipped. */
    XrQuaternionf y90 = xrsc_quat_from_axis_angle(AY, (float)(90 * DEG));
    char text[512];
    snprintf(text, sizeof(text),
             "xrsc-poses 1\ncolumns t_ns px py pz qx qy qz qw\n"
             "0 0 0 0 0 0 0 1\n"
             "1000000000 1 2 3 %.9g %.9g %.9g %.9g\n"
             "3000000000 1 2 3 %.9g %.9g %.9g %.9g\n",
             y90.x, y90.y, y90.z, y90.w, -y90.x, -y90.y, -y90.z, -y90.w);
    hs_pose_stream *s = NULL;
    xrsc_diag diag;
    CHECK_EQ_INT(parse_text(text, HS_POSE_FORMAT_XRSC, &s, &diag), XRSC_OK);
    if (!s)
        return;
    CHECK_EQ_INT(hs_pose_stream_duration_ns(s), 3000000000LL);
    XrPosef p;
    CHECK_EQ_INT(hs_pose_stream_sample(s, 0, &p), HS_LOOKUP_EXACT);
    CHECK_EQ_INT(hs_pose_stream_sample(s, 1000000000, &p), HS_LOOKUP_EXACT);
    CHECK(quat_dist(p.orientation, y90) < 1e-6);
    CHECK_EQ_INT(hs_pose_stream_sample(s, 3000000000LL, &p), HS_LOOKUP_EXACT);
    CHECK_EQ_INT(hs_pose_stream_sample(s, 500000000, &p), HS_LOOKUP_INTERPOLATED);
    /* The midpoint of a 90-degree yaw pair is 45 degrees; position halfway. */
    CHECK(quat_dist(p.orientation, xrsc_quat_from_axis_angle(AY, (float)(45 * DEG))) < 1e-5);
    CHECK_NEAR(p.position.x, 0.5, 1e-6);
    CHECK_NEAR(p.position.z, 1.5, 1e-6);
    /* A quarter of the way. */
    hs_pose_stream_sample(s, 250000000, &p);
    CHECK_NEAR(xrsc_quat_angle_between(xrsc_pose_identity().orientation, p.orientation), 22.5 * DEG,
               1e-5);
    /* Between a rotation and its sign flip nothing moves (the hemisphere check). */
    CHECK_EQ_INT(hs_pose_stream_sample(s, 2000000000, &p), HS_LOOKUP_INTERPOLATED);
    CHECK(quat_dist(p.orientation, y90) < 1e-6);
    /* Clamped outside: held first/last pose. */
    CHECK_EQ_INT(hs_pose_stream_sample(s, -5, &p), HS_LOOKUP_CLAMPED);
    CHECK(quat_dist(p.orientation, xrsc_pose_identity().orientation) < 1e-7);
    CHECK_EQ_INT(hs_pose_stream_sample(s, 4000000000LL, &p), HS_LOOKUP_CLAMPED);
    CHECK(quat_dist(p.orientation, y90) < 1e-6);
    CHECK_NEAR(p.position.y, 2.0, 0);
    /* A NULL or empty stream answers the identity, clamped. */
    CHECK_EQ_INT(hs_pose_stream_sample(NULL, 0, &p), HS_LOOKUP_CLAMPED);
    CHECK(p.orientation.w == 1.0f);
    hs_pose_stream_destroy(&s);
}

static void test_lookup_binary_search(void)
{
    /* Many samples at uneven times: every exact time is EXACT and every midpoint lands between
     * its own two samples (checks the search picks the right interval). */
    char *text = malloc(200000);
    if (!text)
        return;
    size_t len = (size_t)sprintf(text, "xrsc-poses 1\ncolumns t_ns px py pz qx qy qz qw\n");
    int64_t t = 0;
    for (int i = 0; i < 1000; i++) {
        len += (size_t)sprintf(text + len, "%lld %d 0 0 0 0 0 1\n", (long long)t, i);
        t += 1000 + (i * 7919) % 5000;
    }
    hs_pose_stream *s = NULL;
    xrsc_diag diag;
    CHECK_EQ_INT(hs_pose_stream_parse("many", text, len, HS_POSE_FORMAT_XRSC, &s, &diag), XRSC_OK);
    free(text);
    if (!s)
        return;
    int bad = 0;
    for (size_t i = 0; i + 1 < s->count; i++) {
        XrPosef p;
        if (hs_pose_stream_sample(s, s->samples[i].time_ns, &p) != HS_LOOKUP_EXACT ||
            p.position.x != (float)i)
            bad++;
        int64_t mid = s->samples[i].time_ns + 1;
        if (hs_pose_stream_sample(s, mid, &p) != HS_LOOKUP_INTERPOLATED ||
            !(p.position.x > (float)i && p.position.x < (float)i + 1))
            bad++;
    }
    CHECK_EQ_INT(bad, 0);
    hs_pose_stream_destroy(&s);
}

static void test_duplicates(void)
{
    const char *text = "timestamp viewpoint w x y z\n"
                       "0.0 0 1 0 0 0\n"
                       "0.5 0 1 0 0 0\n"
                       "0.5 1 0.6 0 0 0.8\n"
                       "0.75 1 0.6 0 0 0.8\n";
    hs_pose_stream *s = NULL;
    xrsc_diag diag;
    CHECK_EQ_INT(parse_text(text, HS_POSE_FORMAT_AUTO, &s, &diag), XRSC_OK);
    if (!s)
        return;
    CHECK_EQ_INT(s->count, 3);
    CHECK_EQ_INT(s->dropped_duplicates, 1);
    CHECK_EQ_INT(s->samples[1].time_ns, 500000000);
    /* The later sample is kept: (qx, qy, qz, qw) = (-y, z, -x, w), so trace z = 0.8 is qy. */
    CHECK_NEAR(s->samples[1].pose.orientation.y, 0.8, 1e-7);
    CHECK_NEAR(s->samples[1].pose.orientation.w, 0.6, 1e-7);
    hs_pose_stream_destroy(&s);
}

static void test_anchor(void)
{
    XrQuaternionf a = xrsc_quat_from_axis_angle(AY, 0.4f);
    XrQuaternionf b = xrsc_quat_normalize((XrQuaternionf){0.1f, 0.3f, -0.2f, 0.9f});
    char text[512];
    snprintf(text, sizeof(text),
             "xrsc-poses 1\ncolumns t_ns px py pz qx qy qz qw\n"
             "0 0.5 1.2 -0.3 %.9g %.9g %.9g %.9g\n"
             "10 0.7 1.1 -0.9 %.9g %.9g %.9g %.9g\n",
             a.x, a.y, a.z, a.w, b.x, b.y, b.z, b.w);
    hs_pose_stream *s = NULL;
    xrsc_diag diag;
    CHECK_EQ_INT(parse_text(text, HS_POSE_FORMAT_XRSC, &s, &diag), XRSC_OK);
    if (!s)
        return;
    XrPosef rel_before = xrsc_pose_mul(xrsc_pose_inverse(s->samples[0].pose), s->samples[1].pose);
    XrPosef vp = {xrsc_quat_from_axis_angle((XrVector3f){0.6f, 0.0f, 0.8f}, 1.0f), {2, 1.6f, 5}};
    hs_pose_stream_anchor(s, vp);
    /* The first pose becomes the viewpoint... */
    CHECK(quat_dist(s->samples[0].pose.orientation, vp.orientation) < 1e-6);
    CHECK_NEAR(s->samples[0].pose.position.x, 2, 1e-6);
    CHECK_NEAR(s->samples[0].pose.position.y, 1.6, 1e-6);
    CHECK_NEAR(s->samples[0].pose.position.z, 5, 1e-6);
    /* ... and the motion relative to it is unchanged. */
    XrPosef rel_after = xrsc_pose_mul(xrsc_pose_inverse(s->samples[0].pose), s->samples[1].pose);
    CHECK(quat_dist(rel_before.orientation, rel_after.orientation) < 1e-6);
    CHECK_NEAR(rel_before.position.x, rel_after.position.x, 1e-5);
    CHECK_NEAR(rel_before.position.y, rel_after.position.y, 1e-5);
    CHECK_NEAR(rel_before.position.z, rel_after.position.z, 1e-5);
    hs_pose_stream_destroy(&s);

    /* Orientation only: every position is the viewpoint's. */
    const char *ori = "xrsc-poses 1\ncolumns t_ns qx qy qz qw\n0 0 0.6 0 0.8\n5 0 0 0 1\n";
    CHECK_EQ_INT(parse_text(ori, HS_POSE_FORMAT_XRSC, &s, &diag), XRSC_OK);
    if (!s)
        return;
    hs_pose_stream_anchor(s, vp);
    for (size_t i = 0; i < s->count; i++) {
        CHECK(memcmp(&s->samples[i].pose.position, &vp.position, sizeof(XrVector3f)) == 0);
    }
    CHECK(quat_dist(s->samples[0].pose.orientation, vp.orientation) < 1e-6);
    /* sample 1 was the first rotated back by -73.7 deg about Y: the same holds after. */
    XrQuaternionf expect =
        xrsc_quat_mul(vp.orientation, xrsc_quat_conjugate((XrQuaternionf){0, 0.6f, 0, 0.8f}));
    CHECK(quat_dist(s->samples[1].pose.orientation, expect) < 1e-6);
    hs_pose_stream_destroy(&s);
}

static void test_bundled_orbit(void)
{
    hs_pose_stream *s = NULL;
    xrsc_diag diag;
    CHECK_EQ_INT(hs_pose_stream_load(t_source_path("poses/orbit_cornell.xrpose"),
                                     HS_POSE_FORMAT_AUTO, &s, &diag),
                 XRSC_OK);
    if (!s)
        return;
    CHECK_EQ_INT(s->format, HS_POSE_FORMAT_XRSC);
    CHECK_EQ_INT(s->count, 180);
    /* Starts at the identity. */
    CHECK(quat_dist(s->samples[0].pose.orientation, xrsc_pose_identity().orientation) < 1e-7);
    CHECK(s->samples[0].pose.position.x == 0 && s->samples[0].pose.position.y == 0 &&
          s->samples[0].pose.position.z == 0);
    double max_yaw = 0, max_pitch = 0, max_pos = 0, max_rate = 0;
    for (size_t i = 0; i < s->count; i++) {
        const XrPosef *p = &s->samples[i].pose;
        XrVector3f f = xrsc_quat_rotate(p->orientation, (XrVector3f){0, 0, -1});
        max_yaw = fmax(max_yaw, fabs(atan2(-f.x, -f.z)) / DEG);
        max_pitch = fmax(max_pitch, fabs(asin(f.y)) / DEG);
        max_pos = fmax(max_pos, sqrt(p->position.x * p->position.x + p->position.y * p->position.y +
                                     p->position.z * p->position.z));
        if (i > 0) {
            /* 90 Hz: 11.1 ms steps (+-1 ns of rounding). */
            int64_t dt = s->samples[i].time_ns - s->samples[i - 1].time_ns;
            CHECK(dt >= 11111110 && dt <= 11111112);
            double rate =
                xrsc_quat_angle_between(s->samples[i - 1].pose.orientation, p->orientation) / DEG /
                (dt * 1e-9);
            max_rate = fmax(max_rate, rate);
        }
    }
    CHECK(max_yaw > 15 && max_yaw <= 25.5);
    CHECK(max_pitch > 5 && max_pitch <= 10.5);
    CHECK(max_pos > 0.01 && max_pos < 0.06);
    CHECK(max_rate > 100 && max_rate < 250); /* the quick head turn */
    hs_pose_stream_destroy(&s);
}

/* ---- bad input ---------------------------------------------------------------------------- */

typedef struct bad_case {
    const char *what;
    hs_pose_format format;
    const char *text;
    xrsc_result code;
    int line;
    const char *field;
} bad_case;

#define CANON "xrsc-poses 1\ncolumns t_ns px py pz qx qy qz qw\n" /* data from line 3 */
#define PRED "timestamp,x,y,z,qx,qy,qz,qw\n"                      /* data from line 2 */
#define VID "timestamp viewpoint w x y z\n"                       /* data from line 2 */

static const bad_case bad_cases[] = {
    {"nan position", HS_POSE_FORMAT_AUTO, CANON "0 0 0 0 0 0 0 1\n10 nan 0 0 0 0 0 1\n",
     XRSC_ERROR_NAN, 4, "px"},
    {"inf quaternion", HS_POSE_FORMAT_AUTO, CANON "0 0 0 0 0 0 0 inf\n", XRSC_ERROR_NAN, 3, "qw"},
    {"nan time", HS_POSE_FORMAT_AUTO, CANON "NaN 0 0 0 0 0 0 1\n", XRSC_ERROR_NAN, 3, "t_ns"},
    {"float overflow", HS_POSE_FORMAT_AUTO, CANON "0 0 1e39 0 0 0 0 1\n", XRSC_ERROR_NAN, 3, "py"},
    {"non-unit quaternion", HS_POSE_FORMAT_AUTO, CANON "0 0 0 0 0 0 0 1\n5 0 0 0 0 0 0 1.0011\n",
     XRSC_ERROR_QUAT_NOT_UNIT, 4, "qx qy qz qw"},
    {"zero quaternion", HS_POSE_FORMAT_AUTO, CANON "0 0 0 0 0 0 0 0\n", XRSC_ERROR_QUAT_NOT_UNIT, 3,
     "qx qy qz qw"},
    {"time backwards", HS_POSE_FORMAT_AUTO,
     CANON "0 0 0 0 0 0 0 1\n# c\n\n10 0 0 0 0 0 0 1\n9 0 0 0 0 0 0 1\n", XRSC_ERROR_TIME_BACKWARDS,
     7, "t_ns"},
    {"truncated line", HS_POSE_FORMAT_AUTO, CANON "0 0 0 0 0 0 0 1\n10 0 0 0 0\n",
     XRSC_ERROR_TRUNCATED_LINE, 4, "qy"},
    {"truncated last line", HS_POSE_FORMAT_AUTO, CANON "0 0 0 0 0 0 0 1\n10 0 0 0 0 0 0",
     XRSC_ERROR_TRUNCATED_LINE, 4, "qw"},
    {"extra field", HS_POSE_FORMAT_AUTO, CANON "0 0 0 0 0 0 0 1 7\n", XRSC_ERROR_UNKNOWN_COLUMN, 3,
     "field 9"},
    {"unknown column", HS_POSE_FORMAT_AUTO,
     "xrsc-poses 1\ncolumns t_ns px py pz qx qy qz qw speed\n0 0 0 0 0 0 0 1 0\n",
     XRSC_ERROR_UNKNOWN_COLUMN, 2, "speed"},
    {"bad number", HS_POSE_FORMAT_AUTO, CANON "0 0 0 0 0 0 0 1\n10 0.1 0.2x 0 0 0 0 1\n",
     XRSC_ERROR_BAD_NUMBER, 4, "py"},
    {"fractional ns", HS_POSE_FORMAT_AUTO, CANON "1.5 0 0 0 0 0 0 1\n", XRSC_ERROR_BAD_NUMBER, 3,
     "t_ns"},
    {"ns out of range", HS_POSE_FORMAT_AUTO, CANON "99999999999999999999 0 0 0 0 0 0 1\n",
     XRSC_ERROR_BAD_NUMBER, 3, "t_ns"},
    {"ns span overflow", HS_POSE_FORMAT_AUTO,
     CANON "-9000000000000000000 0 0 0 0 0 0 1\n9000000000000000000 0 0 0 0 0 0 1\n",
     XRSC_ERROR_BAD_NUMBER, 4, "t_ns"},
    {"empty", HS_POSE_FORMAT_AUTO, "", XRSC_ERROR_EMPTY_FILE, 0, ""},
    {"blank", HS_POSE_FORMAT_AUTO, " \n\r\n\t\n", XRSC_ERROR_EMPTY_FILE, 0, ""},
    {"only comments", HS_POSE_FORMAT_AUTO, "# a\n\n# b\n", XRSC_ERROR_EMPTY_FILE, 0, ""},
    {"no samples", HS_POSE_FORMAT_AUTO, CANON "# none\n", XRSC_ERROR_EMPTY_FILE, 0, ""},
    {"importer no samples", HS_POSE_FORMAT_AUTO, PRED, XRSC_ERROR_EMPTY_FILE, 0, ""},
    {"unknown header", HS_POSE_FORMAT_AUTO, "# x\nhello world\n", XRSC_ERROR_BAD_HEADER, 2,
     "header"},
    {"version 2", HS_POSE_FORMAT_AUTO, "xrsc-poses 2\n", XRSC_ERROR_BAD_HEADER, 1, "version"},
    {"no version", HS_POSE_FORMAT_AUTO, "# c\nxrsc-poses\n", XRSC_ERROR_BAD_HEADER, 2, "version"},
    {"no columns line", HS_POSE_FORMAT_AUTO, "xrsc-poses 1\n0 0 0 0 0 0 0 1\n",
     XRSC_ERROR_BAD_HEADER, 2, "columns"},
    {"missing column", HS_POSE_FORMAT_AUTO, "xrsc-poses 1\ncolumns t_ns px py pz qx qy qz\n",
     XRSC_ERROR_BAD_HEADER, 2, "qw"},
    {"partial position", HS_POSE_FORMAT_AUTO, "xrsc-poses 1\ncolumns t_ns px qx qy qz qw\n",
     XRSC_ERROR_BAD_HEADER, 2, "py"},
    {"column twice", HS_POSE_FORMAT_AUTO, "xrsc-poses 1\ncolumns t_ns px py pz px qx qy qz qw\n",
     XRSC_ERROR_BAD_HEADER, 2, "px"},
    {"second columns", HS_POSE_FORMAT_AUTO, CANON "0 0 0 0 0 0 0 1\ncolumns t_ns qx qy qz qw\n",
     XRSC_ERROR_BAD_HEADER, 4, "columns"},
    {"format mismatch", HS_POSE_FORMAT_PRED6DOF, CANON "0 0 0 0 0 0 0 1\n", XRSC_ERROR_BAD_HEADER,
     1, "header"},
    {"format mismatch 360", HS_POSE_FORMAT_360VIDEO, PRED "1,0,0,0,0,0,0,1\n",
     XRSC_ERROR_BAD_HEADER, 1, "header"},
    {"format mismatch xrsc", HS_POSE_FORMAT_XRSC, VID "0 0 1 0 0 0\n", XRSC_ERROR_BAD_HEADER, 1,
     "header"},
    /* pred6dof importer */
    {"pred truncated", HS_POSE_FORMAT_AUTO, PRED "100, 1, 2\n", XRSC_ERROR_TRUNCATED_LINE, 2, "z"},
    {"pred backwards", HS_POSE_FORMAT_AUTO,
     PRED "100, 0, 0, 0, 0, 0, 0, 1, \n99, 0, 0, 0, 0, 0, 0, 1, \n", XRSC_ERROR_TIME_BACKWARDS, 3,
     "timestamp"},
    {"pred bad number", HS_POSE_FORMAT_AUTO, PRED "100, 0, 0, 0, 0, 0, abc, 1, \n",
     XRSC_ERROR_BAD_NUMBER, 2, "qz"},
    {"pred empty field", HS_POSE_FORMAT_AUTO, PRED "100, 0, , 0, 0, 0, 0, 1\n",
     XRSC_ERROR_BAD_NUMBER, 2, "y"},
    {"pred nan", HS_POSE_FORMAT_AUTO, PRED "100, nan, 0, 0, 0, 0, 0, 1, \n", XRSC_ERROR_NAN, 2,
     "x"},
    {"pred extra", HS_POSE_FORMAT_AUTO, PRED "100, 0, 0, 0, 0, 0, 0, 1, 5, \n",
     XRSC_ERROR_UNKNOWN_COLUMN, 2, "field 9"},
    {"pred non-unit", HS_POSE_FORMAT_AUTO,
     PRED "100, 0, 0, 0, 0.5, 0.5, 0.5, 0.5\n200, 0, 0, 0, 0, 0, 0, 0.9\n",
     XRSC_ERROR_QUAT_NOT_UNIT, 3, "qx qy qz qw"},
    {"pred tick overflow", HS_POSE_FORMAT_AUTO,
     PRED "0, 0, 0, 0, 0, 0, 0, 1\n9223372036854775807, 0, 0, 0, 0, 0, 0, 1\n",
     XRSC_ERROR_BAD_NUMBER, 3, "timestamp"},
    /* 360video importer */
    {"360 truncated", HS_POSE_FORMAT_AUTO, VID "0.0 0 1 0 0\n", XRSC_ERROR_TRUNCATED_LINE, 2, "z"},
    {"360 backwards", HS_POSE_FORMAT_AUTO, VID "0.5 0 1 0 0 0\n0.25 0 1 0 0 0\n",
     XRSC_ERROR_TIME_BACKWARDS, 3, "timestamp"},
    {"360 viewpoint", HS_POSE_FORMAT_AUTO, VID "0.5 1.5 1 0 0 0\n", XRSC_ERROR_BAD_NUMBER, 2,
     "viewpoint"},
    {"360 non-unit", HS_POSE_FORMAT_AUTO, VID "0.5 0 1 0 0 0.1\n", XRSC_ERROR_QUAT_NOT_UNIT, 2,
     "w x y z"},
    {"360 inf time", HS_POSE_FORMAT_AUTO, VID "inf 0 1 0 0 0\n", XRSC_ERROR_NAN, 2, "timestamp"},
    {"360 extra", HS_POSE_FORMAT_AUTO, VID "0 0 1 0 0 0 #\n", XRSC_ERROR_UNKNOWN_COLUMN, 2,
     "field 7"},
    {"360 huge span", HS_POSE_FORMAT_AUTO, VID "0 0 1 0 0 0\n1e300 0 1 0 0 0\n",
     XRSC_ERROR_BAD_NUMBER, 3, "timestamp"},
};

static void test_bad_input(void)
{
    for (size_t i = 0; i < sizeof(bad_cases) / sizeof(bad_cases[0]); i++) {
        const bad_case *c = &bad_cases[i];
        hs_pose_stream *s = (hs_pose_stream *)&bad_cases; /* must be reset to NULL */
        xrsc_diag diag;
        memset(&diag, 0, sizeof(diag));
        xrsc_result r = parse_text(c->text, c->format, &s, &diag);
        CHECK_MSG(r == c->code, "%s: got %s, want %s", c->what, xrsc_result_name(r),
                  xrsc_result_name(c->code));
        CHECK_MSG(diag.code == c->code, "%s: diag.code %s", c->what, xrsc_result_name(diag.code));
        CHECK_MSG(diag.line == c->line, "%s: line %d, want %d", c->what, diag.line, c->line);
        CHECK_MSG(strcmp(diag.field, c->field) == 0, "%s: field '%s', want '%s'", c->what,
                  diag.field, c->field);
        CHECK_MSG(strcmp(diag.file, "mem.txt") == 0, "%s: file '%s'", c->what, diag.file);
        CHECK_MSG(s == NULL, "%s: out not NULL on error", c->what);
        /* NULL diag is accepted and gives the same result. */
        CHECK(parse_text(c->text, c->format, &s, NULL) == c->code);
    }
}

static void test_good_edge_cases(void)
{
    hs_pose_stream *s = NULL;
    xrsc_diag diag;
    /* Within the unit tolerance: accepted and renormalised. */
    CHECK_EQ_INT(parse_text(CANON "0 0 0 0 0 0 0 1.0009\n", HS_POSE_FORMAT_AUTO, &s, &diag),
                 XRSC_OK);
    if (s)
        CHECK_NEAR(quat_len(s->samples[0].pose.orientation), 1.0, 1e-7);
    hs_pose_stream_destroy(&s);
    /* Lines of pred6dof ending with ", " and without; blank lines; UTF-8 BOM; CRLF. */
    const char *pred = "\xEF\xBB\xBFtimestamp,x,y,z,qx,qy,qz,qw\r\n"
                       "100, 1, 2, 3, 0, 0, 0, 1, \r\n"
                       "\r\n"
                       "200,1,2,3,0,0,0,1\r\n";
    CHECK_EQ_INT(parse_text(pred, HS_POSE_FORMAT_PRED6DOF, &s, &diag), XRSC_OK);
    if (s) {
        CHECK_EQ_INT(s->count, 2);
        CHECK_EQ_INT(s->samples[1].time_ns, 10000);
        CHECK_NEAR(s->samples[1].pose.position.z, -3, 0);
    }
    hs_pose_stream_destroy(&s);
    /* A canonical stream with equal timestamps keeps the later sample. */
    CHECK_EQ_INT(
        parse_text(CANON "0 0 0 0 0 0 0 1\n0 5 0 0 0 0 0 1\n", HS_POSE_FORMAT_AUTO, &s, &diag),
        XRSC_OK);
    if (s) {
        CHECK_EQ_INT(s->count, 1);
        CHECK_EQ_INT(s->dropped_duplicates, 1);
        CHECK_NEAR(s->samples[0].pose.position.x, 5, 0);
    }
    hs_pose_stream_destroy(&s);
    CHECK(strcmp(hs_pose_format_name(HS_POSE_FORMAT_360VIDEO), "360video") == 0);
}

static void test_files(void)
{
    hs_pose_stream *s = NULL;
    xrsc_diag diag;
    /* Unreadable: missing file, a directory. */
    CHECK_EQ_INT(
        hs_pose_stream_load("/nonexistent/xrsc/none.xrpose", HS_POSE_FORMAT_AUTO, &s, &diag),
        XRSC_ERROR_IO);
    CHECK(strcmp(diag.file, "/nonexistent/xrsc/none.xrpose") == 0);
    CHECK_EQ_INT(hs_pose_stream_load(t_source_path("poses"), HS_POSE_FORMAT_AUTO, &s, &diag),
                 XRSC_ERROR_IO);
    /* Empty file on disk. */
    const char *empty = t_temp_file("empty.xrpose", "");
    CHECK_EQ_INT(hs_pose_stream_load(empty, HS_POSE_FORMAT_AUTO, &s, &diag), XRSC_ERROR_EMPTY_FILE);
    /* Over the limit: a sparse file, rejected by its size before anything is read. */
    const char *big = t_temp_file("big.xrpose", "xrsc-poses 1\n");
    CHECK_EQ_INT(truncate(big, (off_t)HS_POSE_MAX_FILE_BYTES + 1), 0);
    CHECK_EQ_INT(hs_pose_stream_load(big, HS_POSE_FORMAT_AUTO, &s, &diag),
                 XRSC_ERROR_FILE_TOO_LARGE);
    CHECK(strcmp(diag.file, big) == 0);
    CHECK(s == NULL);
    unlink(big);
    unlink(empty);
    /* Saving to an impossible path. */
    hs_pose_stream one = {0};
    CHECK_EQ_INT(hs_pose_stream_save(&one, "/nonexistent/xrsc/out.xrpose", &diag), XRSC_ERROR_IO);
    CHECK_EQ_INT(hs_pose_stream_parse("x", NULL, 0, HS_POSE_FORMAT_AUTO, NULL, &diag),
                 XRSC_ERROR_INVALID_ARGUMENT);
}

/** Peak resident memory of this process so far, in KiB (getrusage). */
static long peak_rss_kib(void)
{
    struct rusage ru;
    return getrusage(RUSAGE_SELF, &ru) == 0 ? ru.ru_maxrss : 0;
}

/* Issue 23: a large file is read line by line and its header first: a 256 MiB file whose first
 * line is no header is refused at line 1 without being read into memory (the peak resident
 * size grows by far less than the file); --max-pose-bytes refuses a file over its limit. */
#define HEADER_FIRST_FILE_BYTES (256ll << 20)
#define HEADER_FIRST_MAX_GROWTH_KIB (32l << 10)
static void test_header_first_streaming(void)
{
    const char *big = t_temp_file("bad_header.xrpose", "not a pose stream\n");
    CHECK_EQ_INT(truncate(big, (off_t)HEADER_FIRST_FILE_BYTES), 0);
    hs_pose_stream *s = NULL;
    xrsc_diag diag = {0};
    long before = peak_rss_kib();
    CHECK_EQ_INT(hs_pose_stream_load(big, HS_POSE_FORMAT_AUTO, &s, &diag), XRSC_ERROR_BAD_HEADER);
    CHECK_EQ_INT(diag.line, 1);
    CHECK_EQ_INT(hs_pose_stream_load(big, HS_POSE_FORMAT_PRED6DOF, &s, &diag),
                 XRSC_ERROR_BAD_HEADER);
    CHECK_EQ_INT(diag.line, 1);
    long grown = peak_rss_kib() - before;
    CHECK_MSG(grown < HEADER_FIRST_MAX_GROWTH_KIB, "reading grew the process by %ld KiB", grown);
    unlink(big);
    /* The limit of hs_pose_stream_load_with (xrsc --max-pose-bytes). */
    const char *orbit = t_source_path("poses/orbit_cornell.xrpose");
    hs_pose_load_options lo = {.max_bytes = 1000};
    CHECK_EQ_INT(hs_pose_stream_load_with(orbit, &lo, &s, &diag), XRSC_ERROR_FILE_TOO_LARGE);
    CHECK(s == NULL);
    lo.max_bytes = 0; /* the default */
    CHECK_EQ_INT(hs_pose_stream_load_with(orbit, &lo, &s, &diag), XRSC_OK);
    CHECK(s && s->count == 180);
    hs_pose_stream_destroy(&s);
}

int main(void)
{
    RUN(test_round_trip);
    RUN(test_import_pred6dof);
    RUN(test_import_360video);
    RUN(test_lookup);
    RUN(test_lookup_binary_search);
    RUN(test_duplicates);
    RUN(test_anchor);
    RUN(test_bundled_orbit);
    RUN(test_bad_input);
    RUN(test_good_edge_cases);
    RUN(test_files);
    RUN(test_header_first_streaming);
    return t_finish();
}
