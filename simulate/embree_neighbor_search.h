// The Embree implementation of NeighborSearch (see neighbor_search.h). This
// header does not include Embree; only embree_neighbor_search.cc does.
#ifndef SYLVA_SIMULATE_EMBREE_NEIGHBOR_SEARCH_H_
#define SYLVA_SIMULATE_EMBREE_NEIGHBOR_SEARCH_H_

#include <memory>

#include "simulate/neighbor_search.h"

namespace sylva {

// Throws Error if Embree cannot create a device.
std::unique_ptr<NeighborSearch> MakeEmbreeNeighborSearch();

}  // namespace sylva

#endif  // SYLVA_SIMULATE_EMBREE_NEIGHBOR_SEARCH_H_
