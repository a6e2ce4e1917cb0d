// SPDX-License-Identifier: MIT
/**
 * @file hsrt_entry.c
 * @brief The loader's entry point (xrNegotiateLoaderRuntimeInterface), xrGetInstanceProcAddr,
 *        and the instance-level core functions: instance, system, paths, events, results,
 *        view configurations and blend modes.
 *
 * Debian's OpenXR 1.0.20 has no openxr_loader_negotiation.h, so the negotiation structs of
 * loader interface version 1 are declared here (as the loader's loader_interfaces.h). The
 * runtime keeps no process-wide mutable state: every handle is a heap struct, and the
 * negotiation hands the loader a pointer to a function, nothing else.
 */
#include "hsrt_instance.h"

#include "u_diag.h"

#include <openxr/openxr_reflection.h>

#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* ---- loader negotiation (loader_interfaces.h of the OpenXR SDK, interface version 1) ---- */

typedef enum XrLoaderInterfaceStructs {
    XR_LOADER_INTERFACE_STRUCT_UNINTIALIZED = 0,
    XR_LOADER_INTERFACE_STRUCT_LOADER_INFO,
    XR_LOADER_INTERFACE_STRUCT_API_LAYER_REQUEST,
    XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST,
    XR_LOADER_INTERFACE_STRUCT_API_LAYER_CREATE_INFO,
    XR_LOADER_INTERFACE_STRUCT_API_LAYER_NEXT_INFO,
} XrLoaderInterfaceStructs;

#define XR_LOADER_INFO_STRUCT_VERSION 1
#define XR_RUNTIME_INFO_STRUCT_VERSION 1
#define XR_CURRENT_LOADER_RUNTIME_VERSION 1

typedef struct XrNegotiateLoaderInfo {
    XrLoaderInterfaceStructs structType;
    uint32_t structVersion;
    size_t structSize;
    uint32_t minInterfaceVersion;
    uint32_t maxInterfaceVersion;
    XrVersion minApiVersion;
    XrVersion maxApiVersion;
} XrNegotiateLoaderInfo;

typedef struct XrNegotiateRuntimeRequest {
    XrLoaderInterfaceStructs structType;
    uint32_t structVersion;
    size_t structSize;
    uint32_t runtimeInterfaceVersion;
    XrVersion runtimeApiVersion;
    PFN_xrGetInstanceProcAddr getInstanceProcAddr;
} XrNegotiateRuntimeRequest;

/* The one exported symbol (the version script hides everything else). */
__attribute__((visibility("default"))) XrResult XRAPI_CALL
xrNegotiateLoaderRuntimeInterface(const XrNegotiateLoaderInfo *loaderInfo,
                                  XrNegotiateRuntimeRequest *runtimeRequest);

/* ---- logging and results ---- */

static const char *structure_type_name(XrStructureType type)
{
    switch (type) {
#define HSRT_X_STYPE(name, value)                                                                  \
    case name:                                                                                     \
        return #name;
        XR_LIST_ENUM_XrStructureType(HSRT_X_STYPE)
#undef HSRT_X_STYPE
    default:
        return NULL;
    }
}

#define GET_INSTANCE(var, handle, fn)                                                              \
    hsrt_instance *var = hsrt_instance_from(handle);                                               \
    if (!var)                                                                                      \
        return hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "not an XrInstance of this runtime");

/* ---- events ---- */

static XrResult XRAPI_CALL hsrt_xrPollEvent(XrInstance instance, XrEventDataBuffer *eventData)
{
    GET_INSTANCE(inst, instance, "xrPollEvent");
    if (!eventData)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, "xrPollEvent", "eventData is NULL");
    pthread_mutex_lock(&inst->lock);
    XrResult r = XR_EVENT_UNAVAILABLE;
    if (inst->event_count) {
        *eventData = inst->events[inst->event_head];
        inst->event_head = (inst->event_head + 1) % HSRT_EVENT_QUEUE;
        inst->event_count--;
        r = XR_SUCCESS;
    }
    pthread_mutex_unlock(&inst->lock);
    return r;
}

/* ---- configuration from the environment ---- */

static bool parse_u64(const char *s, uint64_t *out)
{
    if (!s || !*s)
        return false;
    char *end = NULL;
    unsigned long long v = strtoull(s, &end, 10);
    if (*end || s[0] == '-')
        return false;
    *out = v;
    return true;
}

/** A 0/off or 1/on setting; false for anything else. */
static bool parse_switch(const char *v, bool *out)
{
    if (!strcmp(v, "0") || !strcmp(v, "off"))
        *out = false;
    else if (!strcmp(v, "1") || !strcmp(v, "on"))
        *out = true;
    else
        return false;
    return true;
}

/** The preview's overlay, history, reference and end-of-run settings (README.md). */
static XrResult preview_overlay_config_from_env(hsrt_config *cfg)
{
    const char *fn = "xrCreateInstance";
    bool on = true;
    uint64_t n = 0;
    cfg->preview_info_fd = -1;
    cfg->preview_history = HSRT_PREVIEW_HISTORY_DEFAULT;
    const char *v = getenv("XRSC_RT_PREVIEW_AUTOCLOSE");
    if (v && *v && !parse_switch(v, &cfg->preview_autoclose))
        return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, fn,
                         "XRSC_RT_PREVIEW_AUTOCLOSE='%s' is neither 1/on nor 0/off", v);
    v = getenv("XRSC_RT_PREVIEW_OVERLAY");
    if (v && *v && !parse_switch(v, &on))
        return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, fn,
                         "XRSC_RT_PREVIEW_OVERLAY='%s' is neither 1/on nor 0/off", v);
    cfg->preview_no_overlay = !on;
    v = getenv("XRSC_RT_PREVIEW_INFO_FD");
    if (v && *v) {
        if (!parse_u64(v, &n) || n > INT32_MAX)
            return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, fn,
                             "XRSC_RT_PREVIEW_INFO_FD='%s' is not a file descriptor", v);
        cfg->preview_info_fd = (int)n;
    }
    v = getenv("XRSC_RT_PREVIEW_HISTORY");
    if (v && *v) {
        if (!parse_u64(v, &n) || n < 1 || n > HSRT_PREVIEW_HISTORY_MAX)
            return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, fn,
                             "XRSC_RT_PREVIEW_HISTORY='%s' is not 1..%u", v,
                             HSRT_PREVIEW_HISTORY_MAX);
        cfg->preview_history = (uint32_t)n;
    }
    v = getenv("XRSC_RT_PREVIEW_REFERENCE");
    snprintf(cfg->preview_reference, sizeof(cfg->preview_reference), "%s", v ? v : "");
    return XR_SUCCESS;
}

/** The preview window's settings (hsrt_preview.c); headless unless XRSC_RT_PREVIEW=1. */
static XrResult preview_config_from_env(hsrt_config *cfg)
{
    const char *fn = "xrCreateInstance";
    cfg->preview_hold_frame = -1;
    const char *v = getenv("XRSC_RT_PREVIEW");
    if (!v || !*v || !strcmp(v, "0") || !strcmp(v, "off"))
        cfg->preview = false;
    else if (!strcmp(v, "1") || !strcmp(v, "on"))
        cfg->preview = true;
    else
        return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, fn,
                         "XRSC_RT_PREVIEW='%s' is neither 1/on nor 0/off", v);
    v = getenv("XRSC_RT_PREVIEW_SIZE");
    if (v && *v) {
        unsigned w = 0, h = 0;
        char tail = 0;
        if (sscanf(v, "%ux%u%c", &w, &h, &tail) != 2 || w < 16 || h < 16 || w > 8192 || h > 8192)
            return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, fn,
                             "XRSC_RT_PREVIEW_SIZE='%s' is not WxH (16..8192)", v);
        cfg->preview_w = w;
        cfg->preview_h = h;
    }
    v = getenv("XRSC_RT_PREVIEW_HOLD_FRAME");
    if (v && *v) {
        uint64_t n = 0;
        if (!parse_u64(v, &n) || n > (uint64_t)INT64_MAX)
            return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, fn,
                             "XRSC_RT_PREVIEW_HOLD_FRAME='%s' is not a frame number", v);
        cfg->preview_hold_frame = (int64_t)n;
    }
    v = getenv("XRSC_RT_PREVIEW_VIEW");
    if (v && *v) {
        if (!strcmp(v, "swap"))
            cfg->preview_swapped = true;
        else if (!strcmp(v, "diff"))
            cfg->preview_diff = true;
        else if (strcmp(v, "sbs"))
            return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, fn,
                             "XRSC_RT_PREVIEW_VIEW='%s' is not sbs, swap or diff", v);
    }
    v = getenv("XRSC_RT_PREVIEW_DEVICE");
    snprintf(cfg->preview_device, sizeof(cfg->preview_device), "%s", v ? v : "");
    return preview_overlay_config_from_env(cfg);
}

/* XRSC_RT_FOV_DEG: 8 angles in degrees, the left eye's left, right, up, down, then the right
 * eye's (XrFovf's convention: left and down negative), each within +-89.9. */
static bool parse_fov_deg(const char *v, XrFovf out[2])
{
    double a[8];
    const double rad = 3.14159265358979323846 / 180.0;
    for (int i = 0; i < 8; i++) {
        char *end = NULL;
        a[i] = strtod(v, &end);
        if (end == v || !(fabs(a[i]) < 89.9) || *end != (i < 7 ? ',' : '\0'))
            return false;
        v = end + (i < 7);
    }
    for (int e = 0; e < 2; e++) {
        const double *f = a + 4 * e;
        if (!(f[0] < f[1]) || !(f[3] < f[2]))
            return false;
        out[e] = (XrFovf){(float)(f[0] * rad), (float)(f[1] * rad), (float)(f[2] * rad),
                          (float)(f[3] * rad)};
    }
    return true;
}

/* A number from environment variable name in [lo, hi] into *out (*out_set: it was given;
 * unset or empty leaves *out); what = how the error names a valid value. */
static XrResult env_number(const char *name, double lo, double hi, const char *what,
                           double *out, bool *out_set)
{
    const char *v = getenv(name);
    *out_set = false;
    if (!v || !*v)
        return XR_SUCCESS;
    char *end = NULL;
    double x = strtod(v, &end);
    if (*end || !(x >= lo && x <= hi))
        return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, "xrCreateInstance",
                         "%s='%s' is not %s", name, v, what);
    *out = x;
    *out_set = true;
    return XR_SUCCESS;
}

/* The stream and its pacing: XRSC_RT_POSES, _FRAMES, _LOSE_AFTER, _PACE, _START_S. */
static XrResult config_stream(hsrt_config *cfg)
{
    const char *v = getenv("XRSC_RT_POSES");
    snprintf(cfg->poses_path, sizeof(cfg->poses_path), "%s",
             v && *v ? v : XRSC_SOURCE_DIR "/poses/orbit_cornell.xrpose");
    v = getenv("XRSC_RT_FRAMES");
    if (v && *v && !parse_u64(v, &cfg->frames))
        return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, "xrCreateInstance",
                         "XRSC_RT_FRAMES='%s' is not a frame count", v);
    v = getenv("XRSC_RT_LOSE_AFTER");
    if (v && *v && !parse_u64(v, &cfg->lose_after))
        return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, "xrCreateInstance",
                         "XRSC_RT_LOSE_AFTER='%s' is not a frame count", v);
    v = getenv("XRSC_RT_MAX_POSE_BYTES");
    if (v && *v && !parse_u64(v, &cfg->max_pose_bytes))
        return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, "xrCreateInstance",
                         "XRSC_RT_MAX_POSE_BYTES='%s' is not a byte count", v);
    v = getenv("XRSC_RT_PACE");
    if (!v || !*v || !strcmp(v, "realtime"))
        cfg->pace = HSRT_PACE_REALTIME;
    else if (!strcmp(v, "fast"))
        cfg->pace = HSRT_PACE_FAST;
    else
        return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, "xrCreateInstance",
                         "XRSC_RT_PACE='%s' is neither realtime nor fast", v);
    double sec = 0.0;
    bool set;
    XrResult r = env_number("XRSC_RT_START_S", 0.0, 1e9, "seconds >= 0", &sec, &set);
    cfg->start_ns = (int64_t)(sec * 1e9);
    return r;
}

/* What is written: XRSC_RT_OUT, _WRITE (eyes, sbs, linear, none), _EXPOSURE (or auto). */
static XrResult config_outputs(hsrt_config *cfg)
{
    const char *v = getenv("XRSC_RT_OUT");
    snprintf(cfg->out_dir, sizeof(cfg->out_dir), "%s", v ? v : "");
    uint64_t fd = 0;
    cfg->error_fd = -1;
    v = getenv("XRSC_RT_ERROR_FD");
    if (v && *v) {
        if (!parse_u64(v, &fd) || fd > INT32_MAX)
            return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, "xrCreateInstance",
                             "XRSC_RT_ERROR_FD='%s' is not a file descriptor", v);
        cfg->error_fd = (int)fd;
    }
    v = getenv("XRSC_RT_WRITE");
    if (!v || !*v) {
        cfg->write_eyes = cfg->write_sbs = true;
    } else {
        char buf[256];
        snprintf(buf, sizeof(buf), "%s", v);
        for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok;
             tok = strtok_r(NULL, ",", &save)) {
            if (!strcmp(tok, "eyes"))
                cfg->write_eyes = true;
            else if (!strcmp(tok, "sbs"))
                cfg->write_sbs = true;
            else if (!strcmp(tok, "linear"))
                cfg->write_linear = true;
            else if (strcmp(tok, "none"))
                return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, "xrCreateInstance",
                                 "XRSC_RT_WRITE: unknown item '%s' (eyes, sbs, linear, none)", tok);
        }
    }
    v = getenv("XRSC_RT_EXPOSURE");
    cfg->exposure = 1.0f;
    if (v && !strcmp(v, "auto")) {
        cfg->exposure = 0.0f; /* automatic (hs_autoexposure, hsrt_vk_capture) */
        return XR_SUCCESS;
    }
    if (v && *v) {
        char *end = NULL;
        double e = strtod(v, &end);
        if (*end || !(e > 0.0) || !isfinite(e))
            return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, "xrCreateInstance",
                             "XRSC_RT_EXPOSURE='%s' is not a positive number or auto", v);
        cfg->exposure = (float)e;
    }
    return XR_SUCCESS;
}

/* The simulated headset: XRSC_RT_EYE_SIZE, _REFRESH_HZ, _IPD_MM, _FOV_DEG. */
static XrResult config_headset(hsrt_config *cfg)
{
    const char *v = getenv("XRSC_RT_EYE_SIZE");
    if (v && *v) {
        unsigned w = 0, h = 0;
        char tail = 0;
        if (sscanf(v, "%ux%u%c", &w, &h, &tail) != 2 || w < 1 || h < 1 || w > 8192 || h > 8192)
            return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, "xrCreateInstance",
                             "XRSC_RT_EYE_SIZE='%s' is not WxH (1..8192)", v);
        cfg->headset.width_px = w;
        cfg->headset.height_px = h;
    }
    double hz, mm;
    bool hz_set, mm_set;
    XrResult r;
    if ((r = env_number("XRSC_RT_REFRESH_HZ", 1.0, 1000.0, "a rate in 1..1000 Hz", &hz,
                        &hz_set)) != XR_SUCCESS ||
        (r = env_number("XRSC_RT_IPD_MM", 0.0, 200.0, "millimetres in 0..200", &mm, &mm_set)) !=
            XR_SUCCESS)
        return r;
    if (hz_set)
        cfg->headset.refresh_hz = (float)hz;
    if (mm_set)
        cfg->headset.ipd_m = (float)(mm * 1e-3);
    v = getenv("XRSC_RT_FOV_DEG");
    if (v && *v && !parse_fov_deg(v, cfg->headset.fov))
        return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, "xrCreateInstance",
                         "XRSC_RT_FOV_DEG='%s' is not 8 angles in degrees (left eye's left, "
                         "right, up, down, then the right eye's; left < right, down < up, "
                         "each within +-89.9)",
                         v);
    return XR_SUCCESS;
}

static XrResult config_from_env(hsrt_config *cfg)
{
    memset(cfg, 0, sizeof(*cfg));
    xrsc_headset_default(&cfg->headset);
    XrResult r;
    if ((r = config_stream(cfg)) != XR_SUCCESS || (r = config_outputs(cfg)) != XR_SUCCESS ||
        (r = config_headset(cfg)) != XR_SUCCESS)
        return r;
    /* The same selector as the plugin's --device: XRSC_RT_DEVICE, else XRSC_DEVICE. */
    const char *v = getenv("XRSC_RT_DEVICE");
    if (!v || !*v)
        v = getenv("XRSC_DEVICE");
    snprintf(cfg->device, sizeof(cfg->device), "%s", v ? v : "");
    return preview_config_from_env(cfg);
}

/** LOCAL's origin: the first pose's position, turned only about +Y (gravity aligned). */
static XrPosef local_origin_of(const hs_pose_stream *stream)
{
    XrPosef first = stream->samples[0].pose;
    XrVector3f fwd = xrsc_quat_rotate(first.orientation, (XrVector3f){0.0f, 0.0f, -1.0f});
    float yaw = 0.0f;
    if (fabsf(fwd.x) + fabsf(fwd.z) > 1e-4f)
        yaw = atan2f(-fwd.x, -fwd.z);
    XrPosef out = {.orientation = xrsc_quat_from_axis_angle((XrVector3f){0, 1, 0}, yaw),
                   .position = first.position};
    return out;
}

/* ---- paths ---- */

static bool path_well_formed(const char *s)
{
    size_t n = strlen(s);
    if (n < 2 || s[0] != '/' || s[n - 1] == '/')
        return false;
    for (size_t i = 0; i < n; i++) {
        char c = s[i];
        if (c == '/') {
            if (s[i + 1] == '/')
                return false;
            /* "." and ".." components are not allowed */
            if (s[i + 1] == '.' && (s[i + 2] == '/' || !s[i + 2] ||
                                    (s[i + 2] == '.' && (s[i + 3] == '/' || !s[i + 3]))))
                return false;
        } else if (!(islower((unsigned char)c) || isdigit((unsigned char)c) || c == '-' ||
                     c == '_' || c == '.')) {
            return false;
        }
    }
    return true;
}

static XrResult XRAPI_CALL hsrt_xrStringToPath(XrInstance instance, const char *pathString,
                                               XrPath *path)
{
    GET_INSTANCE(inst, instance, "xrStringToPath");
    if (!pathString || !path)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, "xrStringToPath", "NULL argument");
    if (strlen(pathString) >= XR_MAX_PATH_LENGTH || !path_well_formed(pathString))
        return hsrt_fail(XR_ERROR_PATH_FORMAT_INVALID, "xrStringToPath", "'%s'", pathString);
    pthread_mutex_lock(&inst->lock);
    XrResult r = XR_SUCCESS;
    for (uint32_t i = 0; i < inst->path_count; i++) {
        if (!strcmp(inst->paths[i], pathString)) {
            *path = i + 1;
            goto out;
        }
    }
    if (inst->path_count == inst->path_cap) {
        uint32_t cap = inst->path_cap ? inst->path_cap * 2 : 64;
        char **grown = realloc(inst->paths, cap * sizeof(*grown));
        if (!grown) {
            r = hsrt_fail(XR_ERROR_PATH_COUNT_EXCEEDED, "xrStringToPath", "out of memory");
            goto out;
        }
        inst->paths = grown;
        inst->path_cap = cap;
    }
    char *copy = strdup(pathString);
    if (!copy) {
        r = hsrt_fail(XR_ERROR_PATH_COUNT_EXCEEDED, "xrStringToPath", "out of memory");
        goto out;
    }
    inst->paths[inst->path_count++] = copy;
    *path = inst->path_count;
out:
    pthread_mutex_unlock(&inst->lock);
    return r;
}

static XrResult XRAPI_CALL hsrt_xrPathToString(XrInstance instance, XrPath path,
                                               uint32_t bufferCapacityInput,
                                               uint32_t *bufferCountOutput, char *buffer)
{
    GET_INSTANCE(inst, instance, "xrPathToString");
    if (!bufferCountOutput)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, "xrPathToString", "NULL count");
    pthread_mutex_lock(&inst->lock);
    const char *s = hsrt_path_string(inst, path);
    XrResult r = XR_SUCCESS;
    if (!s) {
        r = hsrt_fail(XR_ERROR_PATH_INVALID, "xrPathToString", "unknown path %llu",
                      (unsigned long long)path);
    } else {
        uint32_t need = (uint32_t)strlen(s) + 1;
        *bufferCountOutput = need;
        if (bufferCapacityInput) {
            if (bufferCapacityInput < need || !buffer)
                r = XR_ERROR_SIZE_INSUFFICIENT;
            else
                memcpy(buffer, s, need);
        }
    }
    pthread_mutex_unlock(&inst->lock);
    return r;
}

/* ---- instance ---- */

typedef struct hsrt_ext {
    const char *name;
    uint32_t version;
} hsrt_ext;

static const hsrt_ext k_extensions[] = {
    {XR_KHR_VULKAN_ENABLE_EXTENSION_NAME, XR_KHR_vulkan_enable_SPEC_VERSION},
    {XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME, XR_KHR_vulkan_enable2_SPEC_VERSION},
    {XR_KHR_COMPOSITION_LAYER_DEPTH_EXTENSION_NAME, XR_KHR_composition_layer_depth_SPEC_VERSION},
};
#define HSRT_EXT_COUNT (sizeof(k_extensions) / sizeof(k_extensions[0]))

static XrResult XRAPI_CALL hsrt_xrEnumerateApiLayerProperties(uint32_t propertyCapacityInput,
                                                              uint32_t *propertyCountOutput,
                                                              XrApiLayerProperties *properties)
{
    (void)propertyCapacityInput;
    (void)properties;
    if (!propertyCountOutput)
        return XR_ERROR_VALIDATION_FAILURE;
    *propertyCountOutput = 0;
    return XR_SUCCESS;
}

static XrResult XRAPI_CALL hsrt_xrEnumerateInstanceExtensionProperties(
    const char *layerName, uint32_t propertyCapacityInput, uint32_t *propertyCountOutput,
    XrExtensionProperties *properties)
{
    if (layerName && *layerName)
        return XR_ERROR_API_LAYER_NOT_PRESENT;
    if (!propertyCountOutput)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, "xrEnumerateInstanceExtensionProperties",
                         "NULL count");
    *propertyCountOutput = HSRT_EXT_COUNT;
    if (!propertyCapacityInput)
        return XR_SUCCESS;
    if (propertyCapacityInput < HSRT_EXT_COUNT || !properties)
        return XR_ERROR_SIZE_INSUFFICIENT;
    for (uint32_t i = 0; i < HSRT_EXT_COUNT; i++) {
        if (properties[i].type != XR_TYPE_EXTENSION_PROPERTIES)
            return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, "xrEnumerateInstanceExtensionProperties",
                             "properties[%u].type is not XR_TYPE_EXTENSION_PROPERTIES", i);
        snprintf(properties[i].extensionName, sizeof(properties[i].extensionName), "%s",
                 k_extensions[i].name);
        properties[i].extensionVersion = k_extensions[i].version;
    }
    return XR_SUCCESS;
}

static void instance_free(hsrt_instance *inst)
{
    if (!inst)
        return;
    hsrt_action_sets_free(inst);
    for (uint32_t i = 0; i < inst->path_count; i++)
        free(inst->paths[i]);
    free(inst->paths);
    hs_pose_stream_destroy(&inst->poses);
    pthread_mutex_destroy(&inst->lock);
    hsrt_handle_revoke(inst->handle);
    free(inst);
}

static XrResult XRAPI_CALL hsrt_xrCreateInstance(const XrInstanceCreateInfo *createInfo,
                                                 XrInstance *instance)
{
    const char *fn = "xrCreateInstance";
    if (!createInfo || !instance || createInfo->type != XR_TYPE_INSTANCE_CREATE_INFO)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad createInfo or instance");
    XrVersion api = createInfo->applicationInfo.apiVersion;
    if (XR_VERSION_MAJOR(api) != 1 || XR_VERSION_MINOR(api) != 0)
        return hsrt_fail(XR_ERROR_API_VERSION_UNSUPPORTED, fn,
                         "application asks for OpenXR %u.%u; this runtime is 1.0",
                         (unsigned)XR_VERSION_MAJOR(api), (unsigned)XR_VERSION_MINOR(api));
    if (!createInfo->applicationInfo.applicationName[0])
        return hsrt_fail(XR_ERROR_NAME_INVALID, fn, "empty applicationName");
    /* The loader passes the application's layer names through (loader design: it has already
     * built the chain); they are the loader's business and ignored here. */
    if (createInfo->enabledApiLayerCount && !createInfo->enabledApiLayerNames)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "enabledApiLayerNames is NULL");
    hsrt_instance *inst = calloc(1, sizeof(*inst));
    if (!inst)
        return hsrt_fail(XR_ERROR_OUT_OF_MEMORY, fn, "instance");
    pthread_mutex_init(&inst->lock, NULL);
    for (uint32_t i = 0; i < createInfo->enabledExtensionCount; i++) {
        const char *e = createInfo->enabledExtensionNames[i];
        if (!strcmp(e, XR_KHR_VULKAN_ENABLE_EXTENSION_NAME))
            inst->ext_vulkan = true;
        else if (!strcmp(e, XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME))
            inst->ext_vulkan2 = true;
        else if (!strcmp(e, XR_KHR_COMPOSITION_LAYER_DEPTH_EXTENSION_NAME))
            inst->ext_depth = true;
        else if (strcmp(e, XR_EXT_DEBUG_UTILS_EXTENSION_NAME) != 0) { /* the loader's */
            instance_free(inst);
            return hsrt_fail(XR_ERROR_EXTENSION_NOT_PRESENT, fn, "extension %s is not supported", e);
        }
    }
    XrResult r = config_from_env(&inst->cfg);
    if (XR_FAILED(r)) {
        instance_free(inst);
        return r;
    }
    xrsc_diag diag = {0};
    const hs_pose_load_options lo = {.max_bytes = inst->cfg.max_pose_bytes};
    xrsc_result pr = hs_pose_stream_load_with(inst->cfg.poses_path, &lo, &inst->poses, &diag);
    if (pr != XRSC_OK || !inst->poses || !inst->poses->count) {
        char msg[1024];
        xrsc_diag_format(&diag, msg, sizeof(msg));
        instance_free(inst);
        return hsrt_fail(XR_ERROR_RUNTIME_FAILURE, fn,
                         "the pose stream (XRSC_RT_POSES) cannot be used: %s", msg);
    }
    /* XRSC_RT_START_S past the stream's end would replay clamped, identical frames. */
    int64_t duration_ns = hs_pose_stream_duration_ns(inst->poses);
    if (inst->cfg.start_ns > duration_ns) {
        double start_s = (double)inst->cfg.start_ns * 1e-9;
        instance_free(inst);
        return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, fn,
                         "XRSC_RT_START_S=%.9g s is past the end of the pose stream "
                         "(XRSC_RT_POSES), which lasts %.9g s",
                         start_s, (double)duration_ns * 1e-9);
    }
    inst->local_in_stream = local_origin_of(inst->poses);
    snprintf(inst->app_name, sizeof(inst->app_name), "%s",
             createInfo->applicationInfo.applicationName);
    U_LOG_I("runtime: instance for '%s': poses %s (%zu samples), %ux%u per eye at %.1f Hz, "
            "pace %s, frames %llu, capture %s, preview window %s",
            inst->app_name, inst->cfg.poses_path, inst->poses->count, inst->cfg.headset.width_px,
            inst->cfg.headset.height_px, (double)inst->cfg.headset.refresh_hz,
            inst->cfg.pace == HSRT_PACE_FAST ? "fast" : "realtime",
            (unsigned long long)inst->cfg.frames,
            inst->cfg.out_dir[0] ? inst->cfg.out_dir : "(off)", inst->cfg.preview ? "on" : "off");
    inst->handle = hsrt_handle_issue(inst, HSRT_HANDLE_INSTANCE);
    if (!inst->handle) {
        instance_free(inst);
        return hsrt_fail(XR_ERROR_OUT_OF_MEMORY, fn, "handle table");
    }
    *instance = HSRT_XR(XrInstance, inst->handle);
    return XR_SUCCESS;
}

static XrResult XRAPI_CALL hsrt_xrDestroyInstance(XrInstance instance)
{
    GET_INSTANCE(inst, instance, "xrDestroyInstance");
    if (inst->session) {
        XrSession s = HSRT_XR(XrSession, inst->session->handle);
        PFN_xrDestroySession destroy = (PFN_xrDestroySession)hsrt_session_proc("xrDestroySession");
        destroy(s);
    }
    instance_free(inst);
    return XR_SUCCESS;
}

static XrResult XRAPI_CALL hsrt_xrGetInstanceProperties(XrInstance instance,
                                                        XrInstanceProperties *props)
{
    GET_INSTANCE(inst, instance, "xrGetInstanceProperties");
    (void)inst;
    if (!props || props->type != XR_TYPE_INSTANCE_PROPERTIES)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, "xrGetInstanceProperties", "bad props");
    props->runtimeVersion = XR_MAKE_VERSION(0, 1, 0);
    snprintf(props->runtimeName, sizeof(props->runtimeName), "%s", HSRT_RUNTIME_NAME);
    return XR_SUCCESS;
}

static XrResult XRAPI_CALL hsrt_xrResultToString(XrInstance instance, XrResult value,
                                                 char buffer[XR_MAX_RESULT_STRING_SIZE])
{
    GET_INSTANCE(inst, instance, "xrResultToString");
    (void)inst;
    const char *name = hsrt_result_name(value);
    if (name)
        snprintf(buffer, XR_MAX_RESULT_STRING_SIZE, "%s", name);
    else
        snprintf(buffer, XR_MAX_RESULT_STRING_SIZE, "XR_UNKNOWN_%s_%d",
                 value >= 0 ? "SUCCESS" : "FAILURE", (int)value);
    return XR_SUCCESS;
}

static XrResult XRAPI_CALL hsrt_xrStructureTypeToString(XrInstance instance, XrStructureType value,
                                                        char buffer[XR_MAX_STRUCTURE_NAME_SIZE])
{
    GET_INSTANCE(inst, instance, "xrStructureTypeToString");
    (void)inst;
    const char *name = structure_type_name(value);
    if (name)
        snprintf(buffer, XR_MAX_STRUCTURE_NAME_SIZE, "%s", name);
    else
        snprintf(buffer, XR_MAX_STRUCTURE_NAME_SIZE, "XR_UNKNOWN_STRUCTURE_TYPE_%d", (int)value);
    return XR_SUCCESS;
}

/* ---- system, view configurations, blend modes ---- */

static XrResult check_system(hsrt_instance *inst, XrSystemId systemId, const char *fn)
{
    (void)inst;
    if (systemId != HSRT_SYSTEM_ID)
        return hsrt_fail(XR_ERROR_SYSTEM_INVALID, fn, "systemId %llu is not this runtime's",
                         (unsigned long long)systemId);
    return XR_SUCCESS;
}

/** This runtime's system and the only view configuration it offers (primary stereo). */
static XrResult check_stereo_system(hsrt_instance *inst, XrSystemId systemId,
                                    XrViewConfigurationType viewConfigurationType, const char *fn)
{
    XrResult r = check_system(inst, systemId, fn);
    if (XR_FAILED(r))
        return r;
    if (viewConfigurationType != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO)
        return hsrt_fail(XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED, fn, "type %d",
                         (int)viewConfigurationType);
    return XR_SUCCESS;
}

static XrResult XRAPI_CALL hsrt_xrGetSystem(XrInstance instance, const XrSystemGetInfo *getInfo,
                                            XrSystemId *systemId)
{
    GET_INSTANCE(inst, instance, "xrGetSystem");
    (void)inst;
    if (!getInfo || !systemId || getInfo->type != XR_TYPE_SYSTEM_GET_INFO)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, "xrGetSystem", "bad getInfo");
    if (getInfo->formFactor == XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY) {
        *systemId = HSRT_SYSTEM_ID;
        return XR_SUCCESS;
    }
    /* Handheld, and any value no version of OpenXR defines: not this runtime's. */
    return XR_ERROR_FORM_FACTOR_UNSUPPORTED;
}

static XrResult XRAPI_CALL hsrt_xrGetSystemProperties(XrInstance instance, XrSystemId systemId,
                                                      XrSystemProperties *properties)
{
    GET_INSTANCE(inst, instance, "xrGetSystemProperties");
    XrResult r = check_system(inst, systemId, "xrGetSystemProperties");
    if (XR_FAILED(r))
        return r;
    if (!properties || properties->type != XR_TYPE_SYSTEM_PROPERTIES)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, "xrGetSystemProperties", "bad properties");
    properties->systemId = systemId;
    properties->vendorId = 0;
    snprintf(properties->systemName, sizeof(properties->systemName),
             "xrsc simulated headset (%ux%u, %.0f Hz)", inst->cfg.headset.width_px,
             inst->cfg.headset.height_px, (double)inst->cfg.headset.refresh_hz);
    properties->graphicsProperties.maxSwapchainImageWidth = 8192;
    properties->graphicsProperties.maxSwapchainImageHeight = 8192;
    properties->graphicsProperties.maxLayerCount = XR_MIN_COMPOSITION_LAYERS_SUPPORTED;
    properties->trackingProperties.orientationTracking = XR_TRUE;
    properties->trackingProperties.positionTracking =
        inst->poses->orientation_only ? XR_FALSE : XR_TRUE;
    return XR_SUCCESS;
}

static XrResult XRAPI_CALL hsrt_xrEnumerateEnvironmentBlendModes(
    XrInstance instance, XrSystemId systemId, XrViewConfigurationType viewConfigurationType,
    uint32_t environmentBlendModeCapacityInput, uint32_t *environmentBlendModeCountOutput,
    XrEnvironmentBlendMode *environmentBlendModes)
{
    const char *fn = "xrEnumerateEnvironmentBlendModes";
    GET_INSTANCE(inst, instance, fn);
    XrResult r = check_stereo_system(inst, systemId, viewConfigurationType, fn);
    if (XR_FAILED(r))
        return r;
    if (!environmentBlendModeCountOutput)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "NULL count");
    *environmentBlendModeCountOutput = 1;
    if (!environmentBlendModeCapacityInput)
        return XR_SUCCESS;
    if (!environmentBlendModes)
        return XR_ERROR_VALIDATION_FAILURE;
    environmentBlendModes[0] = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
    return XR_SUCCESS;
}

static XrResult XRAPI_CALL hsrt_xrEnumerateViewConfigurations(
    XrInstance instance, XrSystemId systemId, uint32_t viewConfigurationTypeCapacityInput,
    uint32_t *viewConfigurationTypeCountOutput, XrViewConfigurationType *viewConfigurationTypes)
{
    const char *fn = "xrEnumerateViewConfigurations";
    GET_INSTANCE(inst, instance, fn);
    XrResult r = check_system(inst, systemId, fn);
    if (XR_FAILED(r))
        return r;
    if (!viewConfigurationTypeCountOutput)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "NULL count");
    *viewConfigurationTypeCountOutput = 1;
    if (!viewConfigurationTypeCapacityInput)
        return XR_SUCCESS;
    if (!viewConfigurationTypes)
        return XR_ERROR_VALIDATION_FAILURE;
    viewConfigurationTypes[0] = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
    return XR_SUCCESS;
}

static XrResult XRAPI_CALL hsrt_xrGetViewConfigurationProperties(
    XrInstance instance, XrSystemId systemId, XrViewConfigurationType viewConfigurationType,
    XrViewConfigurationProperties *configurationProperties)
{
    const char *fn = "xrGetViewConfigurationProperties";
    GET_INSTANCE(inst, instance, fn);
    XrResult r = check_stereo_system(inst, systemId, viewConfigurationType, fn);
    if (XR_FAILED(r))
        return r;
    if (!configurationProperties ||
        configurationProperties->type != XR_TYPE_VIEW_CONFIGURATION_PROPERTIES)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad configurationProperties");
    configurationProperties->viewConfigurationType = viewConfigurationType;
    configurationProperties->fovMutable = XR_TRUE;
    return XR_SUCCESS;
}

static XrResult XRAPI_CALL hsrt_xrEnumerateViewConfigurationViews(
    XrInstance instance, XrSystemId systemId, XrViewConfigurationType viewConfigurationType,
    uint32_t viewCapacityInput, uint32_t *viewCountOutput, XrViewConfigurationView *views)
{
    const char *fn = "xrEnumerateViewConfigurationViews";
    GET_INSTANCE(inst, instance, fn);
    XrResult r = check_stereo_system(inst, systemId, viewConfigurationType, fn);
    if (XR_FAILED(r))
        return r;
    if (!viewCountOutput)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "NULL count");
    *viewCountOutput = 2;
    if (!viewCapacityInput)
        return XR_SUCCESS;
    if (viewCapacityInput < 2 || !views)
        return XR_ERROR_SIZE_INSUFFICIENT;
    for (int i = 0; i < 2; i++) {
        if (views[i].type != XR_TYPE_VIEW_CONFIGURATION_VIEW)
            return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "views[%d].type", i);
        views[i].recommendedImageRectWidth = inst->cfg.headset.width_px;
        views[i].recommendedImageRectHeight = inst->cfg.headset.height_px;
        /* The simulated headset's panel: larger images only cost CPU rendering time (lavapipe
         * fills an 8192x8192 RGBA32F image slower than an application's fence wait). */
        views[i].maxImageRectWidth = inst->cfg.headset.width_px;
        views[i].maxImageRectHeight = inst->cfg.headset.height_px;
        views[i].recommendedSwapchainSampleCount = 1;
        views[i].maxSwapchainSampleCount = 1;
    }
    return XR_SUCCESS;
}

/* ---- xrGetInstanceProcAddr ---- */

#define HSRT_ENTRY_FUNCS(X)                                                                        \
    X(GetInstanceProcAddr) X(EnumerateApiLayerProperties) X(EnumerateInstanceExtensionProperties)  \
    X(CreateInstance) X(DestroyInstance) X(GetInstanceProperties) X(PollEvent) X(ResultToString)   \
    X(StructureTypeToString) X(GetSystem) X(GetSystemProperties)                                   \
    X(EnumerateEnvironmentBlendModes) X(EnumerateViewConfigurations)                               \
    X(GetViewConfigurationProperties) X(EnumerateViewConfigurationViews) X(StringToPath)           \
    X(PathToString)

static XrResult XRAPI_CALL hsrt_xrGetInstanceProcAddr(XrInstance instance, const char *name,
                                                      PFN_xrVoidFunction *function);

typedef struct hsrt_proc {
    const char *name;
    PFN_xrVoidFunction fn;
} hsrt_proc;

static const hsrt_proc k_entry_procs[] = {HSRT_ENTRY_FUNCS(HSRT_X_PROC)};

static XrResult XRAPI_CALL hsrt_xrGetInstanceProcAddr(XrInstance instance, const char *name,
                                                      PFN_xrVoidFunction *function)
{
    if (!function || !name)
        return XR_ERROR_VALIDATION_FAILURE;
    *function = NULL;
    if (instance == XR_NULL_HANDLE) {
        /* Only these may be looked up without an instance. */
        if (!strcmp(name, "xrEnumerateInstanceExtensionProperties"))
            *function = (PFN_xrVoidFunction)hsrt_xrEnumerateInstanceExtensionProperties;
        else if (!strcmp(name, "xrEnumerateApiLayerProperties"))
            *function = (PFN_xrVoidFunction)hsrt_xrEnumerateApiLayerProperties;
        else if (!strcmp(name, "xrCreateInstance"))
            *function = (PFN_xrVoidFunction)hsrt_xrCreateInstance;
        else if (!strcmp(name, "xrGetInstanceProcAddr"))
            *function = (PFN_xrVoidFunction)hsrt_xrGetInstanceProcAddr;
        else
            return XR_ERROR_HANDLE_INVALID;
        return XR_SUCCESS;
    }
    hsrt_instance *inst = hsrt_instance_from(instance);
    if (!inst)
        return hsrt_fail(XR_ERROR_HANDLE_INVALID, "xrGetInstanceProcAddr",
                         "not an XrInstance of this runtime (looking up %s)", name);
    for (size_t i = 0; i < sizeof(k_entry_procs) / sizeof(k_entry_procs[0]); i++) {
        if (!strcmp(name, k_entry_procs[i].name)) {
            *function = k_entry_procs[i].fn;
            return XR_SUCCESS;
        }
    }
    PFN_xrVoidFunction f = hsrt_session_proc(name);
    if (f) {
        *function = f;
        return XR_SUCCESS;
    }
    int ext = 0;
    f = hsrt_vulkan_proc(name, &ext);
    if (f && (ext == 0 || (ext == 1 && inst->ext_vulkan) || (ext == 2 && inst->ext_vulkan2))) {
        *function = f;
        return XR_SUCCESS;
    }
    return XR_ERROR_FUNCTION_UNSUPPORTED;
}

XrResult XRAPI_CALL xrNegotiateLoaderRuntimeInterface(const XrNegotiateLoaderInfo *loaderInfo,
                                                      XrNegotiateRuntimeRequest *runtimeRequest)
{
    const char *fn = "xrNegotiateLoaderRuntimeInterface";
    if (!loaderInfo || loaderInfo->structType != XR_LOADER_INTERFACE_STRUCT_LOADER_INFO ||
        loaderInfo->structVersion != XR_LOADER_INFO_STRUCT_VERSION ||
        loaderInfo->structSize != sizeof(XrNegotiateLoaderInfo))
        return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, fn, "unexpected loader info");
    if (!runtimeRequest || runtimeRequest->structType != XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST ||
        runtimeRequest->structVersion != XR_RUNTIME_INFO_STRUCT_VERSION ||
        runtimeRequest->structSize != sizeof(XrNegotiateRuntimeRequest))
        return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, fn, "unexpected runtime request");
    if (loaderInfo->minInterfaceVersion > XR_CURRENT_LOADER_RUNTIME_VERSION ||
        loaderInfo->maxInterfaceVersion < XR_CURRENT_LOADER_RUNTIME_VERSION)
        return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, fn,
                         "loader interface versions %u..%u exclude 1",
                         loaderInfo->minInterfaceVersion, loaderInfo->maxInterfaceVersion);
    XrVersion ours = XR_MAKE_VERSION(1, 0, XR_VERSION_PATCH(XR_CURRENT_API_VERSION));
    if (XR_VERSION_MAJOR(loaderInfo->maxApiVersion) < 1 ||
        loaderInfo->minApiVersion > XR_MAKE_VERSION(1, 0, 0xffffffffu))
        return hsrt_fail(XR_ERROR_INITIALIZATION_FAILED, fn, "loader API versions exclude 1.0");
    runtimeRequest->runtimeInterfaceVersion = XR_CURRENT_LOADER_RUNTIME_VERSION;
    runtimeRequest->runtimeApiVersion = ours;
    runtimeRequest->getInstanceProcAddr = hsrt_xrGetInstanceProcAddr;
    return XR_SUCCESS;
}
