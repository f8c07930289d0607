#include "core/io/vdb_io.h"

#include <exception>
#include <new>

#include "core/types/density_grid_vdb.h"
#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {

void WriteDensityGrid(const fs::path& path, const DensityGrid& grid) {
  InitializeOpenVdb();
  AtomicWriteWith(path, [&](const fs::path& temp) {
    openvdb::io::File file(temp.string());
    openvdb::GridCPtrVec grids;
    grids.push_back(VdbGrid(grid).copyGrid());  // shallow copy shares the tree
    file.write(grids);
    file.close();
  });
}

DensityGrid ReadDensityGrid(const fs::path& path) {
  InitializeOpenVdb();
  std::error_code ec;
  SYLVA_CHECK_INPUT(fs::is_regular_file(path, ec), path.string()) << "file not found";
  openvdb::GridPtrVecPtr grids;
  // Known limit (fuzz/vdb_fuzzer.cc): OpenVDB 10.0's bloscFromStream reads
  // a block whose size field says "uncompressed" (negative) into the node's
  // buffer before comparing the size with the buffer's (later OpenVDB
  // releases compare first), so a deliberately made file can overflow the
  // heap. Only a copy of OpenVDB's reader could check that here; sylva reads
  // the density.vdb it wrote itself.
  try {
    openvdb::io::File file(path.string());
    // Without delayed loading: its metadata, when damaged, fails an
    // assertion inside OpenVDB (found by fuzz/vdb_fuzzer.cc) instead of
    // throwing.
    file.open(/*delayLoad=*/false);
    grids = file.getGrids();
    file.close();
  } catch (const openvdb::Exception& error) {
    SYLVA_INPUT_ERROR(path.string()) << "cannot read OpenVDB file: " << error.what();
  } catch (const std::bad_alloc&) {
    // A damaged size field asks for more memory than there is.
    SYLVA_INPUT_ERROR(path.string()) << "cannot read OpenVDB file: damaged (impossible sizes)";
  } catch (const std::exception& error) {
    SYLVA_INPUT_ERROR(path.string()) << "cannot read OpenVDB file: " << error.what();
  }
  openvdb::FloatGrid::Ptr chosen;
  int num_float_grids = 0;
  for (const openvdb::GridBase::Ptr& base : *grids) {
    auto float_grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    if (!float_grid) continue;
    ++num_float_grids;
    if (float_grid->getName() == "density" || !chosen) chosen = float_grid;
  }
  SYLVA_CHECK_INPUT(chosen != nullptr, path.string()) << "file holds no float grid";
  SYLVA_CHECK_INPUT(chosen->getName() == "density" || num_float_grids == 1, path.string())
      << "file holds several float grids and none is named 'density'";
  DensityGrid grid = DensityGridFromVdb(*chosen, path.string());
  bool in_range = true;
  grid.ForEachActive([&](const Eigen::Vector3i&, float alpha) {
    in_range = in_range && alpha >= 0.0f && alpha <= 1.0f;
  });
  SYLVA_CHECK_INPUT(in_range, path.string()) << "density values must be opacities in [0, 1]";
  return grid;
}

}  // namespace sylva
