// SPDX-License-Identifier: MIT
/**
 * @file hs_bench_cmd.c
 * @brief The `xrsc bench` command line (hs_bench.h).
 */
#include "hs_bench.h"

#include "hs_anim_args.h"
#include "hs_args.h"
#include "hs_opt.h"
#include "u_diag.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#ifndef XRSC_SOURCE_DIR
#define XRSC_SOURCE_DIR "."
#endif

#define DEFAULT_SCENE XRSC_SOURCE_DIR "/scenes/cornell.gltf"
#define DEFAULT_POSES XRSC_SOURCE_DIR "/poses/orbit_cornell.xrpose"
#define DEFAULT_OUT "out/bench"
#define DEFAULT_FRAMES 60
#define DEFAULT_WARMUP 10
#define DEFAULT_SCORE_EVERY 5
#define DEFAULT_SIZE 128
#define DEFAULT_REF_SPP 256
#define SETTINGS_FILE_MAX (64 * 1024)

static int bad_arg(const char *flag, const char *value, const char *why)
{
    return hs_bad_arg("xrsc bench", flag, value, why);
}

/* A relative path that does not exist is looked up under the shared folder. */
static const char *resolve(const char *path, char *buf, size_t cap)
{
    if (path[0] == '/' || access(path, R_OK) == 0)
        return path;
    const char *env = getenv("XRSC_SHARED_DIR");
    const char *bases[] = {env, XRSC_SOURCE_DIR "/../shared", XRSC_SOURCE_DIR};
    for (size_t k = 0; k < sizeof(bases) / sizeof(bases[0]); k++) {
        if (!bases[k] || !bases[k][0])
            continue;
        snprintf(buf, cap, "%s/%s", bases[k], path);
        if (access(buf, R_OK) == 0)
            return buf;
    }
    return path;
}

static char *read_text_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    char *buf = malloc(SETTINGS_FILE_MAX + 1);
    size_t n = buf ? fread(buf, 1, SETTINGS_FILE_MAX, f) : 0;
    fclose(f);
    if (buf)
        buf[n] = '\0';
    return buf;
}

/* What the command line sets: the bench options, the settings' text, --warmup given. */
typedef struct bench_args {
    hs_bench_options opt;
    const char *settings_text;
    char *settings_file; /* --settings @FILE: its text (owned) */
    bool warmup_given;
} bench_args;

#define B(a) ((bench_args *)(a)->target)

static int parse_pose_format(const hs_opt_arg *a)
{
    if (!hs_pose_format_from_name(a->value, &B(a)->opt.pose_format))
        return bad_arg(a->opt->name, a->value, "expected auto, xrsc, pred6dof, 360video or librnr");
    return 0;
}

static int parse_warmup(const hs_opt_arg *a)
{
    if (!hs_parse_u32(a->value, &B(a)->opt.warmup))
        return bad_arg(a->opt->name, a->value, "expected a count");
    B(a)->warmup_given = true;
    return 0;
}

static int parse_settings(const hs_opt_arg *a)
{
    bench_args *ba = B(a);
    ba->settings_text = a->value;
    if (a->value[0] == '@') {
        free(ba->settings_file);
        ba->settings_text = ba->settings_file = read_text_file(a->value + 1);
        if (!ba->settings_file)
            return bad_arg(a->opt->name, a->value, "cannot read the file");
    }
    return 0;
}

static int parse_resolution(const hs_opt_arg *a)
{
    unsigned w, h;
    if (!hs_parse_size(a->value, 16, 8192, &w, &h))
        return bad_arg(a->opt->name, a->value, "expected WxH, each 16..8192");
    B(a)->opt.width = w;
    B(a)->opt.height = h;
    return 0;
}

static int parse_env(const hs_opt_arg *a)
{
    if (!hs_parse_rgb(a->value, B(a)->opt.scene.environment))
        return bad_arg(a->opt->name, a->value, "expected R,G,B >= 0");
    B(a)->opt.scene.env_set = true;
    return 0;
}

static int parse_ipd(const hs_opt_arg *a)
{
    double d;
    if (!hs_parse_f(a->value, &d) || d < 0 || d > 200)
        return bad_arg(a->opt->name, a->value, "expected millimetres 0..200");
    B(a)->opt.headset.ipd_m = (float)(d * 1e-3);
    return 0;
}

static int parse_out(const hs_opt_arg *a)
{
    if (!a->value[0])
        return bad_arg(a->opt->name, a->value, "empty folder name");
    B(a)->opt.out_dir = a->value;
    return 0;
}

static int parse_animation(const hs_opt_arg *a)
{
    return hs_anim_parse("xrsc bench", HS_ANIM_FLAG, a->value, &B(a)->opt.scene);
}

/* --part ref:K | run | report | all */
static int parse_part(const hs_opt_arg *a)
{
    hs_bench_options *opt = &B(a)->opt;
    const char *v = a->value;
    if (!strncmp(v, "ref:", 4) && hs_parse_u32(v + 4, &opt->part_frame))
        opt->part = HS_BENCH_PART_REF;
    else if (!strcmp(v, "run"))
        opt->part = HS_BENCH_PART_RUN;
    else if (!strcmp(v, "report"))
        opt->part = HS_BENCH_PART_REPORT;
    else if (!strcmp(v, "all"))
        opt->part = HS_BENCH_PART_ALL;
    else
        return bad_arg(a->opt->name, v, "expected ref:FRAME, run, report or all");
    return 0;
}

/* The enum it sets is int-sized (hs_opt_enum writes an int). */
_Static_assert(sizeof(xrsc_blas_update) == sizeof(int), "enum field set through int");
static const hs_opt_name k_blas_updates[] = {
    {"auto", XRSC_BLAS_UPDATE_AUTO, "expected auto, refit or rebuild"},
    {"refit", XRSC_BLAS_UPDATE_REFIT, NULL},
    {"rebuild", XRSC_BLAS_UPDATE_REBUILD, NULL},
    {NULL, 0, NULL}};

static int parse_quiet(const hs_opt_arg *a)
{
    B(a)->opt.progress = false;
    return 0;
}

#define STR_(x) #x
#define STR(x) STR_(x)
#define F(field) offsetof(bench_args, opt.field)
#define NUM(lo, hi, why) (&(const hs_opt_num){lo, hi, why})
#define TEXT(s) {NULL, NULL, s, NULL, 0, NULL}

/* hs_opt_enum writes an int: the enum it sets is int-sized. */
_Static_assert(sizeof(hs_bench_anchor) == sizeof(int), "enum field set through int");
static const hs_opt_name k_anchors[] = {{"start", HS_BENCH_ANCHOR_START, "expected start, first or none"},
                                        {"first", HS_BENCH_ANCHOR_FIRST, NULL},
                                        {"none", HS_BENCH_ANCHOR_NONE, NULL},
                                        {NULL, 0, NULL}};

/* Every option of `xrsc bench` once, in --help's order (the setting keys follow, usage()). */
static const hs_opt k_bench_opts[] = {
    TEXT("usage: xrsc bench [options]\n"
         "\n"
         "Speed vs. accuracy: renders every setting (a method and its options) over the same frames of\n"
         "one scene and pose stream (same views and seeds), scores every K-th frame after the warm-up\n"
         "against a converged `spp` reference of that frame's views (cached in OUT/ref/), writes one\n"
         "CSV row per frame and setting, prints a summary with ratios to a baseline setting and draws\n"
         "charts with gnuplot. Rerunning with the same options skips complete settings and cached\n"
         "references (restartable).\n"
         "\n"
         "Input:\n"),
    {"--scene", "PATH", "glTF scene                               [scenes/cornell.gltf]", NULL,
     F(scene_path), NULL},
    {"--poses", "PATH",
     "pose stream; a relative path not found is also looked up in\n"
     "$XRSC_SHARED_DIR and ../shared (e.g. poses/pred6dof-hololens/1.csv)\n"
     "                                         [poses/orbit_cornell.xrpose]",
     NULL, F(poses_path), NULL},
    {"--pose-format", "F", "auto | xrsc | pred6dof | 360video | librnr   [auto]",
     parse_pose_format, 0, NULL},
    {"--anchor", "A",
     "start: the head pose at --start is placed at the scene's viewpoint;\n"
     "first: the stream's first pose (as xrsc replay); none   [start]",
     hs_opt_enum, F(anchor), k_anchors},
    {"--start", "S", "start S seconds into the stream          [0]", hs_opt_double, F(start_s),
     NUM(0, INFINITY, "expected seconds >= 0")},
    {"--frames", "N", "frames per setting (0 = until the stream ends) [" STR(DEFAULT_FRAMES) "]",
     hs_opt_u32, F(frames), NUM(0, 1000000, "expected 0..1000000")},
    {"--warmup", "N", "first N frames left out of the means (caches fill) [" STR(DEFAULT_WARMUP) "]",
     parse_warmup, 0, NULL},
    {"--score-every", "K", "score frames warmup, warmup+K, ...        [" STR(DEFAULT_SCORE_EVERY) "]",
     hs_opt_u32, F(score_every), NUM(1, UINT32_MAX, "expected a count >= 1")},
    TEXT("\nRendering:\n"),
    {"--settings", "LIST",
     "settings separated by ';' (or @FILE, one per line, '#' comments):\n"
     "METHOD[:KEY=VALUE,...]   [spp 1, 4; samplecache single/multi/\n"
     "adaptive x 1pass/2pass; samplecache + moments R = 0, R = 1, pfj23]",
     parse_settings, 0, NULL},
    {"--baseline", "NAME", "setting the ratios are to     [the first samplecache trace=single]",
     NULL, F(baseline), NULL},
    {"--resolution", "WxH",
     "per eye                                  [" STR(DEFAULT_SIZE) "x" STR(DEFAULT_SIZE) "]",
     parse_resolution, 0, NULL},
    {"--ref-spp", "N", "samples per pixel of the references      [" STR(DEFAULT_REF_SPP) "]",
     hs_opt_u32, F(ref_spp), NUM(1, 1u << 20, "expected 1..1048576")},
    {"--ref-floor", NULL,
     "also render a second reference of the first scored frame with\n"
     "another seed; prints the relMSE between the two (the noise floor)",
     NULL, F(ref_floor), NULL},
    {"--seed", "N", "random seed of every setting             [0]", hs_opt_u32, F(seed),
     NUM(0, UINT32_MAX, "expected an unsigned integer")},
    {"--env", "R,G,B", "constant environment radiance", parse_env, 0, NULL},
    {HS_ANIM_FLAG, "A",
     "the clip that plays, looping at the display time: first (the file's\n"
     "first clip) | all (every clip at once) | none | a clip's name or\n"
     "index (xrsc scene info FILE lists them) [first]",
     parse_animation, 0, NULL},
    {"--blas-update", "M", "skinned/morphed meshes' BLAS each frame: auto | refit | rebuild [auto]",
     hs_opt_enum, F(scene.blas_update), k_blas_updates},
    {"--ipd", "MM", "interpupillary distance                  [63]", parse_ipd, 0, NULL},
    {"--refresh", "HZ", "display refresh rate (frame spacing)     [90]", hs_opt_float,
     F(headset.refresh_hz), NUM(1, 1000, "expected 1..1000 Hz")},
    {"--device", "D", "cpu | gpu | index | name part", NULL, F(context.device), NULL},
    {"--validation", NULL, "enable the Vulkan validation layer, synchronization checks included",
     NULL, F(context.validation), NULL},
    TEXT("\nSuites:\n"
         "  --suite stability   the issue-9 failure cases for every method (xrsc bench --suite\n"
         "                      stability --help; bench/README.md)\n"),
    {"--part", "P",
     "one part of the run, for runs split over processes (xrsc sweep):\n"
     "ref:K (frame K's reference), run (the settings, no report) or\n"
     "report (no rendering: the report of complete settings, or an error\n"
     "naming those not complete); parts never empty OUT/ref   [all]",
     parse_part, 0, NULL},
    TEXT("\nOutput:\n"),
    {"--out", "DIR", "output folder                            [" DEFAULT_OUT "]", parse_out, 0,
     NULL},
    {"--fresh", NULL, "ignore results and references already in DIR", NULL, F(fresh), NULL},
    {"--no-plots", NULL, "write the gnuplot scripts, do not run gnuplot", NULL, F(no_plots), NULL},
    {"--timing-only", NULL,
     "times, rays and counters only: no references, read-backs or image\n"
     "metrics (their columns stay empty; for large sizes on a GPU)",
     NULL, F(timing_only), NULL},
    {"--keep-frames", NULL,
     "also write each scored frame as DIR/frames/NAME/frame_K_EYE.pfm\n"
     "(beside DIR/ref/'s references, for error maps)",
     NULL, F(keep_frames), NULL},
    {"--quiet", NULL, "no progress", parse_quiet, 0, NULL},
    TEXT("  -h, --help          this help\n"
         "\n"
         "Setting keys:\n"),
};
#define BENCH_OPT_COUNT (sizeof(k_bench_opts) / sizeof(k_bench_opts[0]))

static void usage(FILE *f)
{
    hs_opt_print_help(f, k_bench_opts, BENCH_OPT_COUNT);
    hs_bench_print_keys(f);
    fprintf(f,
            "\n"
            "Example: xrsc bench --settings \"spp:spp=1;samplecache:trace=single\" --frames 30\n"
            "Files: OUT/bench.csv (all rows), OUT/summary.csv, OUT/frames/NAME.csv, OUT/*.png and "
            "*.gp\n");
}

/* Reads argv[1..argc) into ba: HS_ARG_NEXT when all of it was read, else the exit status. */
static int parse_args(int argc, char **argv, bench_args *ba)
{
    int r = hs_opt_parse("xrsc bench", k_bench_opts, BENCH_OPT_COUNT, argc, argv, 1, ba);
    if (r == HS_OPT_HELP) {
        usage(stdout);
        return 0;
    }
    if (r != HS_ARG_NEXT)
        return r;
    if (ba->opt.frames && ba->opt.warmup >= ba->opt.frames) {
        if (ba->warmup_given)
            return bad_arg("--warmup", NULL, "must be less than --frames");
        ba->opt.warmup = ba->opt.frames / 2; /* short runs keep half of their frames */
    }
    return HS_ARG_NEXT;
}

/* Parses the settings and resolves the input paths: HS_ARG_NEXT, else the exit status. */
static int finish_bench(bench_args *ba, hs_bench_setting *settings, char *scene_buf,
                        char *poses_buf, size_t cap)
{
    hs_bench_options *opt = &ba->opt;
    xrsc_diag diag = {0};
    char msg[1400];
    if (hs_bench_parse_settings(ba->settings_text, settings, HS_BENCH_MAX_SETTINGS,
                                &opt->setting_count, &diag) != XRSC_OK) {
        fprintf(stderr, "xrsc bench: error: %s\n", xrsc_diag_format(&diag, msg, sizeof(msg)));
        return HS_EXIT_BAD_ARGS;
    }
    opt->settings = settings;
    opt->scene_path = resolve(opt->scene_path, scene_buf, cap);
    opt->poses_path = resolve(opt->poses_path, poses_buf, cap);
    return HS_ARG_NEXT;
}

/* The defaults of `xrsc bench`, before its command line. */
static void bench_defaults(bench_args *ba)
{
    *ba = (bench_args){
        .opt = {.scene_path = DEFAULT_SCENE,
                .poses_path = DEFAULT_POSES,
                .out_dir = DEFAULT_OUT,
                .frames = DEFAULT_FRAMES,
                .warmup = DEFAULT_WARMUP,
                .score_every = DEFAULT_SCORE_EVERY,
                .width = DEFAULT_SIZE,
                .height = DEFAULT_SIZE,
                .ref_spp = DEFAULT_REF_SPP,
                .progress = true,
                .anchor = HS_BENCH_ANCHOR_START},
        .settings_text = HS_BENCH_DEFAULT_SETTINGS,
    };
    xrsc_headset_default(&ba->opt.headset);
}

struct hs_bench_cmdline {
    bench_args ba;
    hs_bench_setting settings[HS_BENCH_MAX_SETTINGS];
    char scene_buf[4096], poses_buf[4096];
};

int hs_bench_cmdline_parse(int argc, char **argv, hs_bench_cmdline **out)
{
    *out = NULL;
    hs_bench_cmdline *c = calloc(1, sizeof(*c));
    if (!c) {
        fprintf(stderr, "xrsc bench: error: out of memory\n");
        return 1;
    }
    bench_defaults(&c->ba);
    int r = parse_args(argc, argv, &c->ba);
    if (r == HS_ARG_NEXT)
        r = finish_bench(&c->ba, c->settings, c->scene_buf, c->poses_buf, sizeof(c->scene_buf));
    if (r != HS_ARG_NEXT) { /* an error, or 0 after --help */
        hs_bench_cmdline_free(c);
        return r;
    }
    *out = c;
    return 0;
}

const hs_opt *hs_bench_cmdline_table(size_t *out_count)
{
    *out_count = BENCH_OPT_COUNT;
    return k_bench_opts;
}

hs_bench_options *hs_bench_cmdline_options(hs_bench_cmdline *c)
{
    return &c->ba.opt;
}

void hs_bench_cmdline_free(hs_bench_cmdline *c)
{
    if (c)
        free(c->ba.settings_file);
    free(c);
}

int hs_bench_main(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (!strcmp(argv[i], "--suite") || !strncmp(argv[i], "--suite=", 8))
            return hs_bench_suite_main(argc, argv);
    hs_bench_cmdline *c = NULL;
    int r = hs_bench_cmdline_parse(argc, argv, &c);
    if (r || !c) /* an error, or --help */
        return r;
    xrsc_diag diag = {0};
    char msg[1400];
    if (hs_bench_run(&c->ba.opt, stdout, &diag) != XRSC_OK) {
        fprintf(stderr, "xrsc bench: error: %s\n", xrsc_diag_format(&diag, msg, sizeof(msg)));
        r = 1;
    }
    hs_bench_cmdline_free(c);
    return r;
}
