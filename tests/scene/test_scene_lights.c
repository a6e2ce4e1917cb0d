// SPDX-License-Identifier: MIT
/**
 * @file test_scene_lights.c
 * @brief KHR_lights_punctual → sc_scene (issue 18, item 3): the first directional light is the
 *        sun, every other light (directional, point, spot) an sc_light with its node, colour x
 *        intensity, range and cone angles (bad angles clamped with a warning); unknown types
 *        are noted; --sky drops the directional lights and keeps point and spot lights; point
 *        and spot lights leave the default grey environment on, a directional light turns it
 *        off.
 */
#include "sc_scene.h"
#include "sc_test_util.h"
#include "testing.h"

#include <math.h>
#include <string.h>

/** One triangle (node 0) and light nodes 1.. (JSON objects), lights (a JSON array). */
static const char *lights_gltf(const char *name, const char *lights, const char *nodes,
                               const char *roots)
{
    uint8_t bytes[44];
    sct_triangle_bytes(bytes, 0, 1, 2);
    char *uri = t_data_uri(bytes, sizeof bytes);
    static char json[8192];
    snprintf(
        json, sizeof json,
        "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0, \"scenes\": [{\"nodes\": [%s]}],"
        " \"nodes\": [{\"mesh\": 0}, %s],"
        " \"extensionsUsed\": [\"KHR_lights_punctual\"],"
        " \"extensions\": {\"KHR_lights_punctual\": {\"lights\": %s}},"
        " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"indices\": 1}]}],"
        " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 3,"
        " \"type\": \"VEC3\"}, {\"bufferView\": 1, \"componentType\": 5123, \"count\": 3,"
        " \"type\": \"SCALAR\"}], \"bufferViews\": [{\"buffer\": 0, \"byteLength\": 36},"
        " {\"buffer\": 0, \"byteOffset\": 36, \"byteLength\": 6}],"
        " \"buffers\": [{\"byteLength\": 44, \"uri\": \"%s\"}]}",
        roots, nodes, lights, uri);
    free(uri);
    return t_temp_file(name, json);
}

static sc_scene *load(const char *path, const sc_load_options *opt)
{
    sc_scene *s = NULL;
    xrsc_diag d = {0};
    xrsc_result r = sc_scene_load(path, opt, &s, &d);
    char buf[1024];
    CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&d, buf, sizeof buf));
    return s;
}

static const char *k_lights =
    "[{\"type\": \"directional\", \"color\": [1, 0.5, 0.25], \"intensity\": 2},"
    " {\"type\": \"point\", \"color\": [0, 1, 0], \"intensity\": 7, \"range\": 5},"
    " {\"type\": \"spot\", \"intensity\": 3, \"spot\": {\"innerConeAngle\": 0.8,"
    " \"outerConeAngle\": 0.4}},"
    " {\"type\": \"directional\", \"intensity\": 4},"
    " {\"type\": \"area\", \"intensity\": 1},"
    " {\"type\": \"spot\", \"intensity\": 1, \"spot\": {}}]";
static const char *k_nodes =
    "{\"extensions\": {\"KHR_lights_punctual\": {\"light\": 0}}},"
    " {\"translation\": [1, 2, 3], \"extensions\": {\"KHR_lights_punctual\": {\"light\": 1}}},"
    " {\"extensions\": {\"KHR_lights_punctual\": {\"light\": 2}}},"
    " {\"extensions\": {\"KHR_lights_punctual\": {\"light\": 3}}},"
    " {\"extensions\": {\"KHR_lights_punctual\": {\"light\": 4}}},"
    " {\"extensions\": {\"KHR_lights_punctual\": {\"light\": 5}}}";

static void test_all_lights(void)
{
    const char *path = lights_gltf("lights_all.gltf", k_lights, k_nodes, "0, 1, 2, 3, 4, 5, 6");
    sc_scene *s = load(path, NULL);
    if (!s)
        return;
    /* the first directional light: the sun, towards its node's +Z */
    CHECK(s->sun.present);
    CHECK_NEAR(s->sun.direction[2], 1.0, 1e-6);
    CHECK_NEAR(s->sun.radiance[1], 1.0, 1e-6);
    /* point, spot, directional, spot in walk order; the area light is not one */
    CHECK_EQ_INT(s->light_count, 4);
    if (s->light_count == 4) {
        const sc_light *p = &s->lights[0], *sp = &s->lights[1], *d = &s->lights[2];
        CHECK_EQ_INT(p->type, SC_LIGHT_POINT);
        CHECK_EQ_INT(p->node, 2);
        CHECK_NEAR(p->intensity[0], 0.0, 0.0);
        CHECK_NEAR(p->intensity[1], 7.0, 0.0);
        CHECK_NEAR(p->range_m, 5.0, 0.0);
        CHECK_NEAR(s->nodes[p->node].world[13], 2.0, 0.0);
        /* inner > outer: clamped to inner = outer (warned) */
        CHECK_EQ_INT(sp->type, SC_LIGHT_SPOT);
        CHECK_NEAR(sp->outer_cone_rad, 0.4, 1e-6);
        CHECK_NEAR(sp->inner_cone_rad, 0.4, 1e-6);
        CHECK_NEAR(sp->range_m, 0.0, 0.0); /* absent: infinite */
        CHECK_EQ_INT(d->type, SC_LIGHT_DIRECTIONAL);
        CHECK_NEAR(d->intensity[2], 4.0, 0.0);
        /* glTF's defaults: inner 0, outer pi/4 */
        CHECK_NEAR(s->lights[3].inner_cone_rad, 0.0, 0.0);
        CHECK_NEAR(s->lights[3].outer_cone_rad, 0.78539816, 1e-6);
    }
    CHECK(s->warning_count >= 1); /* the spot's cone angles */
    /* a directional light is the lighting: no default grey */
    CHECK_NEAR(s->environment[0], 0.0, 0.0);
    sc_scene_destroy(&s);

    /* --sky: its sun replaces the directional lights, the lamps stay */
    sc_load_options o = {.sky = true};
    s = load(path, &o);
    if (!s)
        return;
    CHECK(s->sun.present && s->sun.angular_radius_rad > 0.0f);
    CHECK_EQ_INT(s->light_count, 3);
    for (uint32_t i = 0; i < s->light_count; i++)
        CHECK(s->lights[i].type != SC_LIGHT_DIRECTIONAL);
    sc_scene_destroy(&s);
}

static void test_lamps_keep_default_environment(void)
{
    const char *path = lights_gltf(
        "lights_lamp.gltf", "[{\"type\": \"point\", \"intensity\": 1}]",
        "{\"translation\": [0, 1, 0], \"extensions\": {\"KHR_lights_punctual\": {\"light\": 0}}}",
        "0, 1");
    sc_scene *s = load(path, NULL);
    if (!s)
        return;
    CHECK(!s->sun.present);
    CHECK_EQ_INT(s->light_count, 1);
    CHECK(s->env_studio); /* lamps keep the default (studio) environment on, as viewers do */
    CHECK_EQ_INT(s->warning_count, 0);
    sc_scene_destroy(&s);
}

int main(void)
{
    RUN(test_all_lights);
    RUN(test_lamps_keep_default_environment);
    return t_finish();
}
