// SPDX-License-Identifier: MIT
/**
 * @file hsrt_profiles.c
 * @brief The interaction profiles of OpenXR 1.0 (spec section 6.4, "Interaction Profile
 *        Paths") with their input and output paths, which suggested bindings, subaction paths
 *        and top-level user paths are checked against.
 *
 * The runtime reports no input, but an application's suggestions must still be judged as a
 * real runtime would: an unknown profile or a path the profile does not have is
 * XR_ERROR_PATH_UNSUPPORTED. A binding may name a component ("…/input/trigger/value") or, where
 * the spec lets the runtime pick the component, the identifier alone ("…/input/trigger").
 * Profiles an extension adds are offered only while that extension is enabled; this runtime
 * offers none of those extensions, so `ext` is NULL throughout and the check stays in place.
 */
#include "hsrt.h"

#include <string.h>

enum { L = 1, R = 2, LR = 3, HEAD = 4, PAD = 8 }; /* the user paths a component belongs to */

static const char *const k_user_paths[] = {"/user/hand/left", "/user/hand/right", "/user/head",
                                           "/user/gamepad"};

/* The top-level user paths of spec section 6.3.1 (subaction paths must be among them). */
static const char *const k_top_level_paths[] = {"/user/hand/left", "/user/hand/right", "/user/head",
                                                "/user/gamepad", "/user/treadmill"};

typedef struct hsrt_component {
    unsigned users; /**< mask of k_user_paths */
    const char *subpath;
} hsrt_component;

struct hsrt_profile {
    const char *path;
    const char *ext; /**< the extension that adds it, NULL for core */
    const hsrt_component *components;
};

/* The table keeps one component per entry, grouped as the spec lists them. */
// clang-format off
#define HAND_POSES {LR, "input/grip/pose"}, {LR, "input/aim/pose"}
#define TRACKPAD(u)                                                                                \
    {u, "input/trackpad/x"}, {u, "input/trackpad/y"}, {u, "input/trackpad/click"},                 \
        {u, "input/trackpad/touch"}
#define THUMBSTICK(u, id)                                                                          \
    {u, "input/" id "/x"}, {u, "input/" id "/y"}, {u, "input/" id "/click"}

static const hsrt_component k_simple[] = {
    {LR, "input/select/click"}, {LR, "input/menu/click"}, HAND_POSES, {LR, "output/haptic"}, {0}};

static const hsrt_component k_daydream[] = {
    {LR, "input/select/click"}, TRACKPAD(LR), HAND_POSES, {0}};

static const hsrt_component k_vive[] = {
    {LR, "input/system/click"}, {LR, "input/squeeze/click"}, {LR, "input/menu/click"},
    {LR, "input/trigger/click"}, {LR, "input/trigger/value"}, TRACKPAD(LR), HAND_POSES,
    {LR, "output/haptic"}, {0}};

static const hsrt_component k_vive_pro[] = {
    {HEAD, "input/system/click"}, {HEAD, "input/volume_up/click"},
    {HEAD, "input/volume_down/click"}, {HEAD, "input/mute_mic/click"}, {0}};

static const hsrt_component k_wmr[] = {
    {LR, "input/menu/click"}, {LR, "input/squeeze/click"}, {LR, "input/trigger/value"},
    THUMBSTICK(LR, "thumbstick"), TRACKPAD(LR), HAND_POSES, {LR, "output/haptic"}, {0}};

static const hsrt_component k_xbox[] = {
    {PAD, "input/menu/click"}, {PAD, "input/view/click"}, {PAD, "input/a/click"},
    {PAD, "input/b/click"}, {PAD, "input/x/click"}, {PAD, "input/y/click"},
    {PAD, "input/dpad_down/click"}, {PAD, "input/dpad_right/click"},
    {PAD, "input/dpad_up/click"}, {PAD, "input/dpad_left/click"},
    {PAD, "input/shoulder_left/click"}, {PAD, "input/shoulder_right/click"},
    THUMBSTICK(PAD, "thumbstick_left"), THUMBSTICK(PAD, "thumbstick_right"),
    {PAD, "input/trigger_left/value"}, {PAD, "input/trigger_right/value"},
    {PAD, "output/haptic_left"}, {PAD, "output/haptic_right"},
    {PAD, "output/haptic_left_trigger"}, {PAD, "output/haptic_right_trigger"}, {0}};

static const hsrt_component k_go[] = {
    {LR, "input/system/click"}, {LR, "input/trigger/click"}, {LR, "input/back/click"},
    TRACKPAD(LR), HAND_POSES, {0}};

static const hsrt_component k_touch[] = {
    {L, "input/x/click"}, {L, "input/x/touch"}, {L, "input/y/click"}, {L, "input/y/touch"},
    {L, "input/menu/click"}, {R, "input/a/click"}, {R, "input/a/touch"}, {R, "input/b/click"},
    {R, "input/b/touch"}, {R, "input/system/click"}, {LR, "input/squeeze/value"},
    {LR, "input/trigger/value"}, {LR, "input/trigger/touch"}, THUMBSTICK(LR, "thumbstick"),
    {LR, "input/thumbstick/touch"}, {LR, "input/thumbrest/touch"}, HAND_POSES,
    {LR, "output/haptic"}, {0}};

static const hsrt_component k_index[] = {
    {LR, "input/system/click"}, {LR, "input/system/touch"}, {LR, "input/a/click"},
    {LR, "input/a/touch"}, {LR, "input/b/click"}, {LR, "input/b/touch"},
    {LR, "input/squeeze/value"}, {LR, "input/squeeze/force"}, {LR, "input/trigger/click"},
    {LR, "input/trigger/value"}, {LR, "input/trigger/touch"}, THUMBSTICK(LR, "thumbstick"),
    {LR, "input/thumbstick/touch"}, {LR, "input/trackpad/x"}, {LR, "input/trackpad/y"},
    {LR, "input/trackpad/force"}, {LR, "input/trackpad/touch"}, HAND_POSES,
    {LR, "output/haptic"}, {0}};

static const hsrt_profile k_profiles[] = {
    {"/interaction_profiles/khr/simple_controller", NULL, k_simple},
    {"/interaction_profiles/google/daydream_controller", NULL, k_daydream},
    {"/interaction_profiles/htc/vive_controller", NULL, k_vive},
    {"/interaction_profiles/htc/vive_pro", NULL, k_vive_pro},
    {"/interaction_profiles/microsoft/motion_controller", NULL, k_wmr},
    {"/interaction_profiles/microsoft/xbox_controller", NULL, k_xbox},
    {"/interaction_profiles/oculus/go_controller", NULL, k_go},
    {"/interaction_profiles/oculus/touch_controller", NULL, k_touch},
    {"/interaction_profiles/valve/index_controller", NULL, k_index},
};
// clang-format on

const hsrt_profile *hsrt_profile_find(const hsrt_instance *inst, const char *path)
{
    (void)inst; /* no enabled extension of this runtime adds a profile */
    for (size_t i = 0; i < sizeof(k_profiles) / sizeof(k_profiles[0]); i++) {
        if (!strcmp(k_profiles[i].path, path) && !k_profiles[i].ext)
            return &k_profiles[i];
    }
    return NULL;
}

/** rest names the component c, or its identifier alone (e.g. "input/trigger"). */
static bool names_component(const char *rest, const char *subpath)
{
    size_t n = strlen(rest);
    if (strncmp(rest, subpath, n) != 0)
        return false;
    if (!subpath[n])
        return true;
    /* an identifier: "input/<id>" with exactly one more component after it */
    return subpath[n] == '/' && !strchr(subpath + n + 1, '/') && !strncmp(rest, "input/", 6) &&
           !strchr(rest + 6, '/');
}

bool hsrt_profile_has_binding(const hsrt_profile *p, const char *binding)
{
    for (unsigned u = 0; u < sizeof(k_user_paths) / sizeof(k_user_paths[0]); u++) {
        size_t n = strlen(k_user_paths[u]);
        if (strncmp(binding, k_user_paths[u], n) != 0 || binding[n] != '/')
            continue;
        for (const hsrt_component *c = p->components; c->subpath; c++) {
            if ((c->users & (1u << u)) && names_component(binding + n + 1, c->subpath))
                return true;
        }
    }
    return false;
}

bool hsrt_top_level_path(const char *path)
{
    for (size_t i = 0; i < sizeof(k_top_level_paths) / sizeof(k_top_level_paths[0]); i++) {
        if (!strcmp(path, k_top_level_paths[i]))
            return true;
    }
    return false;
}
