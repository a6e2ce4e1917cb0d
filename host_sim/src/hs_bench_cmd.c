// SPDX-License-Identifier: MIT
/**
 * @file hs_bench_cmd.c
 * @brief The `xrsc bench` command line (hs_bench.h).
 */
#include "hs_bench.h"

#include "hs_anim_args.h"
#include "hs_args.h"
#include "u_diag.h"

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

/* clang-format off */
static void usage(FILE *f)
{
    fprintf(f,
"usage: xrsc bench [options]\n"
"\n"
"Speed vs. accuracy: renders every setting (a method and its options) over the same frames of\n"
"one scene and pose stream (same views and seeds), scores every K-th frame after the warm-up\n"
"against a converged `spp` reference of that frame's views (cached in OUT/ref/), writes one\n"
"CSV row per frame and setting, prints a summary with ratios to a baseline setting and draws\n"
"charts with gnuplot. Rerunning with the same options skips complete settings and cached\n"
"references (restartable).\n"
"\n"
"Input:\n"
"  --scene PATH        glTF scene                               [scenes/cornell.gltf]\n"
"  --poses PATH        pose stream; a relative path not found is also looked up in\n"
"                      $XRSC_SHARED_DIR and ../shared (e.g. poses/pred6dof-hololens/1.csv)\n"
"                                                               [poses/orbit_cornell.xrpose]\n"
"  --pose-format F     auto | xrsc | pred6dof | 360video | librnr   [auto]\n"
"  --anchor A          start: the head pose at --start is placed at the scene's viewpoint;\n"
"                      first: the stream's first pose (as xrsc replay); none   [start]\n"
"  --start S           start S seconds into the stream          [0]\n"
"  --frames N          frames per setting (0 = until the stream ends) [%d]\n"
"  --warmup N          first N frames left out of the means (caches fill) [%d]\n"
"  --score-every K     score frames warmup, warmup+K, ...        [%d]\n"
"\n"
"Rendering:\n"
"  --settings LIST     settings separated by ';' (or @FILE, one per line, '#' comments):\n"
"                      METHOD[:KEY=VALUE,...]   [spp 1, 4; samplecache single/multi/\n"
"                      adaptive x 1pass/2pass; samplecache + moments R = 0, R = 1, pfj23]\n"
"  --baseline NAME     setting the ratios are to     [the first samplecache trace=single]\n"
"  --resolution WxH    per eye                                  [%dx%d]\n"
"  --ref-spp N         samples per pixel of the references      [%d]\n"
"  --ref-floor         also render a second reference of the first scored frame with\n"
"                      another seed; prints the relMSE between the two (the noise floor)\n"
"  --seed N            random seed of every setting             [0]\n"
"  --env R,G,B         constant environment radiance\n"
HS_ANIM_USAGE
"  --blas-update M     skinned/morphed meshes' BLAS each frame: auto | refit | rebuild [auto]\n"
"  --ipd MM            interpupillary distance                  [63]\n"
"  --refresh HZ        display refresh rate (frame spacing)     [90]\n"
"  --device D          cpu | gpu | index | name part\n"
"  --validation        enable the Vulkan validation layer, synchronization checks included\n"
"\n"
"Suites:\n"
"  --suite stability   the issue-9 failure cases for every method (xrsc bench --suite\n"
"                      stability --help; bench/README.md)\n"
"  --part P            one part of the run, for runs split over processes (xrsc sweep):\n"
"                      ref:K (frame K's reference), run (the settings, no report) or\n"
"                      report (no rendering: the report of complete settings, or an error\n"
"                      naming those not complete); parts never empty OUT/ref   [all]\n"
"\n"
"Output:\n"
"  --out DIR           output folder                            [out/bench]\n"
"  --fresh             ignore results and references already in DIR\n"
"  --no-plots          write the gnuplot scripts, do not run gnuplot\n"
"  --timing-only       times, rays and counters only: no references, read-backs or image\n"
"                      metrics (their columns stay empty; for large sizes on a GPU)\n"
"  --quiet             no progress\n"
"  -h, --help          this help\n"
"\n"
"Setting keys:\n",
            DEFAULT_FRAMES, DEFAULT_WARMUP, DEFAULT_SCORE_EVERY, DEFAULT_SIZE, DEFAULT_SIZE,
            DEFAULT_REF_SPP);
    hs_bench_print_keys(f);
    fprintf(f,
"\n"
"Example: xrsc bench --settings \"spp:spp=1;samplecache:trace=single\" --frames 30\n"
"Files: OUT/bench.csv (all rows), OUT/summary.csv, OUT/frames/NAME.csv, OUT/*.png and *.gp\n");
}
/* clang-format on */

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

static const char *const value_options[] = {
    "--scene", "--poses", "--pose-format", "--anchor", "--start", "--frames",
    "--warmup", "--score-every", "--settings", "--baseline", "--resolution", "--ref-spp",
    "--seed", "--env", HS_ANIM_FLAG, "--blas-update", "--ipd", "--refresh", "--device", "--out", "--part",
};

/* What the command line sets: the bench options, the settings' text, --warmup given. */
typedef struct bench_args {
    hs_bench_options opt;
    const char *settings_text;
    char *settings_file; /* --settings @FILE: its text (owned) */
    bool warmup_given;
    hs_args args; /* --opt=value: argv points into it */
} bench_args;

/* Options without a value. */
static int parse_flag(const char *a, bench_args *ba)
{
    hs_bench_options *opt = &ba->opt;
    if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
        usage(stdout);
        return 0;
    }
    if (!strcmp(a, "--fresh"))
        opt->fresh = true;
    else if (!strcmp(a, "--ref-floor"))
        opt->ref_floor = true;
    else if (!strcmp(a, "--no-plots"))
        opt->no_plots = true;
    else if (!strcmp(a, "--timing-only"))
        opt->timing_only = true;
    else if (!strcmp(a, "--quiet"))
        opt->progress = false;
    else if (!strcmp(a, "--validation"))
        opt->context.validation = true;
    else
        return HS_ARG_NOT_MINE;
    return HS_ARG_NEXT;
}

/* --part ref:K | run | report | all */
static int parse_part(const char *a, const char *v, hs_bench_options *opt)
{
    if (!strncmp(v, "ref:", 4) && hs_parse_u32(v + 4, &opt->part_frame))
        opt->part = HS_BENCH_PART_REF;
    else if (!strcmp(v, "run"))
        opt->part = HS_BENCH_PART_RUN;
    else if (!strcmp(v, "report"))
        opt->part = HS_BENCH_PART_REPORT;
    else if (!strcmp(v, "all"))
        opt->part = HS_BENCH_PART_ALL;
    else
        return bad_arg(a, v, "expected ref:FRAME, run, report or all");
    return HS_ARG_NEXT;
}

/* What is run: scene, poses, frames and scoring, the settings and the baseline. */
static int parse_run_option(const char *a, const char *v, bench_args *ba)
{
    hs_bench_options *opt = &ba->opt;
    double d;
    if (!strcmp(a, "--scene")) {
        opt->scene_path = v;
    } else if (!strcmp(a, "--poses")) {
        opt->poses_path = v;
    } else if (!strcmp(a, "--pose-format")) {
        if (!hs_pose_format_from_name(v, &opt->pose_format))
            return bad_arg(a, v, "expected auto, xrsc, pred6dof, 360video or librnr");
    } else if (!strcmp(a, "--anchor")) {
        if (!strcmp(v, "start"))
            opt->anchor = HS_BENCH_ANCHOR_START;
        else if (!strcmp(v, "first"))
            opt->anchor = HS_BENCH_ANCHOR_FIRST;
        else if (!strcmp(v, "none"))
            opt->anchor = HS_BENCH_ANCHOR_NONE;
        else
            return bad_arg(a, v, "expected start, first or none");
    } else if (!strcmp(a, "--start")) {
        if (!hs_parse_f(v, &d) || d < 0)
            return bad_arg(a, v, "expected seconds >= 0");
        opt->start_s = d;
    } else if (!strcmp(a, "--frames")) {
        if (!hs_parse_u32(v, &opt->frames) || opt->frames > 1000000)
            return bad_arg(a, v, "expected 0..1000000");
    } else if (!strcmp(a, "--warmup")) {
        if (!hs_parse_u32(v, &opt->warmup))
            return bad_arg(a, v, "expected a count");
        ba->warmup_given = true;
    } else if (!strcmp(a, "--score-every")) {
        if (!hs_parse_u32(v, &opt->score_every) || opt->score_every == 0)
            return bad_arg(a, v, "expected a count >= 1");
    } else if (!strcmp(a, "--settings")) {
        ba->settings_text = v;
        if (v[0] == '@') {
            free(ba->settings_file);
            ba->settings_text = ba->settings_file = read_text_file(v + 1);
            if (!ba->settings_file)
                return bad_arg(a, v, "cannot read the file");
        }
    } else if (!strcmp(a, "--baseline")) {
        opt->baseline = v;
    } else if (!strcmp(a, "--part")) {
        return parse_part(a, v, opt);
    } else {
        return HS_ARG_NOT_MINE;
    }
    return HS_ARG_NEXT;
}

/* How it is rendered and written: size, references, seed, environment, headset, device, out. */
static int parse_render_option(const char *a, const char *v, bench_args *ba)
{
    hs_bench_options *opt = &ba->opt;
    uint32_t u;
    double d;
    if (!strcmp(a, "--resolution")) {
        unsigned w, h;
        if (!hs_parse_size(v, 16, 8192, &w, &h))
            return bad_arg(a, v, "expected WxH, each 16..8192");
        opt->width = w;
        opt->height = h;
    } else if (!strcmp(a, "--ref-spp")) {
        if (!hs_parse_u32(v, &u) || u == 0 || u > 1u << 20)
            return bad_arg(a, v, "expected 1..1048576");
        opt->ref_spp = u;
    } else if (!strcmp(a, "--seed")) {
        if (!hs_parse_u32(v, &opt->seed))
            return bad_arg(a, v, "expected an unsigned integer");
    } else if (!strcmp(a, "--env")) {
        if (!hs_parse_rgb(v, opt->scene.environment))
            return bad_arg(a, v, "expected R,G,B >= 0");
        opt->scene.env_set = true;
    } else if (!strcmp(a, HS_ANIM_FLAG)) {
        int r = hs_anim_parse("xrsc bench", a, v, &opt->scene);
        if (r)
            return r;
    } else if (!strcmp(a, "--blas-update")) {
        static const char *const modes[] = {"auto", "refit", "rebuild"};
        uint32_t m = 0;
        while (m < 3 && strcmp(v, modes[m]))
            m++;
        if (m == 3)
            return bad_arg(a, v, "expected auto, refit or rebuild");
        opt->scene.blas_update = (xrsc_blas_update)m;
    } else if (!strcmp(a, "--ipd")) {
        if (!hs_parse_f(v, &d) || d < 0 || d > 200)
            return bad_arg(a, v, "expected millimetres 0..200");
        opt->headset.ipd_m = (float)(d * 1e-3);
    } else if (!strcmp(a, "--refresh")) {
        if (!hs_parse_f(v, &d) || d < 1 || d > 1000)
            return bad_arg(a, v, "expected 1..1000 Hz");
        opt->headset.refresh_hz = (float)d;
    } else if (!strcmp(a, "--device")) {
        opt->context.device = v;
    } else if (!strcmp(a, "--out")) {
        if (!v[0])
            return bad_arg(a, v, "empty folder name");
        opt->out_dir = v;
    } else {
        return HS_ARG_NOT_MINE;
    }
    return HS_ARG_NEXT;
}

/* Reads argv[1..argc) into ba: HS_ARG_NEXT when all of it was read, else the exit status. */
static int parse_args(int argc, char **argv, bench_args *ba)
{
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        int r = parse_flag(a, ba);
        if (r == HS_ARG_NEXT)
            continue;
        if (r != HS_ARG_NOT_MINE)
            return r;
        if (!hs_arg_in(a, value_options, sizeof(value_options) / sizeof(value_options[0])))
            return bad_arg(a, NULL, a[0] == '-' ? "unknown option" : "unexpected argument");
        if (i + 1 >= argc)
            return bad_arg(a, NULL, "needs a value");
        const char *v = argv[++i];
        r = parse_run_option(a, v, ba);
        if (r == HS_ARG_NOT_MINE)
            r = parse_render_option(a, v, ba);
        if (r != HS_ARG_NEXT && r != HS_ARG_NOT_MINE)
            return r;
    }
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
    int r = hs_args_normalize(&c->ba.args, "xrsc bench", value_options,
                              sizeof(value_options) / sizeof(value_options[0]), &argc, &argv);
    if (r == 0)
        r = parse_args(argc, argv, &c->ba);
    if (r == HS_ARG_NEXT)
        r = finish_bench(&c->ba, c->settings, c->scene_buf, c->poses_buf, sizeof(c->scene_buf));
    if (r != HS_ARG_NEXT) { /* an error, or 0 after --help */
        hs_bench_cmdline_free(c);
        return r;
    }
    *out = c;
    return 0;
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
