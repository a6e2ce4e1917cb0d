// SPDX-License-Identifier: MIT
/**
 * @file test_scene_clips.c
 * @brief The clip that plays (issue 21, sc_load_options.animation) on the CPU: which channels
 *        the scene keeps and which instances are animated for first / a name / an index / all
 *        / none, the file's clips with names, durations and channel counts, the facts of
 *        `xrsc scene info` (skins, morph targets, extensions), a broken clip that does not
 *        play does not refuse the file, and sc_clip_resolve's rules (keywords, names before
 *        indices, unknown -> XRSC_ERROR_ANIMATION_UNKNOWN). Also run under ASan/UBSan.
 */
#include "sc_scene.h"
#include "testing.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/** Two nodes A (instance 0) and B (instance 1) of one triangle; clip "walk" moves A along x
 *  (-1 to +1 over 1 s), clip "idle" moves B (+1 to -1 over 2 s); with `broken`, a third clip
 *  whose sampler input is an accessor that does not exist. One skin (used by no node), one
 *  morph target, extensions used and required. */
static char *two_clips_json(bool broken)
{
    float data[25] = {-0.25f, -0.2f, -3.0f, 0.25f, -0.2f, -3.0f, 0.0f, 0.2f, -3.0f,
                      0.0f,   1.0f,  -1.0f, 0.35f, 0.0f,  1.0f,  0.35f, 0.0f, 0.0f,
                      2.0f,   1.0f,  -0.35f, 0.0f, -1.0f, -0.35f, 0.0f};
    char *uri = t_data_uri(data, sizeof(data));
    size_t cap = strlen(uri) + 4096;
    char *json = malloc(cap);
    snprintf(json, cap,
             "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],"
             "\"extensionsUsed\":[\"KHR_lights_punctual\",\"KHR_mesh_quantization\"],"
             "\"extensionsRequired\":[\"KHR_mesh_quantization\"],"
             "\"nodes\":[{\"name\":\"A\",\"mesh\":0,\"translation\":[-1,0.35,0]},"
             "{\"name\":\"B\",\"mesh\":0,\"translation\":[1,-0.35,0]}],"
             "\"skins\":[{\"joints\":[1]}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},"
             "\"targets\":[{\"POSITION\":0}]}]}],"
             "\"accessors\":["
             "{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
             "\"min\":[-0.25,-0.2,-3],\"max\":[0.25,0.2,-3]},"
             "{\"bufferView\":1,\"componentType\":5126,\"count\":2,\"type\":\"SCALAR\"},"
             "{\"bufferView\":2,\"componentType\":5126,\"count\":2,\"type\":\"VEC3\"},"
             "{\"bufferView\":3,\"componentType\":5126,\"count\":2,\"type\":\"SCALAR\"},"
             "{\"bufferView\":4,\"componentType\":5126,\"count\":2,\"type\":\"VEC3\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36},"
             "{\"buffer\":0,\"byteOffset\":36,\"byteLength\":8},"
             "{\"buffer\":0,\"byteOffset\":44,\"byteLength\":24},"
             "{\"buffer\":0,\"byteOffset\":68,\"byteLength\":8},"
             "{\"buffer\":0,\"byteOffset\":76,\"byteLength\":24}],"
             "\"buffers\":[{\"byteLength\":100,\"uri\":\"%s\"}],"
             "\"animations\":["
             "{\"name\":\"walk\",\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,"
             "\"path\":\"translation\"}}],\"samplers\":[{\"input\":1,\"output\":2}]},"
             "{\"name\":\"idle\",\"channels\":[{\"sampler\":0,\"target\":{\"node\":1,"
             "\"path\":\"translation\"}}],\"samplers\":[{\"input\":3,\"output\":4}]}%s]}",
             uri,
             broken ? ",{\"name\":\"broken\",\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,"
                      "\"path\":\"rotation\"}}],\"samplers\":[{\"input\":9,\"output\":4}]}"
                    : "");
    free(uri);
    return json;
}

static xrsc_result load(bool broken, const char *animation, sc_scene **out)
{
    char *json = two_clips_json(broken);
    sc_load_options o = {.animation = animation, .keep_triangle_order = true};
    xrsc_diag diag = {0};
    xrsc_result r = sc_scene_load_memory("clips.gltf", json, strlen(json), NULL, &o, out, &diag);
    if (r != XRSC_OK)
        CHECK(diag.code == r);
    free(json);
    return r;
}

/** Loads with `animation` and checks the clip that plays, its channels, which instances are
 *  animated, and node A's x at 0.5 s (0 when walk plays, its rest -1 otherwise). */
static void expect_clip(const char *animation, int32_t playing, uint32_t channels,
                        float duration_s, bool a_animated, bool b_animated)
{
    sc_scene *s = NULL;
    CHECK_EQ_INT(load(false, animation, &s), XRSC_OK);
    if (!s)
        return;
    CHECK_EQ_INT(s->clip_playing, playing);
    CHECK_EQ_INT(s->channel_count, channels);
    CHECK_NEAR(s->animation_duration_s, duration_s, 1e-6);
    CHECK_EQ_INT(s->instance_count, 2);
    CHECK_EQ_INT(s->instances[0].animated, a_animated);
    CHECK_EQ_INT(s->instances[1].animated, b_animated);
    sc_scene_evaluate(s, 0.5);
    CHECK_NEAR(s->instances[0].world[12], a_animated ? 0.0 : -1.0, 1e-6);
    CHECK_NEAR(s->instances[1].world[12], b_animated ? 0.5 : 1.0, 1e-6);
    sc_scene_destroy(&s);
}

static void test_choice(void)
{
    expect_clip(NULL, 0, 1, 1.0f, true, false);
    expect_clip("", 0, 1, 1.0f, true, false);
    expect_clip("first", 0, 1, 1.0f, true, false);
    expect_clip("walk", 0, 1, 1.0f, true, false);
    expect_clip("idle", 1, 1, 2.0f, false, true);
    expect_clip("1", 1, 1, 2.0f, false, true);
    expect_clip("all", SC_CLIP_ALL, 2, 2.0f, true, true);
    expect_clip("none", SC_CLIP_NONE, 0, 0.0f, false, false);
}

static void test_clips_and_facts(void)
{
    sc_scene *s = NULL;
    CHECK_EQ_INT(load(true, NULL, &s), XRSC_OK); /* the broken clip does not play */
    if (!s)
        return;
    CHECK_EQ_INT(s->clip_count, 3);
    CHECK(!strcmp(s->clips[0].name, "walk") && !strcmp(s->clips[1].name, "idle") &&
          !strcmp(s->clips[2].name, "broken"));
    CHECK_NEAR(s->clips[0].duration_s, 1.0, 1e-6);
    CHECK_NEAR(s->clips[1].duration_s, 2.0, 1e-6);
    CHECK_NEAR(s->clips[2].duration_s, 0.0, 1e-6); /* its input cannot be read */
    for (uint32_t i = 0; i < 3; i++)
        CHECK_EQ_INT(s->clips[i].channel_count, 1);
    const sc_file_facts *f = &s->facts;
    CHECK_EQ_INT(f->node_count, 2);
    CHECK_EQ_INT(f->mesh_count, 1);
    CHECK_EQ_INT(f->skin_count, 1);
    CHECK_EQ_INT(f->morph_target_count, 1);
    CHECK_EQ_INT(f->morph_mesh_count, 1);
    CHECK(!strcmp(f->extensions_used, "KHR_lights_punctual, KHR_mesh_quantization"));
    CHECK(!strcmp(f->extensions_required, "KHR_mesh_quantization"));
    sc_scene_destroy(&s);
    /* The broken clip is refused when it is chosen, by name or as part of all. */
    CHECK_EQ_INT(load(true, "broken", &s), XRSC_ERROR_GLTF_INVALID);
    CHECK_EQ_INT(load(true, "all", &s), XRSC_ERROR_GLTF_INVALID);
    CHECK(s == NULL);
}

static void test_unknown(void)
{
    static const char *const bad[] = {"run", "3", "Walk", "-1", "1x", " 0"};
    for (size_t k = 0; k < sizeof(bad) / sizeof(bad[0]); k++) {
        sc_scene *s = NULL;
        CHECK_EQ_INT(load(true, bad[k], &s), XRSC_ERROR_ANIMATION_UNKNOWN);
        CHECK(s == NULL);
    }
}

static void test_resolve_rules(void)
{
    sc_clip clips[3] = {{.name = "x"}, {.name = "0"}, {.name = "all"}};
    int32_t p = 99;
    xrsc_diag d = {0};
    CHECK_EQ_INT(sc_clip_resolve(clips, 3, "0", "f", &p, &d), XRSC_OK);
    CHECK_EQ_INT(p, 1); /* a clip's name wins over an index */
    CHECK_EQ_INT(sc_clip_resolve(clips, 3, "all", "f", &p, &d), XRSC_OK);
    CHECK_EQ_INT(p, SC_CLIP_ALL); /* keywords win over names */
    CHECK_EQ_INT(sc_clip_resolve(clips, 3, "2", "f", &p, &d), XRSC_OK);
    CHECK_EQ_INT(p, 2);
    CHECK_EQ_INT(sc_clip_resolve(clips, 3, "3", "f", &p, &d), XRSC_ERROR_ANIMATION_UNKNOWN);
    CHECK_EQ_INT(d.code, XRSC_ERROR_ANIMATION_UNKNOWN);
    CHECK(!strcmp(d.field, "animation") && !strcmp(d.file, "f"));
    /* no clips: first and all mean none; a name or index is unknown */
    CHECK_EQ_INT(sc_clip_resolve(NULL, 0, NULL, "f", &p, &d), XRSC_OK);
    CHECK_EQ_INT(p, SC_CLIP_NONE);
    CHECK_EQ_INT(sc_clip_resolve(NULL, 0, "all", "f", &p, &d), XRSC_OK);
    CHECK_EQ_INT(p, SC_CLIP_NONE);
    CHECK_EQ_INT(sc_clip_resolve(NULL, 0, "0", "f", &p, &d), XRSC_ERROR_ANIMATION_UNKNOWN);
}

int main(void)
{
    RUN(test_choice);
    RUN(test_clips_and_facts);
    RUN(test_unknown);
    RUN(test_resolve_rules);
    return t_finish();
}
