// Regions (docs/simplify.md "Regions"): a mesh with one large connected component, cut by space
// into parts whose collapses run on separate threads, each with a queue of its own, up to a bound
// below the stop; then one queue over the whole mesh goes on to the stop. The corners of every
// face that crosses a cut are frozen while the regions run: a collapse whose ends are not frozen
// reads and writes only its own region's faces, face lists, quadrics and marks, so each region
// does the same whatever runs beside it (the argument is in regions.cpp).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "dynpm/core.h"
#include "dynpm/simplify.h"

namespace dynpm::simplification {

// Whether simplify() cuts a mesh of `referenced` vertices in faces, the largest component
// holding `largest`, into regions (SimplifyOptions::region_min_vertices); `listener`: whether
// the collapses are told to one.
bool regions_allowed(const SimplifyOptions& options, bool listener, size_t referenced,
                     size_t largest);

// Regions the mesh is cut into: a power of two, fixed so that the result is the same
// on any thread count. Eight keep two cores busy in rounds and freeze a few percent of a large
// mesh's vertices.
inline constexpr unsigned kRegionLevels = 3;  // 2³ regions

// The regions stop once they have made this share of the collapses (or removed faces) a vertex
// or face target leaves to them (those of the vertices not frozen); the one queue makes the rest,
// the frozen borders first. Measured on the dragon: 0.8 left 17 % of the collapses to one core
// for the same result.
inline constexpr double kRegionShare = 0.95;

// Each vertex's region: the vertices in faces split at the median of the longest side of their
// box, `levels` times; vertices in no face go to region 0. Vertex v's position is at
// xyz + v · stride (the simplifier's rows hold every key step; it cuts at the first).
std::vector<uint16_t> spatial_regions(const Topology& input, const float* xyz, size_t stride,
                                      unsigned levels);

// 1 for each corner of a face whose corners lie in more than one region, and for every vertex of
// a component with fewer than five such corners.
std::vector<uint8_t> frozen_borders(const Topology& input, std::span<const uint16_t> region_of,
                                    std::span<const uint32_t> component_of, size_t components);

}  // namespace dynpm::simplification
