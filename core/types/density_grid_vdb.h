// Direct OpenVDB access to a DensityGrid. Include only in .cc files that need
// OpenVDB (it is a heavy header).
#ifndef SYLVA_CORE_TYPES_DENSITY_GRID_VDB_H_
#define SYLVA_CORE_TYPES_DENSITY_GRID_VDB_H_

#include <openvdb/openvdb.h>

#include "core/types/density_grid.h"

namespace sylva {

// Initialises OpenVDB once per process (thread-safe, idempotent).
void InitializeOpenVdb();

// The wrapped grid. Its transform is kept in sync with voxel_size()/origin().
openvdb::FloatGrid& VdbGrid(DensityGrid& grid);
const openvdb::FloatGrid& VdbGrid(const DensityGrid& grid);

// Wraps an existing OpenVDB grid (deep-copied); its transform must be a
// uniform scale plus translation. Throws InputError naming `source` otherwise.
DensityGrid DensityGridFromVdb(const openvdb::FloatGrid& vdb_grid, const std::string& source);

}  // namespace sylva

#endif  // SYLVA_CORE_TYPES_DENSITY_GRID_VDB_H_
