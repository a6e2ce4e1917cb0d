// SPDX-License-Identifier: MIT
/**
 * @file u_device.c
 * @brief The Vulkan device selector shared by the plugin and host_sim's runtime (u_device.h).
 */
#include "u_device.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

static bool contains_ci(const char *hay, const char *needle)
{
    size_t n = strlen(needle);
    for (; *hay; hay++) {
        size_t i = 0;
        while (i < n && hay[i] &&
               tolower((unsigned char)hay[i]) == tolower((unsigned char)needle[i]))
            i++;
        if (i == n)
            return true;
    }
    return n == 0;
}

static bool is_index(const char *s)
{
    if (!*s)
        return false;
    for (; *s; s++)
        if (!isdigit((unsigned char)*s))
            return false;
    return true;
}

bool u_device_matches(const char *selector, uint32_t index, const char *name, bool is_cpu)
{
    if (!selector || !*selector)
        return true;
    if (!strcmp(selector, "cpu"))
        return is_cpu;
    if (!strcmp(selector, "gpu"))
        return !is_cpu;
    if (is_index(selector))
        return strtoul(selector, NULL, 10) == index;
    return contains_ci(name ? name : "", selector);
}

int32_t u_device_select(const char *selector, uint32_t n, const char *const *names,
                        const bool *is_cpu, const bool *usable, bool *out_any_match)
{
    bool any = false;
    int32_t pick = -1;
    if (!selector || !*selector) {
        any = n > 0;
        for (int want_cpu = 0; want_cpu < 2 && pick < 0; want_cpu++)
            for (uint32_t i = 0; i < n && pick < 0; i++)
                if (is_cpu[i] == (bool)want_cpu && usable[i])
                    pick = (int32_t)i;
    } else {
        for (uint32_t i = 0; i < n && pick < 0; i++) {
            if (!u_device_matches(selector, i, names[i], is_cpu[i]))
                continue;
            any = true;
            if (usable[i])
                pick = (int32_t)i;
        }
    }
    if (out_any_match)
        *out_any_match = any;
    return pick;
}
