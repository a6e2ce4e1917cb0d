// SPDX-License-Identifier: MIT
/**
 * @file hs_pareto.c
 * @brief The Pareto front of (cost, error) points (hs_pareto.h).
 */
#include "hs_pareto.h"

#include <math.h>

static bool finite_point(double c, double e)
{
    return isfinite(c) && isfinite(e);
}

/* Whether (cj, ej) dominates (ci, ei): no worse in both, strictly better in one. */
static bool dominates(double cj, double ej, double ci, double ei)
{
    return cj <= ci && ej <= ei && (cj < ci || ej < ei);
}

uint32_t hs_pareto_front(const double *cost, const double *err, uint32_t n, bool *out_front)
{
    uint32_t count = 0;
    for (uint32_t i = 0; i < n; i++) {
        bool front = finite_point(cost[i], err[i]);
        for (uint32_t j = 0; j < n && front; j++)
            if (j != i && finite_point(cost[j], err[j]) &&
                dominates(cost[j], err[j], cost[i], err[i]))
                front = false;
        out_front[i] = front;
        count += front;
    }
    return count;
}
