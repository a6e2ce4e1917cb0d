// SPDX-License-Identifier: MIT
/**
 * @file hsrt_handle.c
 * @brief The table of the handles this runtime has issued: an application's handle is looked
 *        up as a number, never dereferenced, so a stale or made-up value fails cleanly.
 *
 * OpenXR asks a runtime to answer XR_ERROR_HANDLE_INVALID for any value it did not issue (the
 * CTS's `-H` passes destroyed handles and values such as 0x1234). An XrInstance has no context
 * to look it up in, so the table is process-wide: the runtime's second piece of process state,
 * beside the preview's GLFW flag (CONVENTIONS.md). Values are never reused: bits 8..55 count
 * issued handles, bits 0..7 say the type, and a tag in the top byte keeps them far from small
 * integers and from pointers.
 */
#include "hsrt.h"

#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#define HSRT_HANDLE_TAG (0x58ull << 56)

typedef struct hsrt_handle_entry {
    uint64_t value;
    void *object;
} hsrt_handle_entry;

/* Sorted by value: values only grow, so issuing appends. */
static struct {
    pthread_mutex_t lock;
    hsrt_handle_entry *entries;
    size_t count, cap;
    uint64_t issued;
} g_handles = {.lock = PTHREAD_MUTEX_INITIALIZER};

/** Index of value in the table, or -1 (locked). */
static ptrdiff_t find(uint64_t value)
{
    size_t lo = 0, hi = g_handles.count;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        uint64_t v = g_handles.entries[mid].value;
        if (v == value)
            return (ptrdiff_t)mid;
        if (v < value)
            lo = mid + 1;
        else
            hi = mid;
    }
    return -1;
}

uint64_t hsrt_handle_issue(void *object, hsrt_handle_type type)
{
    uint64_t value = 0;
    pthread_mutex_lock(&g_handles.lock);
    if (g_handles.count == g_handles.cap) {
        size_t cap = g_handles.cap ? g_handles.cap * 2 : 64;
        hsrt_handle_entry *grown = realloc(g_handles.entries, cap * sizeof(*grown));
        if (!grown)
            goto out;
        g_handles.entries = grown;
        g_handles.cap = cap;
    }
    value = HSRT_HANDLE_TAG | (++g_handles.issued << 8) | (uint64_t)type;
    g_handles.entries[g_handles.count++] = (hsrt_handle_entry){value, object};
out:
    pthread_mutex_unlock(&g_handles.lock);
    return value;
}

void *hsrt_handle_get(uint64_t value, hsrt_handle_type type)
{
    if ((value & 0xffu) != (uint64_t)type || (value & (0xffull << 56)) != HSRT_HANDLE_TAG)
        return NULL;
    pthread_mutex_lock(&g_handles.lock);
    ptrdiff_t i = find(value);
    void *object = i >= 0 ? g_handles.entries[i].object : NULL;
    pthread_mutex_unlock(&g_handles.lock);
    return object;
}

void hsrt_handle_revoke(uint64_t value)
{
    pthread_mutex_lock(&g_handles.lock);
    ptrdiff_t i = find(value);
    if (i >= 0) {
        memmove(&g_handles.entries[i], &g_handles.entries[i + 1],
                (g_handles.count - (size_t)i - 1) * sizeof(g_handles.entries[0]));
        g_handles.count--;
    }
    if (!g_handles.count) { /* the last handle is gone: give the memory back */
        free(g_handles.entries);
        g_handles.entries = NULL;
        g_handles.cap = 0;
    }
    pthread_mutex_unlock(&g_handles.lock);
}
