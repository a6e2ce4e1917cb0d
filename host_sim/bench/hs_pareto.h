// SPDX-License-Identifier: MIT
/**
 * @file hs_pareto.h
 * @brief The Pareto front of (cost, error) points, both minimised: the bench report's pareto
 *        chart marks the settings that no other setting beats on both (issue 19 item 4).
 */
#pragma once

#include <stdbool.h>
#include <stdint.h>

/**
 * Marks out_front[i] true when point i is non-dominated: no point j has cost_j <= cost_i and
 * err_j <= err_i with at least one of the two strictly smaller. Ties: points equal in both
 * coordinates do not dominate each other (all of them are on the front, or none); at equal
 * cost only the lowest error is on the front, at equal error only the lowest cost. A point
 * with a non-finite coordinate (a setting without references, say) is never on the front and
 * dominates nothing. Returns the number of points on the front. O(n^2): n is a few dozen.
 */
uint32_t hs_pareto_front(const double *cost, const double *err, uint32_t n, bool *out_front);
