// SPDX-License-Identifier: MIT
/**
 * @file test_pareto.c
 * @brief hs_pareto_front: the non-dominated settings that the bench's pareto chart marks —
 *        dominated points are off the front, ties are handled, non-finite points are ignored.
 */
#include "hs_pareto.h"
#include "testing.h"

#include <math.h>

/* A front of three, and points each dominated by one of them. */
static void test_dominated_off(void)
{
    /*                   0    1    2    3    4    5 */
    const double c[] = {1.0, 2.0, 4.0, 3.0, 2.5, 5.0};
    const double e[] = {9.0, 5.0, 1.0, 6.0, 5.0, 1.5};
    bool f[6];
    CHECK_EQ_INT(hs_pareto_front(c, e, 6, f), 3);
    CHECK(f[0] && f[1] && f[2]);
    CHECK(!f[3]); /* slower and worse than 1 */
    CHECK(!f[4]); /* equal error to 1, slower */
    CHECK(!f[5]); /* slower and worse than 2 */
}

/* Equal points do not dominate each other; equal cost keeps only the lowest error, equal
 * error only the lowest cost. */
static void test_ties(void)
{
    const double c[] = {1.0, 1.0, 1.0, 2.0, 3.0};
    const double e[] = {4.0, 4.0, 6.0, 2.0, 2.0};
    bool f[5];
    CHECK_EQ_INT(hs_pareto_front(c, e, 5, f), 3);
    CHECK(f[0] && f[1]); /* identical: both stay */
    CHECK(!f[2]);        /* same cost, more error */
    CHECK(f[3]);
    CHECK(!f[4]); /* same error, more cost */
    /* Two identical points that a third dominates both leave. */
    const double c2[] = {2.0, 2.0, 1.0};
    const double e2[] = {3.0, 3.0, 3.0};
    CHECK_EQ_INT(hs_pareto_front(c2, e2, 3, f), 1);
    CHECK(!f[0] && !f[1] && f[2]);
}

/* A point without a figure (NaN) is never on the front and dominates nothing, even when its
 * other coordinate is the best. */
static void test_nonfinite(void)
{
    const double c[] = {0.5, 1.0, 2.0, INFINITY};
    const double e[] = {NAN, 3.0, 1.0, 0.1};
    bool f[4];
    CHECK_EQ_INT(hs_pareto_front(c, e, 4, f), 2);
    CHECK(!f[0] && f[1] && f[2] && !f[3]);
    CHECK_EQ_INT(hs_pareto_front(c, e, 0, f), 0);
    const double one_c[] = {7.0}, one_e[] = {7.0};
    CHECK_EQ_INT(hs_pareto_front(one_c, one_e, 1, f), 1);
    CHECK(f[0]);
}

int main(void)
{
    RUN(test_dominated_off);
    RUN(test_ties);
    RUN(test_nonfinite);
    return t_finish();
}
