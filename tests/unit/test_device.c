// SPDX-License-Identifier: MIT
/**
 * @file test_device.c
 * @brief The Vulkan device selector (u_device.h) that the plugin's --device / XRSC_DEVICE and
 *        the runtime's XRSC_RT_DEVICE share: matching and the choice among matches.
 */
#include "testing.h"
#include "u_device.h"

static const char *const k_names[] = {"llvmpipe (LLVM 15.0.6, 256 bits)",
                                      "NVIDIA GeForce RTX 4090", "Intel(R) UHD Graphics 770",
                                      "NVIDIA H100"};
static const bool k_cpu[] = {true, false, false, false};

static void test_matches(void)
{
    CHECK(u_device_matches(NULL, 0, k_names[0], true));
    CHECK(u_device_matches("", 3, k_names[3], false));
    CHECK(u_device_matches("cpu", 0, k_names[0], true));
    CHECK(!u_device_matches("cpu", 1, k_names[1], false));
    CHECK(u_device_matches("gpu", 1, k_names[1], false));
    CHECK(!u_device_matches("gpu", 0, k_names[0], true));
    CHECK(u_device_matches("2", 2, k_names[2], false));
    CHECK(!u_device_matches("2", 1, k_names[1], false));
    CHECK(u_device_matches("nvidia", 1, k_names[1], false)); /* case ignored */
    CHECK(u_device_matches("RTX", 1, k_names[1], false));
    CHECK(!u_device_matches("rtx", 3, k_names[3], false));
    CHECK(u_device_matches("LLVMPIPE", 0, k_names[0], true));
}

static void test_select(void)
{
    const bool all[] = {true, true, true, true};
    const bool rt_cpu_h100[] = {true, false, false, true};
    const bool none[] = {false, false, false, false};
    bool any = false;
    /* No selector: the first usable non-CPU device, else the CPU one. */
    CHECK_EQ_INT(u_device_select(NULL, 4, k_names, k_cpu, all, &any), 1);
    CHECK(any);
    CHECK_EQ_INT(u_device_select("", 4, k_names, k_cpu, rt_cpu_h100, NULL), 3);
    const bool only_cpu[] = {true, false, false, false};
    CHECK_EQ_INT(u_device_select(NULL, 4, k_names, k_cpu, only_cpu, NULL), 0);
    CHECK_EQ_INT(u_device_select(NULL, 4, k_names, k_cpu, none, NULL), -1);
    /* A selector: the first usable match in enumeration order. */
    CHECK_EQ_INT(u_device_select("gpu", 4, k_names, k_cpu, all, NULL), 1);
    CHECK_EQ_INT(u_device_select("gpu", 4, k_names, k_cpu, rt_cpu_h100, NULL), 3);
    CHECK_EQ_INT(u_device_select("nvidia", 4, k_names, k_cpu, rt_cpu_h100, NULL), 3);
    CHECK_EQ_INT(u_device_select("cpu", 4, k_names, k_cpu, all, NULL), 0);
    CHECK_EQ_INT(u_device_select("2", 4, k_names, k_cpu, all, NULL), 2);
    /* Matches that are not usable, and no match at all. */
    CHECK_EQ_INT(u_device_select("intel", 4, k_names, k_cpu, rt_cpu_h100, &any), -1);
    CHECK(any);
    CHECK_EQ_INT(u_device_select("amd", 4, k_names, k_cpu, all, &any), -1);
    CHECK(!any);
    CHECK_EQ_INT(u_device_select("7", 4, k_names, k_cpu, all, &any), -1);
    CHECK(!any);
}

int main(void)
{
    RUN(test_matches);
    RUN(test_select);
    return t_finish();
}
