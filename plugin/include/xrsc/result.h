// SPDX-License-Identifier: MIT
/**
 * @file result.h
 * @brief One result enum for all of xrsc, generated with its names from one X-macro list.
 *
 * 0 is success, negative values are errors, positive values are warnings (never returned by a
 * function: recorded where the API says, e.g. a loaded scene's warning list). Tests assert on
 * these IDs, never on message text.
 * Errors about input carry the file, line and field in an ::xrsc_diag.
 */
#pragma once

#ifdef __cplusplus
extern "C" {
#endif

/* X(name, value, short description) */
#define XRSC_RESULT_LIST(X)                                                                        \
    X(XRSC_OK, 0, "success")                                                                       \
    X(XRSC_ERROR_INVALID_ARGUMENT, -1, "invalid argument")                                         \
    X(XRSC_ERROR_OUT_OF_MEMORY, -2, "out of host memory")                                          \
    X(XRSC_ERROR_IO, -3, "file cannot be opened, read or written")                                 \
    X(XRSC_ERROR_EMPTY_FILE, -4, "file is empty")                                                  \
    X(XRSC_ERROR_FILE_TOO_LARGE, -5, "file is larger than the documented limit")                   \
    X(XRSC_ERROR_TRUNCATED_LINE, -6, "line has fewer fields than its columns")                     \
    X(XRSC_ERROR_UNKNOWN_COLUMN, -7, "unknown column or record type")                              \
    X(XRSC_ERROR_BAD_NUMBER, -8, "field is not a number")                                          \
    X(XRSC_ERROR_NAN, -9, "field is NaN or infinite")                                              \
    X(XRSC_ERROR_QUAT_NOT_UNIT, -10, "quaternion is not of unit length")                           \
    X(XRSC_ERROR_TIME_BACKWARDS, -11, "timestamp goes backwards")                                  \
    X(XRSC_ERROR_BAD_HEADER, -12, "missing or unsupported format header")                          \
    X(XRSC_ERROR_GLTF_PARSE, -13, "glTF file cannot be parsed")                                    \
    X(XRSC_ERROR_GLTF_MISSING_BUFFER, -14, "glTF buffer or image file is missing")                 \
    X(XRSC_ERROR_GLTF_UNSUPPORTED, -15, "glTF uses a required feature xrsc cannot render")         \
    X(XRSC_ERROR_GLTF_INVALID, -16, "glTF data is inconsistent (indices, accessors, nodes)")       \
    X(XRSC_ERROR_NO_RAY_TRACING_DEVICE, -17, "no Vulkan device with ray-tracing pipelines")        \
    X(XRSC_ERROR_VULKAN, -18, "a Vulkan call failed")                                              \
    X(XRSC_ERROR_SHADER, -19, "a SPIR-V shader module cannot be loaded")                           \
    X(XRSC_ERROR_UNKNOWN_METHOD, -20, "unknown rendering method")                                  \
    X(XRSC_ERROR_DEVICE_NOT_FOUND, -21, "the requested Vulkan device does not exist")          \
    X(XRSC_ERROR_XR, -22, "an OpenXR call failed")                                                 \
    X(XRSC_ERROR_XR_RUNTIME_UNAVAILABLE, -23, "no OpenXR runtime (see XR_RUNTIME_JSON)")           \
    X(XRSC_ERROR_XR_SESSION_LOST, -24, "the OpenXR runtime lost the session or instance")         \
    XRSC_RESULT_LIST_LOADER(X)                                                                     \
    XRSC_RESULT_LIST_RUN(X)                                                                        \
    XRSC_RESULT_LIST_CLIPS(X)

/* Scene loader (issue 18): bad-file errors found before the bytes reach tinygltf, and
 * warnings (positive: the load succeeds) that a scene records in sc_scene.warning_ids. */
#define XRSC_RESULT_LIST_LOADER(X)                                                                 \
    X(XRSC_ERROR_GLTF_NOT_GLTF, -40, "file is not glTF 2.0 (another format)")                      \
    X(XRSC_ERROR_GLTF_VERSION, -41, "glTF asset.version is not 2.x (glTF 1.0 is not read)")       \
    X(XRSC_ERROR_GLB_MAGIC, -42, "GLB file does not start with the magic 'glTF'")                  \
    X(XRSC_ERROR_GLB_TRUNCATED, -43, "GLB file is shorter than its header or chunks say")          \
    X(XRSC_WARN_GLTF_IMAGE_MISSING, 40, "glTF image file is missing: neutral stand-in used")       \
    X(XRSC_WARN_GLTF_IMAGE_UNDECODABLE, 41, "glTF image cannot be decoded: neutral stand-in used") \
    X(XRSC_WARN_GLTF_PRIMITIVE_SKIPPED, 42, "glTF points or lines primitives skipped")             \
    X(XRSC_WARN_GLTF_EXTENSION_IGNORED, 43, "optional glTF extension ignored")

/* A replay's run (issue 23): warnings are positive (the run goes on), printed with their ID. */
#define XRSC_RESULT_LIST_RUN(X)                                                                    \
    X(XRSC_WARN_FRAMES_PAST_END, 60, "--frames runs past the pose stream: its last pose is held")

/* Animation clips (issue 21): the clip a user picks (--animation). */
#define XRSC_RESULT_LIST_CLIPS(X)                                                                  \
    X(XRSC_ERROR_ANIMATION_UNKNOWN, -80, "--animation names no clip of the scene (name or index)")

typedef enum xrsc_result {
#define XRSC_X_ENUM(name, value, text) name = value,
    XRSC_RESULT_LIST(XRSC_X_ENUM)
#undef XRSC_X_ENUM
} xrsc_result;

/** The enumerator's name, e.g. "XRSC_ERROR_NAN"; "XRSC_RESULT_UNKNOWN" for other values. */
const char *xrsc_result_name(xrsc_result result);
/** A short English description of the result. */
const char *xrsc_result_text(xrsc_result result);

/**
 * Where and why an operation failed. Filled by functions that take an `xrsc_diag *out_diag`
 * (which may be NULL). `line` is 1-based, 0 when not applicable; `field` names the column,
 * JSON member or setting that was wrong ("" when none).
 */
typedef struct xrsc_diag {
    xrsc_result code;
    char file[512];
    int line;
    char field[96];
    char message[512];
} xrsc_diag;

/** Formats "file:line: field: message [ID]" into buf (always terminated). Returns buf. */
char *xrsc_diag_format(const xrsc_diag *diag, char *buf, unsigned long buf_size);

#ifdef __cplusplus
}
#endif
