// Density grids as OpenVDB files (.vdb). Files open in Blender (Volume
// object), Houdini and OpenVDB's own tools; the grid is named "density" and
// classed as a fog volume.
#ifndef SYLVA_CORE_IO_VDB_IO_H_
#define SYLVA_CORE_IO_VDB_IO_H_

#include <filesystem>

#include "core/types/density_grid.h"

namespace sylva {

// Writes atomically.
void WriteDensityGrid(const std::filesystem::path& path, const DensityGrid& grid);

// Reads the float grid named "density" (or the only float grid in the file).
// Throws InputError naming the file if it is missing, corrupt or has no
// suitable grid.
DensityGrid ReadDensityGrid(const std::filesystem::path& path);

}  // namespace sylva

#endif  // SYLVA_CORE_IO_VDB_IO_H_
