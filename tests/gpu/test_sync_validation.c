// SPDX-License-Identifier: MIT
/**
 * @file test_sync_validation.c
 * @brief The validated context turns synchronization validation on and counts its hazards as
 *        errors: two fills of one buffer without a barrier fail, with one they pass (issue 20).
 *
 * lavapipe runs a command buffer's commands one after another, so a missing barrier never
 * changes an image here; only synchronization validation sees it. Every GPU test runs under
 * the same context (t_context.h, gpu_context_create with validation), so this test is what
 * makes "any future hazard fails a test" true.
 */
#include "gpu_context.h"
#include "gpu_resource.h"
#include "testing.h"

#include <stdio.h>

#define T_BUFFER_BYTES 256u

/** Records two fills of one buffer, with or without a barrier between, submits and waits;
 *  returns the validation errors the submission added (UINT32_MAX when it could not run). */
static uint32_t errors_of_two_fills(gpu_context *gpu, const gpu_buffer *buf, bool barrier)
{
    uint32_t before = gpu->validation_errors;
    VkCommandBuffer cmd;
    if (gpu_cmd_begin(gpu, &cmd, NULL) != XRSC_OK)
        return UINT32_MAX;
    vkCmdFillBuffer(cmd, buf->buffer, 0, VK_WHOLE_SIZE, 0);
    if (barrier)
        gpu_cmd_barrier_all(cmd);
    vkCmdFillBuffer(cmd, buf->buffer, 0, T_BUFFER_BYTES / 2, 1);
    if (gpu_cmd_submit_wait(gpu, cmd, NULL) != XRSC_OK)
        return UINT32_MAX;
    return gpu->validation_errors - before;
}

/** A validated context; NULL (the case skipped) when the validation layer is not installed. */
static gpu_context *open_validated(void)
{
    gpu_context_options go = {.validation = true};
    gpu_context *gpu = NULL;
    xrsc_diag diag;
    char text[1024];
    xrsc_result r = gpu_context_create(&go, &gpu, &diag);
    CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&diag, text, sizeof(text)));
    if (r == XRSC_OK && !gpu->validation) {
        printf("skipped: VK_LAYER_KHRONOS_validation is not installed\n");
        gpu_context_destroy(&gpu);
    }
    return gpu;
}

static void test_missing_barrier_is_an_error(void)
{
    gpu_context *gpu = open_validated();
    if (!gpu)
        return;
    gpu_buffer buf = {0};
    CHECK_EQ_INT(gpu_buffer_create_storage(gpu, T_BUFFER_BYTES, &buf, NULL), XRSC_OK);
    if (buf.buffer) {
        uint32_t errors = errors_of_two_fills(gpu, &buf, false);
        /* exactly the one SYNC-HAZARD-WRITE-AFTER-WRITE of the second fill */
        CHECK_MSG(errors == 1, "%u validation errors, expected the one hazard", errors);
    }
    gpu_buffer_destroy(gpu, &buf);
    gpu_context_destroy(&gpu);
}

static void test_barrier_passes(void)
{
    gpu_context *gpu = open_validated();
    if (!gpu)
        return;
    gpu_buffer buf = {0};
    CHECK_EQ_INT(gpu_buffer_create_storage(gpu, T_BUFFER_BYTES, &buf, NULL), XRSC_OK);
    if (buf.buffer) {
        CHECK_EQ_INT(errors_of_two_fills(gpu, &buf, true), 0);
        /* the next submission writes again: the fence wait orders it after the last */
        CHECK_EQ_INT(errors_of_two_fills(gpu, &buf, true), 0);
    }
    gpu_buffer_destroy(gpu, &buf);
    CHECK_EQ_INT(gpu->validation_errors, 0);
    gpu_context_destroy(&gpu);
}

int main(void)
{
    RUN(test_missing_barrier_is_an_error);
    RUN(test_barrier_passes);
    return t_finish();
}
