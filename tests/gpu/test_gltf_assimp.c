// SPDX-License-Identifier: MIT
/**
 * @file test_gltf_assimp.c
 * @brief glTF files nobody here wrote: every glTF 2.0 file of Debian's `assimp-testmodels`
 *        either loads and renders one tiny frame, or is refused with a named reason.
 *
 * Outcomes per file: "renders" (loads, 2x16x16 `primary` frame with finite colours);
 * "unsupported" (XRSC_ERROR_GLTF_UNSUPPORTED, the feature named in the message); "invalid"
 * (a file of assimp's deliberately broken set, refused with a glTF error ID that names the
 * offending field or file; a broken file may also load where tinygltf tolerates the damage).
 * Anything else fails: a crash, a generic error, or an invalid-file error for a file outside
 * the broken set.
 * Without the package (or with XRSC_ASSIMP_MODELS pointing nowhere) the test prints
 * "skipped" and exits T_SKIP (ctest SKIP_RETURN_CODE). Runs under the validation layer.
 */
#define _XOPEN_SOURCE 700 /* nftw */
#include "t_context.h"
#include "testing.h"
#include "xrsc/xrsc.h"

#include <ftw.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/** ctest's SKIP_RETURN_CODE for this test (tests/gpu/CMakeLists.txt). */
#define T_SKIP 77
#define T_SIZE 16u
#define T_MAX_FILES 512
#define T_DEFAULT_ROOT "/usr/share/assimp/models/glTF2"

/* assimp's own negative tests: folders of files that are broken on purpose (bad indices,
 * missing .bin, node cycles, schema violations, wrong JSON types, infinities, bad
 * vertex-array lengths, files with no scene or no nodes, i.e. nothing to draw). xrsc may
 * load them where the damage does not matter (tinygltf takes some wrong JSON types), else
 * must refuse them with a glTF error ID that names the field or file. */
static const char *const k_broken_dirs[] = {
    "/IncorrectVertexArrays/", "/IndexOutOfRange/", "/MissingBin/",    "/RecursiveNodes/",
    "/SchemaFailures/",        "/wrongTypes/",      "/TestNoRootNode/", "/BoxWithInfinites-glTF-Binary/",
};

typedef struct file_list {
    char *paths[T_MAX_FILES];
    int count;
} file_list;

static file_list g_files; /* nftw has no user pointer; this test's only global */
static xrsc_context *g_ctx;
static int g_renders, g_unsupported, g_invalid, g_other;

static int collect(const char *path, const struct stat *st, int type, struct FTW *ftw)
{
    (void)st, (void)ftw;
    size_t n = strlen(path);
    bool gltf = (n > 5 && !strcmp(path + n - 5, ".gltf")) || (n > 4 && !strcmp(path + n - 4, ".glb"));
    if (type == FTW_F && gltf && g_files.count < T_MAX_FILES)
        g_files.paths[g_files.count++] = strdup(path);
    return 0;
}

static int cmp_str(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static bool in_broken_set(const char *path)
{
    for (size_t i = 0; i < sizeof(k_broken_dirs) / sizeof(k_broken_dirs[0]); i++)
        if (strstr(path, k_broken_dirs[i]))
            return true;
    return false;
}

/** Renders one 2x16x16 `primary` frame from the scene's viewpoint; true when colours are
 *  finite and non-negative. */
static bool render_tiny(xrsc_scene *scene, const char *path)
{
    char buf[1024];
    xrsc_diag diag;
    xrsc_renderer_options ro = {.method = XRSC_METHOD_PRIMARY, .width = T_SIZE, .height = T_SIZE};
    xrsc_renderer *rend = NULL;
    xrsc_result r = xrsc_renderer_create(g_ctx, scene, &ro, &rend, &diag);
    CHECK_MSG(r == XRSC_OK, "%s: %s", path, xrsc_diag_format(&diag, buf, sizeof(buf)));
    if (r != XRSC_OK)
        return false;
    xrsc_scene_info info;
    xrsc_scene_get_info(scene, &info);
    xrsc_headset hs;
    xrsc_headset_default(&hs);
    XrPosef eyes[2];
    xrsc_headset_eye_poses(&hs, info.viewpoint, eyes);
    xrsc_frame frame;
    memset(&frame, 0, sizeof(frame));
    for (int e = 0; e < 2; e++) {
        frame.views[e].pose = eyes[e];
        frame.views[e].fov = hs.fov[e];
    }
    bool ok = xrsc_renderer_render(rend, &frame) == XRSC_OK;
    size_t csize = xrsc_renderer_output_size(rend, XRSC_OUTPUT_COLOR);
    float *color = malloc(csize);
    for (uint32_t eye = 0; ok && color && eye < 2; eye++) {
        ok = xrsc_renderer_read(rend, eye, XRSC_OUTPUT_COLOR, color, csize) == XRSC_OK;
        for (size_t i = 0; ok && i < csize / sizeof(float); i++)
            ok = isfinite(color[i]) && color[i] >= 0.0f;
    }
    free(color);
    xrsc_renderer_destroy(&rend);
    return ok;
}

static void check_file(const char *path)
{
    char buf[1024];
    xrsc_diag diag;
    memset(&diag, 0, sizeof(diag));
    xrsc_scene *scene = NULL;
    xrsc_result r = xrsc_scene_load(g_ctx, path, NULL, &scene, &diag);
    bool broken = in_broken_set(path);
    const char *outcome;
    if (r == XRSC_OK) {
        bool ok = render_tiny(scene, path);
        xrsc_scene_destroy(&scene);
        CHECK_MSG(ok, "%s: the frame failed or has non-finite colours", path);
        outcome = ok ? "renders" : "FAILED";
        if (ok)
            g_renders++;
        else
            g_other++;
    } else if (r == XRSC_ERROR_GLTF_UNSUPPORTED && diag.message[0]) {
        outcome = "unsupported";
        g_unsupported++;
    } else if (broken && diag.message[0] &&
               (r == XRSC_ERROR_GLTF_INVALID || r == XRSC_ERROR_GLTF_PARSE ||
                r == XRSC_ERROR_GLTF_MISSING_BUFFER || r == XRSC_ERROR_GLTF_NOT_GLTF ||
                r == XRSC_ERROR_GLTF_VERSION || r == XRSC_ERROR_GLB_MAGIC ||
                r == XRSC_ERROR_GLB_TRUNCATED)) {
        outcome = "invalid";
        g_invalid++;
    } else {
        outcome = "OTHER";
        g_other++;
        CHECK_MSG(false, "%s: refused without a named reason: %s", path,
                  xrsc_diag_format(&diag, buf, sizeof(buf)));
    }
    printf("%-12s %s", outcome, path);
    if (r != XRSC_OK)
        printf("  -- %s", xrsc_diag_format(&diag, buf, sizeof(buf)));
    printf("\n");
}

static void test_all_files(void)
{
    for (int i = 0; i < g_files.count; i++)
        check_file(g_files.paths[i]);
    printf("assimp-testmodels glTF 2.0: %d files: %d render, %d named unsupported, %d invalid "
           "(deliberately broken, named error), %d other\n",
           g_files.count, g_renders, g_unsupported, g_invalid, g_other);
    CHECK_EQ_INT(g_other, 0);
    CHECK(g_renders > 0);
}

int main(void)
{
    const char *root = getenv("XRSC_ASSIMP_MODELS");
    if (!root || !root[0])
        root = T_DEFAULT_ROOT;
    struct stat st;
    if (stat(root, &st) != 0 || !S_ISDIR(st.st_mode)) {
        printf("skipped: %s not found (apt-get install assimp-testmodels)\n", root);
        return T_SKIP;
    }
    nftw(root, collect, 16, FTW_PHYS);
    qsort(g_files.paths, (size_t)g_files.count, sizeof(char *), cmp_str);
    if (g_files.count == 0) {
        printf("skipped: no .gltf/.glb files under %s\n", root);
        return T_SKIP;
    }
    if (!(g_ctx = t_context_open()))
        return 1;
    RUN(test_all_files);
    t_context_close(&g_ctx);
    for (int i = 0; i < g_files.count; i++)
        free(g_files.paths[i]);
    return t_finish();
}
