#include "core/io/vdb_io.h"

#include <cstdint>
#include <cstring>
#include <exception>
#include <fstream>
#include <new>
#include <string>

#include "core/types/density_grid_vdb.h"
#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

// OpenVDB's stream layout (io/Archive.cc, io/File.cc of OpenVDB 10): a
// header, the file's metadata, then per grid its descriptor (name, type,
// instance parent, the positions of the grid, its data block and its end),
// the grid's compression flags, its metadata, transform, topology and
// buffers.
constexpr uint64_t kVdbMagic = 0x56444220;
constexpr uint32_t kFirstVersionWithGridCompression = 222;  // flags per grid
constexpr uint32_t kCompressZip = 0x1, kCompressActiveMask = 0x2, kCompressBlosc = 0x4;

// Reads the fields of a .vdb file in order, each checked against the
// file's size; InputError naming the file and the byte where it breaks.
class VdbLayoutReader {
 public:
  explicit VdbLayoutReader(const fs::path& path)
      : path_(path), file_(path, std::ios::binary), size_(FileSize(path)) {}

  uint64_t at() const { return at_; }
  uint64_t size() const { return size_; }

  template <typename T>
  T Read(const char* what) {
    T value{};
    Need(sizeof(T), what);
    file_.read(reinterpret_cast<char*>(&value), sizeof(T));
    at_ += sizeof(T);
    return value;
  }
  // A length-prefixed string.
  std::string String(const char* what) {
    const uint32_t length = Read<uint32_t>(what);
    Need(length, what);
    std::string text(length, '\0');
    file_.read(text.data(), length);
    at_ += length;
    return text;
  }
  void Skip(uint64_t bytes, const char* what) {
    Need(bytes, what);
    Seek(at_ + bytes);
  }
  void Seek(uint64_t position) {
    at_ = position;
    file_.seekg(static_cast<std::streamoff>(position));
  }
  // Metadata: a count, then per item its name, type name, value size and
  // value (12 bytes at the least: two empty names and a size).
  void Metadata(const char* what) {
    const int32_t count = Read<int32_t>(what);
    Fail(count < 0 || uint64_t(count) > (size_ - at_) / 12, what);
    for (int32_t k = 0; k < count; ++k) {
      String(what);
      String(what);
      Skip(Read<uint32_t>(what), what);
    }
  }
  void Fail(bool failed, const std::string& what) const {
    SYLVA_CHECK_INPUT(!failed, path_.string())
        << "damaged OpenVDB file: " << what << " at byte " << at_ << " is impossible";
  }

 private:
  static uint64_t FileSize(const fs::path& path) {
    std::error_code ec;
    const uint64_t size = fs::file_size(path, ec);
    SYLVA_CHECK_INPUT(!ec, path.string()) << "cannot read file: " << ec.message();
    return size;
  }
  void Need(uint64_t bytes, const char* what) const {
    SYLVA_CHECK_INPUT(file_ && bytes <= size_ - at_, path_.string())
        << "damaged OpenVDB file: " << what << " at byte " << at_ << " runs past its end (" << size_
        << " bytes; truncated)";
  }

  fs::path path_;
  std::ifstream file_;
  uint64_t size_;
  uint64_t at_ = 0;
};

// A grid's transform (the scale-and-translate maps sylva's grids use) and
// its tree's root: OpenVDB reads each root tile's active flag straight into
// a bool, and a damaged byte there is undefined behaviour (found by
// fuzz/vdb_fuzzer.cc under UBSan).
void CheckTransformAndRoot(const fs::path& path, VdbLayoutReader* in) {
  const std::string map = in->String("a grid's transform");
  // The maps' fields: translation (scale-translate maps), scale, voxel size,
  // inverse scale, inverse squared scale, inverse twice the scale.
  const uint64_t map_bytes = map == "UniformScaleTranslateMap" || map == "ScaleTranslateMap"
                                 ? 6 * 24
                             : map == "UniformScaleMap" || map == "ScaleMap" ? 5 * 24
                                                                             : 0;
  SYLVA_CHECK_INPUT(map_bytes > 0, path.string())
      << "the grid's transform '" << map
      << "' is not read (sylva's grids are scaled and translated voxels)";
  in->Skip(map_bytes, "a grid's transform");
  in->Fail(in->Read<int32_t>("the tree's buffer count") != 1, "the tree's buffer count");
  in->Read<float>("the tree's background");
  const uint32_t tiles = in->Read<uint32_t>("the root's tile count");
  in->Read<uint32_t>("the root's child count");
  // A tile: origin (3 int32), value (float), active flag (1 byte).
  in->Fail(tiles > (in->size() - in->at()) / 17, "the root's tile count");
  for (uint32_t t = 0; t < tiles; ++t) {
    in->Skip(16, "a root tile");  // origin and value
    const char active = in->Read<char>("a root tile's active flag");
    in->Fail(active != 0 && active != 1, "a root tile's active flag");
  }
}

// Checks a .vdb file's layout up to each grid's root node before OpenVDB
// reads it, and that no grid is compressed with zlib or Blosc. OpenVDB
// 10.0's readers trust the sizes a file states: a damaged string length or
// metadata size allocates gigabytes, and its zlib and Blosc readers copy a
// block whose size says "uncompressed" into the node's buffer before
// comparing the sizes (a heap overflow; later releases compare first; found
// by fuzz/vdb_fuzzer.cc). sylva writes its grids with active-mask
// compression only (values stored as they are), so it never needs those
// readers; a .vdb from elsewhere with zlib or Blosc is refused with a word
// on how to convert it.
void CheckVdbLayout(const fs::path& path) {
  VdbLayoutReader in(path);
  in.Fail(in.Read<uint64_t>("the magic number") != kVdbMagic, "the magic number (not a .vdb)");
  const uint32_t version = in.Read<uint32_t>("the file version");
  SYLVA_CHECK_INPUT(version >= kFirstVersionWithGridCompression && version < 1000, path.string())
      << "OpenVDB file version " << version << " is not read (versions "
      << kFirstVersionWithGridCompression << " and later: OpenVDB 3 onwards)";
  in.Read<uint32_t>("the library's major version");
  in.Read<uint32_t>("the library's minor version");
  in.Fail(in.Read<char>("the grid offsets flag") != 1, "a file without grid offsets");
  in.Skip(36, "the file's UUID");
  in.Metadata("the file's metadata");
  const int32_t num_grids = in.Read<int32_t>("the grid count");
  // A descriptor holds 3 strings and 3 positions: 36 bytes at the least.
  in.Fail(num_grids < 0 || uint64_t(num_grids) > in.size() / 36, "the grid count");
  for (int32_t g = 0; g < num_grids; ++g) {
    in.String("a grid name");
    in.String("a grid type");
    in.String("a grid's instance parent");
    const uint64_t grid = in.Read<uint64_t>("a grid position");
    const uint64_t block = in.Read<uint64_t>("a grid's data position");
    const uint64_t end = in.Read<uint64_t>("a grid's end position");
    in.Fail(grid < in.at() || block < grid || end < block, "a grid's positions");
    in.Skip(end - in.at(), "a grid");  // checks that the grid ends within the file
    in.Seek(grid);
    const uint32_t compression = in.Read<uint32_t>("a grid's compression flags");
    in.Fail(compression > (kCompressZip | kCompressActiveMask | kCompressBlosc),
            "a grid's compression flags");
    SYLVA_CHECK_INPUT((compression & (kCompressZip | kCompressBlosc)) == 0, path.string())
        << "the grid is compressed with " << ((compression & kCompressBlosc) ? "Blosc" : "zlib")
        << "; sylva reads .vdb files without it, as it writes them (OpenVDB 10.0's "
           "decompressors trust the sizes a file states); save it without compression "
           "(in OpenVDB: io::File::setCompression(io::COMPRESS_ACTIVE_MASK))";
    in.Metadata("a grid's metadata");
    CheckTransformAndRoot(path, &in);
    in.Fail(in.at() > block, "a grid's metadata, transform or root");
    in.Seek(end);
  }
}

}  // namespace

void WriteDensityGrid(const fs::path& path, const DensityGrid& grid) {
  InitializeOpenVdb();
  AtomicWriteWith(path, [&](const fs::path& temp) {
    openvdb::io::File file(temp.string());
    // Values stored as they are (CheckVdbLayout explains why).
    file.setCompression(openvdb::io::COMPRESS_ACTIVE_MASK);
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
  CheckVdbLayout(path);
  openvdb::GridPtrVecPtr grids;
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
  // An active tile stands for up to 4096^3 voxels of one value; a density
  // has voxels only (found by fuzz/vdb_fuzzer.cc: a damaged file's tile made
  // the range check below visit ~10^11 voxels).
  SYLVA_CHECK_INPUT(chosen->tree().activeTileCount() == 0, path.string())
      << "the density grid holds active tiles (regions of one value); sylva's density grids "
         "hold voxels only";
  DensityGrid grid = DensityGridFromVdb(*chosen, path.string());
  bool in_range = true;
  grid.ForEachActive([&](const Eigen::Vector3i&, float alpha) {
    in_range = in_range && alpha >= 0.0f && alpha <= 1.0f;
  });
  SYLVA_CHECK_INPUT(in_range, path.string()) << "density values must be opacities in [0, 1]";
  return grid;
}

}  // namespace sylva
