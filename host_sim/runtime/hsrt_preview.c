// SPDX-License-Identifier: MIT
/**
 * @file hsrt_preview.c
 * @brief The optional preview window (XRSC_RT_PREVIEW=1, `xrsc replay --preview`): the
 *        submitted eyes in a GLFW window presented through a Vulkan swapchain, with an overlay
 *        (frame, stream time, ms, method, blend, R), views (side by side, one eye, the
 *        depth-compensated stereo difference, the error against a reference), stepping back
 *        through recent frames, pause, single step and exit.
 *
 * Design. The window has a Vulkan instance, device and swapchain of its own, owned by one
 * thread of its own; it never touches the application's VkInstance or VkDevice. The frames
 * it shows are the ones xrEndFrame already reads back to host memory (hsrt_vk_capture, the
 * same display-referred sRGB bytes the PNGs hold, their linear values, and the depth of a
 * depth layer): the thread composes the picture on the CPU (hsrt_preview_view.c) into a
 * host-visible buffer at the window's size and copies that buffer into the acquired swapchain
 * image (vkCmdCopyBufferToImage, so the swapchain only needs TRANSFER_DST usage; no pipeline,
 * no shaders). Why not present on the application's device: the application created it, so
 * the surface and swapchain extensions would have to be forced into its create infos
 * (xrCreateVulkanInstanceKHR could, XR_KHR_vulkan_enable could not), presenting would share
 * its queue, and a device that cannot present to the display (NVIDIA under Xvfb) would lose
 * the preview. A separate device needs none of that; it defaults to the CPU device (lavapipe)
 * when that can present, because the work is one copy and a CPU device presents to any X
 * server. XRSC_RT_PREVIEW_DEVICE picks another (cpu, gpu, an index or part of a name).
 *
 * Overlay information. OpenXR carries no method names or timings, so the application may
 * send them on a pipe whose read end XRSC_RT_PREVIEW_INFO_FD names (hs_preview_link.h: lines
 * "run method=M blend=B r=R" and "frame N ms=X pass=ms ..."); the preview thread reads it
 * without blocking and keeps the last HSRT_PREVIEW_INFO_SLOTS frames' lines.
 *
 * Threads. The preview thread alone calls GLFW (glfwInit to glfwTerminate) and its Vulkan
 * objects. The application's threads meet it only through this struct's mutex: xrEndFrame
 * hands over a frame (hsrt_preview_submit: queued, then moved into the history, so stepping
 * back shows every frame of the last XRSC_RT_PREVIEW_HISTORY, shown or not), xrWaitFrame
 * blocks while paused (hsrt_preview_wait), and both take a pending exit request
 * (hsrt_preview_take_exit). The preview thread never takes the instance's lock, so a session
 * can be destroyed (joining the thread, after the window is closed unless autoclose) while
 * holding it. GLFW's state is process-wide: one preview at a time per process (a second
 * session meanwhile runs without one), and an application that uses GLFW itself must not
 * enable the preview.
 *
 * Keys: P or Space pause/resume; N or Right while paused lets one frame through (while running
 * it pauses; while stepped back it steps forward); B or Left steps back through the history
 * (pausing); V cycles the views, 1 side by side, 2 left eye, 3 right eye, D the stereo
 * difference, E the reference error; S swaps the eyes; O the overlay; Esc, Q or closing the
 * window requests exit (the session walks down to STOPPING, as xrRequestExitSession). The
 * title shows the frame on screen, the state and the view.
 */
#include "hsrt_instance.h"
#include "hsrt_preview_view.h"

#include "hs_image.h"
#include "u_diag.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#if HSRT_HAVE_GLFW
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#endif

/** How long the preview thread sleeps in glfwWaitEventsTimeout between housekeeping. */
#define HSRT_PREVIEW_POLL_S 0.1
/** How long one draw waits for a swapchain image, so that closing never hangs on it. */
#define HSRT_PREVIEW_ACQUIRE_TIMEOUT_NS 250000000ull
/** Frames whose overlay lines are kept (a ring indexed by frame number). */
#define HSRT_PREVIEW_INFO_SLOTS 256u
/** Longest line of the information channel; longer ones are dropped. */
#define HSRT_PREVIEW_INFO_LINE 1100u

/* ---- the shared part: frames handed over, pause, exit ---- */

struct hsrt_preview {
    hsrt_preview_options opt;
    pthread_t thread;
    bool thread_started;
    pthread_mutex_t lock;
    pthread_cond_t cond; /**< startup finished; pause, step, exit or the run's end changed */
    /* under lock */
    bool ready, failed, quit;
    bool broken; /**< presenting failed: never pause again, so the frame loop cannot hang */
    bool paused, swapped, overlay;
    hsrt_view view;
    uint32_t back;             /**< frames behind the newest of the history on screen */
    bool ended;                /**< the session has ended; the window waits to be closed */
    bool autoclose;            /**< opt.autoclose, or asked for on the information channel */
    bool exit_requested;       /**< by a key or the window; stays set */
    bool exit_pending;         /**< not yet taken by the session */
    uint32_t steps;            /**< single steps granted while paused */
    hsrt_preview_frame *queue; /**< handed over, not yet in the history: q_count from q_first */
    uint32_t q_first, q_count;
    size_t q_bytes;
    /* preview thread only */
    hsrt_preview_frame *ring; /**< the history: ring_count frames from ring_first, oldest first */
    uint32_t ring_first, ring_count;
    size_t ring_bytes;
    hsrt_preview_run_info run;
    hsrt_preview_frame_info info[HSRT_PREVIEW_INFO_SLOTS];
    uint64_t info_frame[HSRT_PREVIEW_INFO_SLOTS];
    char line[HSRT_PREVIEW_INFO_LINE];
    size_t line_len;
    bool line_overflow;
    hsrt_eye_image reference[2]; /**< of reference_frame, rgba only */
    int64_t reference_frame;     /**< -1: none loaded */
    bool reference_ok;
    hsrt_view_cache diff_cache; /**< the last stereo difference computed */
    bool dirty;
    char title[192];
#if HSRT_HAVE_GLFW
    GLFWwindow *win;
    struct {
        VkInstance instance;
        VkDebugUtilsMessengerEXT messenger;
        VkSurfaceKHR surface;
        VkPhysicalDevice physical;
        VkDevice device;
        VkQueue queue;
        uint32_t family;
        VkCommandPool pool;
        VkCommandBuffer cmd;
        VkFence fence;
        bool fence_pending;
        VkSemaphore acquired;
        VkSwapchainKHR swapchain;
        VkFormat format;
        VkExtent2D extent;
        uint32_t image_count;
        VkImage images[8];
        VkSemaphore rendered[8];
        VkBuffer staging;
        VkDeviceMemory staging_mem;
        VkDeviceSize staging_size;
        void *staging_map;
        bool staging_coherent;
        uint32_t validation_errors;
    } vk;
#endif
};

/** One preview per process: GLFW's state is process-wide. */
static pthread_mutex_t g_preview_owner_lock = PTHREAD_MUTEX_INITIALIZER;
static bool g_preview_owned;

/** Bytes of a frame's pixels (sRGB, linear RGBA and depth of both eyes). */
static size_t frame_bytes(const hsrt_preview_frame *f)
{
    size_t b = 0;
    for (int e = 0; e < 2; e++)
        b += (size_t)f->eyes[e].w * f->eyes[e].h * (3 + 4 * sizeof(float) + sizeof(float));
    return b;
}

void hsrt_preview_submit(hsrt_preview *p, hsrt_preview_frame *frame)
{
    pthread_mutex_lock(&p->lock);
    uint32_t cap = p->opt.history;
    size_t bytes = frame_bytes(frame);
    /* A window that fell behind (by a history, or its bytes) loses the oldest frames. */
    while (p->q_count && (p->q_count == cap || p->q_bytes + bytes > HSRT_PREVIEW_HISTORY_BYTES)) {
        p->q_bytes -= frame_bytes(&p->queue[p->q_first]);
        hsrt_preview_frame_free(&p->queue[p->q_first]);
        p->q_first = (p->q_first + 1) % cap;
        p->q_count--;
    }
    uint64_t n = frame->frame;
    p->queue[(p->q_first + p->q_count++) % cap] = *frame;
    p->q_bytes += bytes;
    memset(frame, 0, sizeof(*frame));
    if (p->opt.hold_frame >= 0 && n == (uint64_t)p->opt.hold_frame && !p->exit_requested &&
        !p->broken) {
        p->paused = true;
        p->steps = 0;
        U_LOG_I("runtime: preview: holding at frame %llu (XRSC_RT_PREVIEW_HOLD_FRAME)",
                (unsigned long long)n);
    }
#if HSRT_HAVE_GLFW
    if (!p->quit)
        glfwPostEmptyEvent(); /* under the lock: the thread terminates GLFW only after quit */
#endif
    pthread_mutex_unlock(&p->lock);
}

int64_t hsrt_preview_wait(hsrt_preview *p)
{
    XrTime t0 = hsrt_now_ns();
    pthread_mutex_lock(&p->lock);
    while (p->paused && !p->steps && !p->exit_requested && !p->quit)
        pthread_cond_wait(&p->cond, &p->lock);
    if (p->paused && p->steps)
        p->steps--;
    pthread_mutex_unlock(&p->lock);
    return hsrt_now_ns() - t0;
}

bool hsrt_preview_take_exit(hsrt_preview *p)
{
    pthread_mutex_lock(&p->lock);
    bool e = p->exit_pending;
    p->exit_pending = false;
    pthread_mutex_unlock(&p->lock);
    return e;
}

#if HSRT_HAVE_GLFW

/* ---- the history and the overlay's information (preview thread) ---- */

static hsrt_preview_frame *ring_at(hsrt_preview *p, uint32_t back)
{
    if (back >= p->ring_count)
        return NULL;
    uint32_t cap = p->opt.history;
    return &p->ring[(p->ring_first + p->ring_count - 1 - back) % cap];
}

/** Takes a frame into the history, dropping the oldest past the count or byte limit. */
static void ring_push(hsrt_preview *p, hsrt_preview_frame *f)
{
    uint32_t cap = p->opt.history;
    size_t bytes = frame_bytes(f);
    while (p->ring_count &&
           (p->ring_count == cap || p->ring_bytes + bytes > HSRT_PREVIEW_HISTORY_BYTES)) {
        hsrt_preview_frame *old = &p->ring[p->ring_first];
        p->ring_bytes -= frame_bytes(old);
        hsrt_preview_frame_free(old);
        p->ring_first = (p->ring_first + 1) % cap;
        p->ring_count--;
    }
    p->ring[(p->ring_first + p->ring_count) % cap] = *f;
    memset(f, 0, sizeof(*f));
    p->ring_count++;
    p->ring_bytes += bytes;
}

/** One line of the information channel (hs_preview_link.h); unknown words are skipped. */
static void parse_info_line(hsrt_preview *p, char *line)
{
    char *save = NULL, *w = strtok_r(line, " ", &save);
    if (!w)
        return;
    if (!strcmp(w, "run")) {
        hsrt_preview_run_info r = {.has = true};
        while ((w = strtok_r(NULL, " ", &save))) {
            if (!strncmp(w, "method=", 7))
                snprintf(r.method, sizeof(r.method), "%s", w + 7);
            else if (!strncmp(w, "blend=", 6))
                snprintf(r.blend, sizeof(r.blend), "%s", w + 6);
            else if (!strncmp(w, "r=", 2))
                r.r = strtod(w + 2, NULL);
        }
        p->run = r;
        p->dirty = true;
        return;
    }
    if (!strcmp(w, "autoclose") || !strcmp(w, "stop")) {
        pthread_mutex_lock(&p->lock);
        p->autoclose = true;
        if (!strcmp(w, "stop")) { /* the application was interrupted: never hold it */
            p->paused = false;
            p->opt.hold_frame = -1;
        }
        pthread_cond_broadcast(&p->cond);
        pthread_mutex_unlock(&p->lock);
        p->dirty = true;
        return;
    }
    if (strcmp(w, "frame") || !(w = strtok_r(NULL, " ", &save)))
        return;
    uint64_t frame = strtoull(w, NULL, 10);
    hsrt_preview_frame_info fi = {.has = true};
    while ((w = strtok_r(NULL, " ", &save))) {
        char *eq = strchr(w, '=');
        if (!eq)
            continue;
        *eq = '\0';
        if (!strcmp(w, "ms")) {
            fi.ms = strtod(eq + 1, NULL);
        } else if (fi.pass_count < HSRT_PREVIEW_MAX_PASSES) {
            snprintf(fi.pass_name[fi.pass_count], sizeof(fi.pass_name[0]), "%s", w);
            fi.pass_ms[fi.pass_count++] = strtod(eq + 1, NULL);
        }
    }
    p->info[frame % HSRT_PREVIEW_INFO_SLOTS] = fi;
    p->info_frame[frame % HSRT_PREVIEW_INFO_SLOTS] = frame;
    p->dirty = true; /* the frame on screen may be this one */
}

/** Reads what the information channel has (never blocks). */
static void read_info(hsrt_preview *p)
{
    if (p->opt.info_fd < 0)
        return;
    char buf[4096];
    ssize_t n;
    while ((n = read(p->opt.info_fd, buf, sizeof(buf))) > 0) {
        for (ssize_t i = 0; i < n; i++) {
            if (buf[i] != '\n') {
                if (p->line_len + 1 < sizeof(p->line))
                    p->line[p->line_len++] = buf[i];
                else
                    p->line_overflow = true;
                continue;
            }
            p->line[p->line_len] = '\0';
            if (!p->line_overflow)
                parse_info_line(p, p->line);
            p->line_len = 0;
            p->line_overflow = false;
        }
    }
}

static const hsrt_preview_frame_info *info_of(const hsrt_preview *p, uint64_t frame)
{
    uint32_t k = (uint32_t)(frame % HSRT_PREVIEW_INFO_SLOTS);
    return p->info[k].has && p->info_frame[k] == frame ? &p->info[k] : NULL;
}

/** The reference frames of `f`'s number (loaded once per number); NULL if there are none. */
static const hsrt_eye_image *reference_of(hsrt_preview *p, const hsrt_preview_frame *f)
{
    if (!p->opt.reference[0] || !f)
        return NULL;
    if (p->reference_frame != (int64_t)f->frame) {
        p->reference_frame = (int64_t)f->frame;
        p->reference_ok = true;
        for (int e = 0; e < 2; e++) {
            hsrt_eye_image_free(&p->reference[e]);
            char path[1200];
            snprintf(path, sizeof(path), "%s/frame_%05llu_%s.pfm", p->opt.reference,
                     (unsigned long long)f->frame, e ? "right" : "left");
            xrsc_diag d = {0};
            hsrt_eye_image *r = &p->reference[e];
            p->reference_ok = p->reference_ok &&
                              hs_read_pfm(path, &r->rgba, &r->w, &r->h, &d) == XRSC_OK &&
                              r->w == f->eyes[e].w && r->h == f->eyes[e].h;
        }
        if (!p->reference_ok)
            U_LOG_W("runtime: preview: no reference frame %llu of the eyes' size in %s",
                    (unsigned long long)f->frame, p->opt.reference);
    }
    return p->reference_ok ? p->reference : NULL;
}

/* ---- the preview thread: GLFW and Vulkan ---- */

#define PV_VK(call, what)                                                                          \
    do {                                                                                           \
        VkResult vr_ = (call);                                                                     \
        if (vr_ != VK_SUCCESS) {                                                                   \
            U_LOG_E("runtime: preview: %s failed with VkResult %d", what, (int)vr_);               \
            return false;                                                                          \
        }                                                                                          \
    } while (0)

static void glfw_error(int code, const char *msg)
{
    U_LOG_E("runtime: preview: GLFW error 0x%x: %s", code, msg);
}

static VKAPI_ATTR VkBool32 VKAPI_CALL pv_debug(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                               VkDebugUtilsMessageTypeFlagsEXT type,
                                               const VkDebugUtilsMessengerCallbackDataEXT *data,
                                               void *user)
{
    (void)type;
    hsrt_preview *p = user;
    if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        p->vk.validation_errors++;
        U_LOG_E("runtime: preview: Vulkan validation: %s", data->pMessage);
    } else {
        U_LOG_W("runtime: preview: Vulkan validation: %s", data->pMessage);
    }
    return VK_FALSE;
}

static bool has_layer(const char *name)
{
    uint32_t n = 0;
    if (vkEnumerateInstanceLayerProperties(&n, NULL) != VK_SUCCESS || !n)
        return false;
    VkLayerProperties *props = calloc(n, sizeof(*props));
    bool found = false;
    if (props && vkEnumerateInstanceLayerProperties(&n, props) == VK_SUCCESS) {
        for (uint32_t i = 0; i < n && !found; i++)
            found = !strcmp(props[i].layerName, name);
    }
    free(props);
    return found;
}

static bool create_instance(hsrt_preview *p)
{
    uint32_t glfw_count = 0;
    const char **glfw_ext = glfwGetRequiredInstanceExtensions(&glfw_count);
    if (!glfw_ext) {
        U_LOG_E("runtime: preview: GLFW found no Vulkan surface support for this display");
        return false;
    }
    const char *ext[16];
    uint32_t n = 0;
    for (uint32_t i = 0; i < glfw_count && n < 15; i++)
        ext[n++] = glfw_ext[i];
    const char *layers[1];
    uint32_t layer_count = 0;
    const char *val = getenv("XRSC_VALIDATION");
    bool validation = val && !strcmp(val, "1") && has_layer("VK_LAYER_KHRONOS_validation");
    if (validation) {
        layers[layer_count++] = "VK_LAYER_KHRONOS_validation";
        ext[n++] = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
    }
    VkApplicationInfo app = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
                             .pApplicationName = "xrsc runtime preview",
                             .apiVersion = VK_API_VERSION_1_1};
    VkDebugUtilsMessengerCreateInfoEXT mci = {
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
        .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT |
                           VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT,
        .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT,
        .pfnUserCallback = pv_debug,
        .pUserData = p};
    VkInstanceCreateInfo ici = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
                                .pNext = validation ? &mci : NULL,
                                .pApplicationInfo = &app,
                                .enabledLayerCount = layer_count,
                                .ppEnabledLayerNames = layers,
                                .enabledExtensionCount = n,
                                .ppEnabledExtensionNames = ext};
    PV_VK(vkCreateInstance(&ici, NULL, &p->vk.instance), "vkCreateInstance");
    if (validation) {
        PFN_vkCreateDebugUtilsMessengerEXT create =
            (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
                p->vk.instance, "vkCreateDebugUtilsMessengerEXT");
        if (create)
            PV_VK(create(p->vk.instance, &mci, NULL, &p->vk.messenger),
                  "vkCreateDebugUtilsMessengerEXT");
    }
    return true;
}

/** Picks a device and queue family that can present to the window's surface. */
static bool pick_device(hsrt_preview *p)
{
    uint32_t n = 0;
    PV_VK(vkEnumeratePhysicalDevices(p->vk.instance, &n, NULL), "vkEnumeratePhysicalDevices");
    VkPhysicalDevice devs[16];
    n = n > 16 ? 16 : n;
    VkResult vr = vkEnumeratePhysicalDevices(p->vk.instance, &n, devs);
    if (vr != VK_SUCCESS && vr != VK_INCOMPLETE)
        PV_VK(vr, "vkEnumeratePhysicalDevices");
    const char *want = p->opt.device;
    int best = -1, best_score = 0;
    uint32_t best_family = 0;
    for (uint32_t i = 0; i < n; i++) {
        VkPhysicalDeviceProperties props;
        vkGetPhysicalDeviceProperties(devs[i], &props);
        uint32_t nf = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(devs[i], &nf, NULL);
        VkQueueFamilyProperties fams[16];
        nf = nf > 16 ? 16 : nf;
        vkGetPhysicalDeviceQueueFamilyProperties(devs[i], &nf, fams);
        int family = -1;
        for (uint32_t f = 0; f < nf && family < 0; f++) {
            VkBool32 present = VK_FALSE;
            if (!(fams[f].queueFlags &
                  (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT | VK_QUEUE_TRANSFER_BIT)))
                continue;
            if (vkGetPhysicalDeviceSurfaceSupportKHR(devs[i], f, p->vk.surface, &present) ==
                    VK_SUCCESS &&
                present)
                family = (int)f;
        }
        bool is_cpu = props.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
        int score;
        switch (props.deviceType) {
        case VK_PHYSICAL_DEVICE_TYPE_CPU:
            score = 4;
            break; /* see the file comment */
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
            score = 3;
            break;
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
            score = 2;
            break;
        default:
            score = 1;
            break;
        }
        if (!strcmp(want, "cpu"))
            score = is_cpu ? 10 : 0;
        else if (!strcmp(want, "gpu"))
            score = is_cpu ? 0 : score;
        else if (want[0] && strspn(want, "0123456789") == strlen(want))
            score = (uint32_t)atoi(want) == i ? 10 : 0;
        else if (want[0])
            score = strstr(props.deviceName, want) ? 10 : 0;
        U_LOG_D("runtime: preview: device %u %s: present %s, score %d", i, props.deviceName,
                family >= 0 ? "yes" : "no", score);
        if (family >= 0 && score > best_score) {
            best = (int)i;
            best_score = score;
            best_family = (uint32_t)family;
        }
    }
    if (best < 0) {
        U_LOG_E("runtime: preview: no Vulkan device can present to the window%s%s%s",
                want[0] ? " (XRSC_RT_PREVIEW_DEVICE='" : "", want, want[0] ? "')" : "");
        return false;
    }
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(devs[best], &props);
    U_LOG_I("runtime: preview: presenting with %s", props.deviceName);
    p->vk.physical = devs[best];
    p->vk.family = best_family;
    return true;
}

static bool create_device(hsrt_preview *p)
{
    float prio = 1.0f;
    VkDeviceQueueCreateInfo qci = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
                                   .queueFamilyIndex = p->vk.family,
                                   .queueCount = 1,
                                   .pQueuePriorities = &prio};
    const char *ext[] = {VK_KHR_SWAPCHAIN_EXTENSION_NAME};
    VkDeviceCreateInfo dci = {.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
                              .queueCreateInfoCount = 1,
                              .pQueueCreateInfos = &qci,
                              .enabledExtensionCount = 1,
                              .ppEnabledExtensionNames = ext};
    PV_VK(vkCreateDevice(p->vk.physical, &dci, NULL, &p->vk.device), "vkCreateDevice");
    vkGetDeviceQueue(p->vk.device, p->vk.family, 0, &p->vk.queue);
    VkCommandPoolCreateInfo pci = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                   .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
                                   .queueFamilyIndex = p->vk.family};
    PV_VK(vkCreateCommandPool(p->vk.device, &pci, NULL, &p->vk.pool), "vkCreateCommandPool");
    VkCommandBufferAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
                                      .commandPool = p->vk.pool,
                                      .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                      .commandBufferCount = 1};
    PV_VK(vkAllocateCommandBuffers(p->vk.device, &ai, &p->vk.cmd), "vkAllocateCommandBuffers");
    VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    PV_VK(vkCreateFence(p->vk.device, &fci, NULL, &p->vk.fence), "vkCreateFence");
    VkSemaphoreCreateInfo sci = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    PV_VK(vkCreateSemaphore(p->vk.device, &sci, NULL, &p->vk.acquired), "vkCreateSemaphore");
    return true;
}

static void destroy_swapchain(hsrt_preview *p)
{
    for (uint32_t i = 0; i < p->vk.image_count; i++) {
        if (p->vk.rendered[i])
            vkDestroySemaphore(p->vk.device, p->vk.rendered[i], NULL);
        p->vk.rendered[i] = VK_NULL_HANDLE;
    }
    if (p->vk.swapchain)
        vkDestroySwapchainKHR(p->vk.device, p->vk.swapchain, NULL);
    p->vk.swapchain = VK_NULL_HANDLE;
    p->vk.image_count = 0;
}

/** (Re)creates the swapchain at the framebuffer's size; false with extent 0 when minimised. */
/* Waits for the last frame and the presents still using the swapchain, drops its
 * semaphores; returns it, detached from p (the new one is created from it). */
static VkSwapchainKHR swapchain_detach(hsrt_preview *p)
{
    if (p->vk.fence_pending) {
        vkWaitForFences(p->vk.device, 1, &p->vk.fence, VK_TRUE, UINT64_MAX);
        vkResetFences(p->vk.device, 1, &p->vk.fence);
        p->vk.fence_pending = false;
    }
    vkQueueWaitIdle(p->vk.queue); /* the presents that still wait on `rendered` semaphores */
    VkSwapchainKHR old = p->vk.swapchain;
    p->vk.swapchain = VK_NULL_HANDLE;
    for (uint32_t i = 0; i < p->vk.image_count; i++) {
        vkDestroySemaphore(p->vk.device, p->vk.rendered[i], NULL);
        p->vk.rendered[i] = VK_NULL_HANDLE;
    }
    p->vk.image_count = 0;
    p->vk.extent = (VkExtent2D){0, 0};
    return old;
}

/* The surface's extent, or the framebuffer's clamped to the surface's limits. */
static VkExtent2D surface_extent(const VkSurfaceCapabilitiesKHR *caps, int fw, int fh)
{
    VkExtent2D ext = caps->currentExtent;
    if (ext.width != UINT32_MAX)
        return ext;
    uint32_t w = (uint32_t)(fw > 0 ? fw : 0), h = (uint32_t)(fh > 0 ? fh : 0);
    w = w < caps->minImageExtent.width ? caps->minImageExtent.width : w;
    w = w > caps->maxImageExtent.width ? caps->maxImageExtent.width : w;
    h = h < caps->minImageExtent.height ? caps->minImageExtent.height : h;
    h = h > caps->maxImageExtent.height ? caps->maxImageExtent.height : h;
    return (VkExtent2D){w, h};
}

/* An 8-bit RGBA/BGRA sRGB-colour-space format of the surface (format UNDEFINED: none). The
 * bytes copied are display sRGB values: a UNORM format stores them as they are; an _SRGB
 * format would too (copies do not convert), but UNORM says what is meant. */
static VkSurfaceFormatKHR choose_format(const hsrt_preview *p)
{
    uint32_t nf = 0;
    vkGetPhysicalDeviceSurfaceFormatsKHR(p->vk.physical, p->vk.surface, &nf, NULL);
    VkSurfaceFormatKHR fmts[64];
    nf = nf > 64 ? 64 : nf;
    vkGetPhysicalDeviceSurfaceFormatsKHR(p->vk.physical, p->vk.surface, &nf, fmts);
    static const VkFormat prefer[] = {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM,
                                      VK_FORMAT_B8G8R8A8_SRGB, VK_FORMAT_R8G8B8A8_SRGB};
    for (size_t k = 0; k < sizeof(prefer) / sizeof(prefer[0]); k++)
        for (uint32_t i = 0; i < nf; i++)
            if (fmts[i].format == prefer[k] &&
                fmts[i].colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR)
                return fmts[i];
    return (VkSurfaceFormatKHR){VK_FORMAT_UNDEFINED, VK_COLOR_SPACE_SRGB_NONLINEAR_KHR};
}

/* Mailbox when the surface has it, else FIFO (always there). */
static VkPresentModeKHR choose_present_mode(const hsrt_preview *p)
{
    uint32_t nm = 0;
    vkGetPhysicalDeviceSurfacePresentModesKHR(p->vk.physical, p->vk.surface, &nm, NULL);
    VkPresentModeKHR modes[16];
    nm = nm > 16 ? 16 : nm;
    vkGetPhysicalDeviceSurfacePresentModesKHR(p->vk.physical, p->vk.surface, &nm, modes);
    for (uint32_t i = 0; i < nm; i++)
        if (modes[i] == VK_PRESENT_MODE_MAILBOX_KHR)
            return modes[i];
    return VK_PRESENT_MODE_FIFO_KHR;
}

/* The new swapchain's images and a `rendered` semaphore for each. */
static bool fetch_images(hsrt_preview *p)
{
    uint32_t ni = 0;
    PV_VK(vkGetSwapchainImagesKHR(p->vk.device, p->vk.swapchain, &ni, NULL),
          "vkGetSwapchainImagesKHR");
    if (ni > 8) {
        U_LOG_E("runtime: preview: %u swapchain images (at most 8 handled)", ni);
        return false;
    }
    PV_VK(vkGetSwapchainImagesKHR(p->vk.device, p->vk.swapchain, &ni, p->vk.images),
          "vkGetSwapchainImagesKHR");
    VkSemaphoreCreateInfo semi = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    for (uint32_t i = 0; i < ni; i++) {
        PV_VK(vkCreateSemaphore(p->vk.device, &semi, NULL, &p->vk.rendered[i]),
              "vkCreateSemaphore");
        p->vk.image_count = i + 1;
    }
    return true;
}

static bool create_swapchain(hsrt_preview *p)
{
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(p->win, &fw, &fh);
    VkSwapchainKHR old = swapchain_detach(p);
    VkSurfaceCapabilitiesKHR caps;
    VkResult vr = vkGetPhysicalDeviceSurfaceCapabilitiesKHR(p->vk.physical, p->vk.surface, &caps);
    VkExtent2D ext = vr == VK_SUCCESS ? surface_extent(&caps, fw, fh) : (VkExtent2D){0, 0};
    VkSurfaceFormatKHR chosen = choose_format(p);
    bool minimised = vr == VK_SUCCESS && (!ext.width || !ext.height);
    bool usable = vr == VK_SUCCESS && !minimised &&
                  (caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT) && chosen.format;
    if (!usable) {
        if (old)
            vkDestroySwapchainKHR(p->vk.device, old, NULL);
        PV_VK(vr, "vkGetPhysicalDeviceSurfaceCapabilitiesKHR");
        if (minimised)
            return true; /* nothing to present to */
        if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
            U_LOG_E("runtime: preview: the surface's images cannot be transfer destinations");
        else
            U_LOG_E("runtime: preview: the surface offers no 8-bit RGBA/BGRA sRGB format");
        return false;
    }
    VkPresentModeKHR mode = choose_present_mode(p);
    uint32_t count = caps.minImageCount + 1;
    if (caps.maxImageCount && count > caps.maxImageCount)
        count = caps.maxImageCount;
    VkSwapchainCreateInfoKHR sci = {.sType = VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR,
                                    .surface = p->vk.surface,
                                    .minImageCount = count,
                                    .imageFormat = chosen.format,
                                    .imageColorSpace = chosen.colorSpace,
                                    .imageExtent = ext,
                                    .imageArrayLayers = 1,
                                    .imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                                    .imageSharingMode = VK_SHARING_MODE_EXCLUSIVE,
                                    .preTransform = caps.currentTransform,
                                    .compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR,
                                    .presentMode = mode,
                                    .clipped = VK_TRUE,
                                    .oldSwapchain = old};
    if (!(caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR))
        sci.compositeAlpha = VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR;
    vr = vkCreateSwapchainKHR(p->vk.device, &sci, NULL, &p->vk.swapchain);
    if (old)
        vkDestroySwapchainKHR(p->vk.device, old, NULL);
    PV_VK(vr, "vkCreateSwapchainKHR");
    if (!fetch_images(p))
        return false;
    p->vk.format = chosen.format;
    p->vk.extent = ext;
    U_LOG_D("runtime: preview: swapchain %ux%u, %u images, format %d, present mode %d", ext.width,
            ext.height, p->vk.image_count, (int)chosen.format, (int)mode);
    return true;
}

static void staging_free(hsrt_preview *p)
{
    if (p->vk.staging_map)
        vkUnmapMemory(p->vk.device, p->vk.staging_mem);
    if (p->vk.staging)
        vkDestroyBuffer(p->vk.device, p->vk.staging, NULL);
    if (p->vk.staging_mem)
        vkFreeMemory(p->vk.device, p->vk.staging_mem, NULL);
    p->vk.staging_map = NULL;
    p->vk.staging = VK_NULL_HANDLE;
    p->vk.staging_mem = VK_NULL_HANDLE;
    p->vk.staging_size = 0;
}

static bool ensure_staging(hsrt_preview *p, VkDeviceSize size)
{
    if (p->vk.staging_size >= size)
        return true;
    staging_free(p);
    VkBufferCreateInfo bci = {.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
                              .size = size,
                              .usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                              .sharingMode = VK_SHARING_MODE_EXCLUSIVE};
    PV_VK(vkCreateBuffer(p->vk.device, &bci, NULL, &p->vk.staging), "vkCreateBuffer");
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(p->vk.device, p->vk.staging, &req);
    VkPhysicalDeviceMemoryProperties mp;
    vkGetPhysicalDeviceMemoryProperties(p->vk.physical, &mp);
    int type = -1;
    for (int pass = 0; pass < 2 && type < 0; pass++) {
        VkMemoryPropertyFlags want = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                     (pass == 0 ? VK_MEMORY_PROPERTY_HOST_COHERENT_BIT : 0);
        for (uint32_t i = 0; i < mp.memoryTypeCount && type < 0; i++) {
            if ((req.memoryTypeBits & (1u << i)) &&
                (mp.memoryTypes[i].propertyFlags & want) == want)
                type = (int)i;
        }
    }
    if (type < 0) {
        U_LOG_E("runtime: preview: no host-visible memory for the staging buffer");
        return false;
    }
    p->vk.staging_coherent =
        (mp.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT) != 0;
    VkMemoryAllocateInfo mai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                                .allocationSize = req.size,
                                .memoryTypeIndex = (uint32_t)type};
    PV_VK(vkAllocateMemory(p->vk.device, &mai, NULL, &p->vk.staging_mem), "vkAllocateMemory");
    PV_VK(vkBindBufferMemory(p->vk.device, p->vk.staging, p->vk.staging_mem, 0),
          "vkBindBufferMemory");
    PV_VK(vkMapMemory(p->vk.device, p->vk.staging_mem, 0, VK_WHOLE_SIZE, 0, &p->vk.staging_map),
          "vkMapMemory");
    p->vk.staging_size = size;
    return true;
}

/** Composes the current picture and presents it; false on a Vulkan failure. */
/* Composes the picture into the staging buffer, copies it into swapchain image index and
 * submits that (waiting for the acquisition, signalling the image's `rendered`). */
static bool submit_picture(hsrt_preview *p, const hsrt_preview_frame *f,
                           const hsrt_view_state *vs, uint32_t index)
{
    uint32_t w = p->vk.extent.width, h = p->vk.extent.height;
    if (!ensure_staging(p, (VkDeviceSize)w * h * 4))
        return false;
    bool bgra =
        p->vk.format == VK_FORMAT_B8G8R8A8_UNORM || p->vk.format == VK_FORMAT_B8G8R8A8_SRGB;
    if (!hsrt_view_compose(f, vs, p->vk.staging_map, w, h, bgra)) {
        U_LOG_E("runtime: preview: out of memory composing the picture");
        return false;
    }
    if (!p->vk.staging_coherent) {
        VkMappedMemoryRange mr = {.sType = VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE,
                                  .memory = p->vk.staging_mem,
                                  .size = VK_WHOLE_SIZE};
        vkFlushMappedMemoryRanges(p->vk.device, 1, &mr);
    }
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                   .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    PV_VK(vkResetCommandBuffer(p->vk.cmd, 0), "vkResetCommandBuffer");
    PV_VK(vkBeginCommandBuffer(p->vk.cmd, &bi), "vkBeginCommandBuffer");
    VkImageMemoryBarrier b = {.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
                              .srcAccessMask = 0,
                              .dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                              .oldLayout = VK_IMAGE_LAYOUT_UNDEFINED,
                              .newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                              .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                              .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                              .image = p->vk.images[index],
                              .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1}};
    vkCmdPipelineBarrier(p->vk.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, NULL, 0, NULL, 1, &b);
    VkBufferImageCopy copy = {.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
                              .imageExtent = {w, h, 1}};
    vkCmdCopyBufferToImage(p->vk.cmd, p->vk.staging, p->vk.images[index],
                           VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
    b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    b.dstAccessMask = 0;
    b.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    b.newLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
    vkCmdPipelineBarrier(p->vk.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0, 0, NULL, 0, NULL, 1, &b);
    PV_VK(vkEndCommandBuffer(p->vk.cmd), "vkEndCommandBuffer");
    VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_TRANSFER_BIT;
    VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
                       .waitSemaphoreCount = 1,
                       .pWaitSemaphores = &p->vk.acquired,
                       .pWaitDstStageMask = &wait_stage,
                       .commandBufferCount = 1,
                       .pCommandBuffers = &p->vk.cmd,
                       .signalSemaphoreCount = 1,
                       .pSignalSemaphores = &p->vk.rendered[index]};
    PV_VK(vkQueueSubmit(p->vk.queue, 1, &si, p->vk.fence), "vkQueueSubmit");
    p->vk.fence_pending = true;
    return true;
}

static bool draw(hsrt_preview *p, const hsrt_preview_frame *f, const hsrt_view_state *vs)
{
    for (int attempt = 0; attempt < 2; attempt++) {
        if (!p->vk.swapchain && !create_swapchain(p))
            return false;
        if (!p->vk.swapchain)
            return true; /* minimised */
        if (p->vk.fence_pending) {
            PV_VK(vkWaitForFences(p->vk.device, 1, &p->vk.fence, VK_TRUE, UINT64_MAX),
                  "vkWaitForFences");
            PV_VK(vkResetFences(p->vk.device, 1, &p->vk.fence), "vkResetFences");
            p->vk.fence_pending = false;
        }
        uint32_t index = 0;
        VkResult vr =
            vkAcquireNextImageKHR(p->vk.device, p->vk.swapchain, HSRT_PREVIEW_ACQUIRE_TIMEOUT_NS,
                                  p->vk.acquired, VK_NULL_HANDLE, &index);
        if (vr == VK_TIMEOUT || vr == VK_NOT_READY) {
            p->dirty = true; /* no image free yet (e.g. an unmapped window): try again later */
            return true;
        }
        if (vr == VK_ERROR_OUT_OF_DATE_KHR) {
            if (!create_swapchain(p))
                return false;
            continue;
        }
        if (vr != VK_SUCCESS && vr != VK_SUBOPTIMAL_KHR)
            PV_VK(vr, "vkAcquireNextImageKHR");
        if (!submit_picture(p, f, vs, index))
            return false;
        VkPresentInfoKHR pi = {.sType = VK_STRUCTURE_TYPE_PRESENT_INFO_KHR,
                               .waitSemaphoreCount = 1,
                               .pWaitSemaphores = &p->vk.rendered[index],
                               .swapchainCount = 1,
                               .pSwapchains = &p->vk.swapchain,
                               .pImageIndices = &index};
        vr = vkQueuePresentKHR(p->vk.queue, &pi);
        if (vr == VK_ERROR_OUT_OF_DATE_KHR || vr == VK_SUBOPTIMAL_KHR) {
            /* shown or not, the next draw starts on a swapchain of the new size */
            if (!create_swapchain(p))
                return false;
            if (vr == VK_ERROR_OUT_OF_DATE_KHR)
                continue;
            return true;
        }
        if (vr != VK_SUCCESS)
            PV_VK(vr, "vkQueuePresentKHR");
        return true;
    }
    return true;
}

static void vk_destroy(hsrt_preview *p)
{
    if (p->vk.device) {
        vkDeviceWaitIdle(p->vk.device);
        destroy_swapchain(p);
        staging_free(p);
        if (p->vk.acquired)
            vkDestroySemaphore(p->vk.device, p->vk.acquired, NULL);
        if (p->vk.fence)
            vkDestroyFence(p->vk.device, p->vk.fence, NULL);
        if (p->vk.pool)
            vkDestroyCommandPool(p->vk.device, p->vk.pool, NULL);
        vkDestroyDevice(p->vk.device, NULL);
    }
    if (p->vk.instance) {
        if (p->vk.surface)
            vkDestroySurfaceKHR(p->vk.instance, p->vk.surface, NULL);
        if (p->vk.messenger) {
            PFN_vkDestroyDebugUtilsMessengerEXT destroy =
                (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
                    p->vk.instance, "vkDestroyDebugUtilsMessengerEXT");
            if (destroy)
                destroy(p->vk.instance, p->vk.messenger, NULL);
        }
        vkDestroyInstance(p->vk.instance, NULL);
    }
    if (p->vk.validation_errors)
        U_LOG_E("runtime: preview: %u Vulkan validation errors", p->vk.validation_errors);
    memset(&p->vk, 0, sizeof(p->vk));
}

/* ---- input (on the preview thread, inside glfwWaitEventsTimeout) ---- */

static void request_exit_locked(hsrt_preview *p)
{
    if (!p->exit_requested) {
        p->exit_requested = true;
        p->exit_pending = true;
        U_LOG_I("runtime: preview: exit requested");
    }
    pthread_cond_broadcast(&p->cond);
}

/** The view keys (under the lock); false for other keys. */
static bool view_key(hsrt_preview *p, int key)
{
    switch (key) {
    case GLFW_KEY_S:
        p->swapped = !p->swapped;
        break;
    case GLFW_KEY_D:
        p->view = p->view == HSRT_VIEW_STEREO_DIFF ? HSRT_VIEW_SBS : HSRT_VIEW_STEREO_DIFF;
        break;
    case GLFW_KEY_E:
        p->view = p->view == HSRT_VIEW_REF_ERROR ? HSRT_VIEW_SBS : HSRT_VIEW_REF_ERROR;
        break;
    case GLFW_KEY_V:
        p->view = (hsrt_view)((p->view + 1) % HSRT_VIEW_COUNT);
        break;
    case GLFW_KEY_1:
    case GLFW_KEY_2:
    case GLFW_KEY_3:
        p->view = key == GLFW_KEY_1   ? HSRT_VIEW_SBS
                  : key == GLFW_KEY_2 ? HSRT_VIEW_LEFT
                                      : HSRT_VIEW_RIGHT;
        break;
    case GLFW_KEY_O:
        p->overlay = !p->overlay;
        break;
    default:
        return false;
    }
    return true;
}

static void on_key(GLFWwindow *win, int key, int scancode, int action, int mods)
{
    (void)scancode;
    (void)mods;
    if (action != GLFW_PRESS && action != GLFW_REPEAT)
        return;
    hsrt_preview *p = glfwGetWindowUserPointer(win);
    pthread_mutex_lock(&p->lock);
    switch (key) {
    case GLFW_KEY_P:
    case GLFW_KEY_SPACE: /* (keys arrive only while the thread runs its loop: never broken) */
        if (action == GLFW_PRESS) {
            p->paused = !p->paused;
            p->steps = 0;
            if (!p->paused)
                p->back = 0;
        }
        break;
    case GLFW_KEY_N:
    case GLFW_KEY_RIGHT:
        if (p->back)
            p->back--;
        else if (p->paused)
            p->steps++;
        else
            p->paused = true;
        break;
    case GLFW_KEY_B:
    case GLFW_KEY_LEFT:
        if (p->back + 1 < p->ring_count) /* ring_count: this thread's own */
            p->back++;
        p->paused = true;
        break;
    case GLFW_KEY_ESCAPE:
    case GLFW_KEY_Q:
        request_exit_locked(p);
        break;
    default:
        if (action != GLFW_PRESS || !view_key(p, key)) {
            pthread_mutex_unlock(&p->lock);
            return;
        }
        break;
    }
    p->dirty = true;
    pthread_cond_broadcast(&p->cond);
    pthread_mutex_unlock(&p->lock);
}

static void on_refresh(GLFWwindow *win)
{
    hsrt_preview *p = glfwGetWindowUserPointer(win);
    p->dirty = true; /* only the preview thread reads it outside the lock */
}

static void on_resize(GLFWwindow *win, int w, int h)
{
    (void)w;
    (void)h;
    hsrt_preview *p = glfwGetWindowUserPointer(win);
    p->dirty = true;
    if (p->vk.swapchain)
        create_swapchain(p); /* a failure leaves no swapchain; draw() tries again */
}

static bool thread_init(hsrt_preview *p)
{
    glfwSetErrorCallback(glfw_error);
    if (!glfwInit()) {
        U_LOG_E("runtime: preview: glfwInit failed (is DISPLAY set to a running X server?)");
        return false;
    }
    if (!glfwVulkanSupported()) {
        U_LOG_E("runtime: preview: GLFW finds no Vulkan loader");
        return false;
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    snprintf(p->title, sizeof(p->title), "xrsc preview: waiting for a frame");
    p->win = glfwCreateWindow((int)p->opt.width, (int)p->opt.height, p->title, NULL, NULL);
    if (!p->win)
        return false;
    glfwSetWindowUserPointer(p->win, p);
    glfwSetKeyCallback(p->win, on_key);
    glfwSetWindowRefreshCallback(p->win, on_refresh);
    glfwSetFramebufferSizeCallback(p->win, on_resize);
    if (!create_instance(p))
        return false;
    VkResult vr = glfwCreateWindowSurface(p->vk.instance, p->win, NULL, &p->vk.surface);
    if (vr != VK_SUCCESS) {
        U_LOG_E("runtime: preview: glfwCreateWindowSurface failed with VkResult %d", (int)vr);
        return false;
    }
    return pick_device(p) && create_device(p) && create_swapchain(p);
}

/** A snapshot of what the loop draws, taken under the lock. */
typedef struct pv_snapshot {
    bool paused, swapped, overlay, exiting, ended;
    hsrt_view view;
    uint32_t back;
} pv_snapshot;

static const char *state_name(const pv_snapshot *s)
{
    return s->ended ? "ended" : s->exiting ? "exiting" : s->paused ? "paused" : "running";
}

/* Moves the handed-over frames into the history; a viewer stepped back keeps its frame. */
static void take_pending_locked(hsrt_preview *p)
{
    for (; p->q_count; p->q_count--) {
        p->q_bytes -= frame_bytes(&p->queue[p->q_first]);
        ring_push(p, &p->queue[p->q_first]);
        p->q_first = (p->q_first + 1) % p->opt.history;
        if (p->back && p->back + 1 < p->ring_count)
            p->back++;
        else if (p->back)
            p->back = p->ring_count - 1;
        p->dirty = true;
    }
}

/* Draws the snapshot and sets the title; false when presenting failed. */
static bool present(hsrt_preview *p, const pv_snapshot *s)
{
    const hsrt_preview_frame *f = ring_at(p, s->back);
    hsrt_view_state vs = {.view = s->view,
                          .swapped = s->swapped,
                          .overlay = s->overlay,
                          .state = state_name(s),
                          .back = s->back,
                          .run = &p->run,
                          .info = f ? info_of(p, f->frame) : NULL,
                          .has_reference = p->opt.reference[0] != '\0',
                          .cache = &p->diff_cache};
    if (s->view == HSRT_VIEW_REF_ERROR)
        vs.reference = reference_of(p, f);
    if (!draw(p, f, &vs))
        return false;
    /* The title names what is on screen now (tests read it to know when to look). */
    char title[sizeof(p->title)];
    if (f)
        snprintf(title, sizeof(title), "xrsc preview: frame %llu, %s, %s%s",
                 (unsigned long long)f->frame, vs.state, hsrt_view_name(f, &vs),
                 s->back ? ", stepped back" : "");
    else
        snprintf(title, sizeof(title), "xrsc preview: waiting for a frame");
    if (strcmp(title, p->title)) {
        snprintf(p->title, sizeof(p->title), "%s", title);
        glfwSetWindowTitle(p->win, p->title);
    }
    return true;
}

static void *preview_thread(void *arg)
{
    hsrt_preview *p = arg;
    bool ok = thread_init(p);
    pthread_mutex_lock(&p->lock);
    p->ready = ok;
    p->failed = !ok;
    pthread_cond_broadcast(&p->cond);
    pthread_mutex_unlock(&p->lock);
    p->dirty = true;
    pv_snapshot last = {0};
    while (ok) {
        glfwWaitEventsTimeout(HSRT_PREVIEW_POLL_S);
        read_info(p);
        pthread_mutex_lock(&p->lock);
        if (glfwWindowShouldClose(p->win)) {
            glfwSetWindowShouldClose(p->win, GLFW_FALSE);
            request_exit_locked(p);
        }
        if (p->quit) {
            pthread_mutex_unlock(&p->lock);
            break;
        }
        take_pending_locked(p);
        pv_snapshot s = {p->paused, p->swapped, p->overlay, p->exit_requested,
                         p->ended,  p->view,    p->back};
        pthread_mutex_unlock(&p->lock);
        if (memcmp(&s, &last, sizeof(s)))
            p->dirty = true;
        last = s;
        if (!p->dirty)
            continue;
        p->dirty = false;
        if (!present(p, &s)) {
            U_LOG_E("runtime: preview: presenting failed; the window stops updating");
            pthread_mutex_lock(&p->lock);
            p->broken = true;
            p->paused = false; /* nothing could resume it any more */
            pthread_cond_broadcast(&p->cond);
            pthread_mutex_unlock(&p->lock);
            break;
        }
    }
    /* Wait for quit if presenting failed, so the session's calls keep working. */
    pthread_mutex_lock(&p->lock);
    while (ok && !p->quit)
        pthread_cond_wait(&p->cond, &p->lock);
    pthread_mutex_unlock(&p->lock);
    vk_destroy(p);
    if (p->win)
        glfwDestroyWindow(p->win);
    p->win = NULL;
    glfwTerminate();
    glfwSetErrorCallback(NULL);
    return NULL;
}

#endif /* HSRT_HAVE_GLFW */

static void release_owner(void)
{
    pthread_mutex_lock(&g_preview_owner_lock);
    g_preview_owned = false;
    pthread_mutex_unlock(&g_preview_owner_lock);
}

XrResult hsrt_preview_create(const hsrt_preview_options *opt, hsrt_preview **out)
{
    const char *fn = "xrCreateSession (XRSC_RT_PREVIEW)";
    *out = NULL;
#if !HSRT_HAVE_GLFW
    (void)opt;
    return hsrt_fail(XR_ERROR_RUNTIME_FAILURE, fn,
                     "this runtime was built without GLFW (libglfw3-dev): no preview window");
#else
    pthread_mutex_lock(&g_preview_owner_lock);
    bool taken = g_preview_owned;
    g_preview_owned = true;
    pthread_mutex_unlock(&g_preview_owner_lock);
    if (taken) {
        U_LOG_W("runtime: preview: another session of this process shows the preview; this one "
                "runs without");
        return XR_SUCCESS;
    }
    hsrt_preview *p = calloc(1, sizeof(*p));
    uint32_t history = opt->history ? opt->history : HSRT_PREVIEW_HISTORY_DEFAULT;
    hsrt_preview_frame *ring = calloc(history, sizeof(*ring));
    hsrt_preview_frame *queue = calloc(history, sizeof(*queue));
    if (!p || !ring || !queue) {
        free(p);
        free(ring);
        free(queue);
        release_owner();
        return hsrt_fail(XR_ERROR_OUT_OF_MEMORY, fn, "preview");
    }
    p->opt = *opt;
    p->opt.history = history;
    p->ring = ring;
    p->queue = queue;
    p->swapped = opt->swapped;
    p->view = opt->diff ? HSRT_VIEW_STEREO_DIFF : HSRT_VIEW_SBS;
    p->overlay = !opt->no_overlay;
    p->autoclose = opt->autoclose;
    p->reference_frame = -1;
    /* Never block on the channel: the application's end may stay open and quiet. */
    if (opt->info_fd >= 0 &&
        fcntl(opt->info_fd, F_SETFL, fcntl(opt->info_fd, F_GETFL) | O_NONBLOCK) != 0) {
        U_LOG_W("runtime: preview: XRSC_RT_PREVIEW_INFO_FD %d: %s; no overlay information",
                opt->info_fd, strerror(errno));
        p->opt.info_fd = -1;
    }
    pthread_mutex_init(&p->lock, NULL);
    pthread_cond_init(&p->cond, NULL);
    int err = pthread_create(&p->thread, NULL, preview_thread, p);
    if (err) {
        hsrt_preview_destroy(&p);
        return hsrt_fail(XR_ERROR_RUNTIME_FAILURE, fn, "pthread_create: %s", strerror(err));
    }
    p->thread_started = true;
    pthread_mutex_lock(&p->lock);
    while (!p->ready && !p->failed)
        pthread_cond_wait(&p->cond, &p->lock);
    bool failed = p->failed;
    pthread_mutex_unlock(&p->lock);
    if (failed) {
        hsrt_preview_destroy(&p);
        return hsrt_fail(XR_ERROR_RUNTIME_FAILURE, fn,
                         "the preview window could not be opened (errors above); unset "
                         "XRSC_RT_PREVIEW to run headless");
    }
    U_LOG_I("runtime: preview: window %ux%u (P/Space pause, N/Right step, B/Left back, V/1/2/3 "
            "views, D stereo difference, E reference error, S swap, O overlay, Esc/Q exit)",
            opt->width, opt->height);
    *out = p;
    return XR_SUCCESS;
#endif
}

/* The end of the run stays on screen until the window is closed (unless autoclose). */
static void wait_until_closed(hsrt_preview *p)
{
    pthread_mutex_lock(&p->lock);
    if (p->ready && !p->autoclose && !p->exit_requested && !p->broken) {
        p->ended = true;
        p->paused = false;
        U_LOG_I("runtime: preview: the session has ended; the window stays open until it is "
                "closed (Esc, Q or its close button; XRSC_RT_PREVIEW_AUTOCLOSE=1 or "
                "--preview-autoclose close it at once)");
#if HSRT_HAVE_GLFW
        glfwPostEmptyEvent();
#endif
        while (!p->exit_requested && !p->broken && !p->autoclose)
            pthread_cond_wait(&p->cond, &p->lock);
    }
    pthread_mutex_unlock(&p->lock);
}

void hsrt_preview_destroy(hsrt_preview **pp)
{
    if (!pp || !*pp)
        return;
    hsrt_preview *p = *pp;
    *pp = NULL;
    if (p->thread_started) {
        wait_until_closed(p);
        pthread_mutex_lock(&p->lock);
        p->quit = true;
#if HSRT_HAVE_GLFW
        if (p->ready)
            glfwPostEmptyEvent();
#endif
        pthread_cond_broadcast(&p->cond);
        pthread_mutex_unlock(&p->lock);
        pthread_join(p->thread, NULL);
        pthread_mutex_destroy(&p->lock);
        pthread_cond_destroy(&p->cond);
    }
    for (uint32_t k = 0; p->ring && k < p->opt.history; k++) {
        hsrt_preview_frame_free(&p->ring[k]);
        hsrt_preview_frame_free(&p->queue[k]);
    }
    free(p->queue);
    for (int e = 0; e < 2; e++)
        hsrt_eye_image_free(&p->reference[e]);
    hsrt_view_cache_free(&p->diff_cache);
    free(p->ring);
    free(p);
    release_owner();
}
