// SPDX-License-Identifier: MIT
/**
 * @file hs_scene_cmd.c
 * @brief `xrsc scene info [--json] [--animation A] FILE` (hs_scene_cmd.h): the file read by
 *        xrsc_file_inspect (CPU only, no Vulkan device), printed as text or JSON.
 */
#include "hs_scene_cmd.h"

#include "hs_args.h"
#include "hs_opt.h"
#include "xrsc/xrsc.h"

#include "u_diag.h"

#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SCENE_CMD "xrsc scene"

/* What `xrsc scene info` reads: the file, --json, --animation. */
typedef struct scene_args {
    const char *path;
    bool json;
    xrsc_scene_options so;
} scene_args;

static int parse_path(const hs_opt_arg *a)
{
    scene_args *sa = a->target;
    if (sa->path)
        return hs_bad_arg(a->cmd, a->value, NULL, "expected one FILE");
    sa->path = a->value;
    return 0;
}

static int parse_animation(const hs_opt_arg *a)
{
    if (!a->value[0])
        return hs_bad_arg(a->cmd, a->opt->name, a->value,
                          "expected first, all, none, a clip's name or index");
    ((scene_args *)a->target)->so.animation = a->value;
    return 0;
}

#define TEXT(s) {NULL, NULL, s, NULL, 0, NULL}
static const hs_opt k_scene_opts[] = {
    TEXT("usage: xrsc scene info [options] FILE\n"
         "\n"
         "Reads a glTF 2.0 file (.gltf/.glb) on the CPU, without a Vulkan device, and\n"
         "prints what it holds: triangles (as drawn, over all instances), instances,\n"
         "materials, textures, images, lights, cameras, nodes, meshes, skins, morph\n"
         "targets, extensions used and required, the bounds, and its animation clips with\n"
         "their durations and channel counts, marking the clip that plays (the first one\n"
         "unless --animation says otherwise).\n"
         "\n"),
    {NULL, NULL, NULL, parse_path, 0, NULL},
    {"--json", NULL, "one JSON object instead of text", NULL, offsetof(scene_args, json), NULL},
    {"--animation", "A",
     "first | all | none | a clip's name or index: the clip a replay\n"
     "with this option plays (an unknown one is an error)  [first]",
     parse_animation, 0, NULL},
    TEXT("  -h, --help          this help\n"),
};
#define SCENE_OPT_COUNT (sizeof(k_scene_opts) / sizeof(k_scene_opts[0]))

static void usage(FILE *f)
{
    hs_opt_print_help(f, k_scene_opts, SCENE_OPT_COUNT);
}

/** s as a JSON string (quotes, backslashes and control characters escaped). */
static void json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        if (*p == '"' || *p == '\\')
            fprintf(f, "\\%c", *p);
        else if (*p < 0x20)
            fprintf(f, "\\u%04x", *p);
        else
            fputc(*p, f);
    }
    fputc('"', f);
}

/** The clip that plays: its index, "none" or "all". */
static const char *playing_text(const xrsc_file_info *fi, char *buf, size_t cap)
{
    int32_t p = fi->scene.clip_playing;
    if (p == XRSC_CLIP_NONE)
        snprintf(buf, cap, "none");
    else if (p == XRSC_CLIP_ALL)
        snprintf(buf, cap, "all");
    else
        snprintf(buf, cap, "%d", p);
    return buf;
}

static void print_text(const char *path, const xrsc_file_info *fi)
{
    const xrsc_scene_info *si = &fi->scene;
    char play[32];
    printf("file: %s\n", path);
    printf("triangles: %llu (%u instances)\n", (unsigned long long)si->triangle_count,
           si->instance_count);
    printf("materials: %u  textures: %u (images %u)  lights: %u%s  cameras: %u\n",
           fi->material_count, si->texture_count, fi->image_count, si->light_count,
           si->studio_environment ? " (studio environment)" : "", si->camera_count);
    printf("nodes: %u  meshes: %u  skins: %u  morph targets: %u (in %u meshes)\n", fi->node_count,
           fi->mesh_count, fi->skin_count, fi->morph_target_count, fi->morph_mesh_count);
    printf("extensions used: %s\n", fi->extensions_used[0] ? fi->extensions_used : "none");
    printf("extensions required: %s\n",
           fi->extensions_required[0] ? fi->extensions_required : "none");
    printf("bounds: (%.3g, %.3g, %.3g) .. (%.3g, %.3g, %.3g) m\n", (double)si->bounds_min[0],
           (double)si->bounds_min[1], (double)si->bounds_min[2], (double)si->bounds_max[0],
           (double)si->bounds_max[1], (double)si->bounds_max[2]);
    printf("clips: %u (plays: %s)\n", fi->clip_count, playing_text(fi, play, sizeof play));
    for (uint32_t i = 0; i < fi->clip_count && i < XRSC_FILE_INFO_MAX_CLIPS; i++) {
        const xrsc_clip_info *c = &fi->clips[i];
        bool plays = si->clip_playing == XRSC_CLIP_ALL || si->clip_playing == (int32_t)i;
        printf("  %c %2u  %-24s %8.3f s  %4u channels\n", plays ? '*' : ' ', i,
               c->name[0] ? c->name : "(unnamed)", (double)c->duration_s, c->channel_count);
    }
}

static void print_json(const char *path, const xrsc_file_info *fi)
{
    const xrsc_scene_info *si = &fi->scene;
    char play[32];
    printf("{\"file\": ");
    json_string(stdout, path);
    printf(", \"triangles\": %llu, \"instances\": %u, \"materials\": %u, \"textures\": %u, "
           "\"images\": %u, \"lights\": %u, \"cameras\": %u, \"nodes\": %u, \"meshes\": %u, "
           "\"skins\": %u, \"morph_targets\": %u, \"morph_meshes\": %u",
           (unsigned long long)si->triangle_count, si->instance_count, fi->material_count,
           si->texture_count, fi->image_count, si->light_count, si->camera_count, fi->node_count,
           fi->mesh_count, fi->skin_count, fi->morph_target_count, fi->morph_mesh_count);
    printf(", \"extensions_used\": ");
    json_string(stdout, fi->extensions_used);
    printf(", \"extensions_required\": ");
    json_string(stdout, fi->extensions_required);
    printf(", \"bounds_min\": [%g, %g, %g], \"bounds_max\": [%g, %g, %g]",
           (double)si->bounds_min[0], (double)si->bounds_min[1], (double)si->bounds_min[2],
           (double)si->bounds_max[0], (double)si->bounds_max[1], (double)si->bounds_max[2]);
    /* the index, or the strings "none" / "all" */
    if (si->clip_playing >= 0)
        printf(", \"clip_playing\": %d, \"clips\": [", si->clip_playing);
    else
        printf(", \"clip_playing\": \"%s\", \"clips\": [", playing_text(fi, play, sizeof play));
    for (uint32_t i = 0; i < fi->clip_count && i < XRSC_FILE_INFO_MAX_CLIPS; i++) {
        printf("%s{\"index\": %u, \"name\": ", i ? ", " : "", i);
        json_string(stdout, fi->clips[i].name);
        printf(", \"duration_s\": %g, \"channels\": %u}", (double)fi->clips[i].duration_s,
               fi->clips[i].channel_count);
    }
    printf("]}\n");
}

int hs_scene_main(int argc, char **argv)
{
    if (argc > 1 && (!strcmp(argv[1], "-h") || !strcmp(argv[1], "--help"))) {
        usage(stdout);
        return 0;
    }
    if (argc < 2 || strcmp(argv[1], "info")) {
        fprintf(stderr, SCENE_CMD ": expected the subcommand info\n");
        usage(stderr);
        return HS_EXIT_BAD_ARGS;
    }
    scene_args sa = {0};
    int c = hs_opt_parse(SCENE_CMD " info", k_scene_opts, SCENE_OPT_COUNT, argc, argv, 2, &sa);
    if (c == HS_OPT_HELP) {
        usage(stdout);
        return 0;
    }
    if (c != HS_ARG_NEXT)
        return c;
    if (!sa.path) {
        fprintf(stderr, SCENE_CMD " info: expected one FILE\n");
        return HS_EXIT_BAD_ARGS;
    }
    const char *path = sa.path;
    bool json = sa.json;
    xrsc_scene_options so = sa.so;
    xrsc_file_info *fi = calloc(1, sizeof(*fi)); /* ~12 KiB */
    xrsc_diag diag = {0};
    char msg[1400];
    xrsc_result r = fi ? xrsc_file_inspect(path, &so, fi, &diag)
                       : u_diag_set(&diag, XRSC_ERROR_OUT_OF_MEMORY, path, 0, "", "out of memory");
    if (r != XRSC_OK)
        fprintf(stderr, SCENE_CMD ": error: %s\n", xrsc_diag_format(&diag, msg, sizeof msg));
    else if (json)
        print_json(path, fi);
    else
        print_text(path, fi);
    free(fi);
    return r == XRSC_OK ? 0 : 1;
}
