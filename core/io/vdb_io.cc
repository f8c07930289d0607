#include "core/io/vdb_io.h"

#include <array>
#include <bitset>
#include <cstdint>
#include <cstring>
#include <exception>
#include <fstream>
#include <map>
#include <new>
#include <string>

#include <openvdb/points/StreamCompression.h>

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
const std::string kFloatTree = "Tree_float_5_4_3", kHalfSuffix = "_HalfFloat";
// That tree's nodes, as OpenVDB defines them: internal nodes of 32^3 and
// 16^3 entries (log2 of their side: 5 and 4) above leaves of 8^3 voxels.
using UpperNode = openvdb::FloatTree::RootNodeType::ChildNodeType;
using LowerNode = UpperNode::ChildNodeType;
using LeafNode = LowerNode::ChildNodeType;
// The metadata types OpenVDB registers (openvdb.cc) whose values have a
// fixed size, in bytes; besides these, "string" and "__delayedload".
const std::map<std::string, uint32_t> kFixedMetadataBytes = {
    {"bool", 1},   {"int32", 4},  {"int64", 8},  {"float", 4},  {"double", 8}, {"vec2i", 8},
    {"vec2s", 8},  {"vec2d", 16}, {"vec3i", 12}, {"vec3s", 12}, {"vec3d", 24}, {"vec4i", 16},
    {"vec4s", 16}, {"vec4d", 32}, {"mat4s", 64}, {"mat4d", 128}};

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
  // value (12 bytes at the least: two empty names and a size). OpenVDB reads
  // a value of fixed size whatever size the file states, and a bool's byte
  // straight into a bool: sizes must match the type, and only the types
  // OpenVDB itself registers are read.
  void Metadata(const char* what) {
    const int32_t count = Read<int32_t>(what);
    Fail(count < 0 || uint64_t(count) > (size_ - at_) / 12, what);
    for (int32_t k = 0; k < count; ++k) {
      String(what);
      const std::string type = String(what);
      const uint32_t bytes = Read<uint32_t>(what);
      if (type == "string") {
        Skip(bytes, what);
      } else if (type == "__delayedload") {
        DelayedLoad(bytes, what);
      } else {
        const auto fixed = kFixedMetadataBytes.find(type);
        SYLVA_CHECK_INPUT(fixed != kFixedMetadataBytes.end(), path_.string())
            << "the OpenVDB file holds metadata of type '" << type << "' at byte " << at_
            << ", which sylva does not read";
        Fail(bytes != fixed->second, what);
        if (type == "bool") {
          const char value = Read<char>(what);
          Fail(value != 0 && value != 1, what);
        } else {
          Skip(bytes, what);
        }
      }
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
  // OpenVDB's delayed-loading metadata (io/DelayedLoadMetadata.cc): a leaf
  // count, a mask byte per leaf and, optionally, a compressed size per leaf
  // (8 bytes), each stored raw or as a Blosc buffer. OpenVDB allocates the
  // count and decompresses the buffers as stated, so their sizes are checked
  // against each other (a Blosc header holds the uncompressed size at byte 4
  // and the compressed size at byte 12).
  void DelayedLoad(uint32_t bytes, const char* what) {
    if (bytes == 0) return;
    Need(bytes, what);
    const uint64_t end = at_ + bytes;
    const uint32_t leaves = Read<uint32_t>(what);
    Fail(leaves > size_ / LeafNode::NodeMaskType::memUsage(), what);  // its mask alone
    DelayedLoadBuffer(leaves, /*optional=*/false, what);
    DelayedLoadBuffer(uint64_t{leaves} * 8, /*optional=*/true, what);
    Fail(at_ > end, what);
    Seek(end);
  }
  void DelayedLoadBuffer(uint64_t raw_bytes, bool optional, const char* what) {
    const uint32_t bytes = Read<uint32_t>(what);
    if (optional && bytes == 0xffffffff) return;   // absent
    if (bytes == 0) return Skip(raw_bytes, what);  // stored raw
    Fail(bytes < 16, what);
    const uint64_t start = at_;
    Skip(4, what);
    const uint32_t uncompressed = Read<uint32_t>(what);
    Skip(4, what);
    const uint32_t compressed = Read<uint32_t>(what);
    // OpenVDB pads small buffers to BLOSC_PAD_BYTES before compressing them.
    const uint64_t padded = openvdb::compression::BLOSC_PAD_BYTES;
    Fail((uncompressed != raw_bytes && !(raw_bytes < padded && uncompressed == padded)) ||
             compressed != bytes,
         what);
    Seek(start);
    Skip(bytes, what);
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

// The layout of OpenVDB's float tree (Tree_float_5_4_3, tree/RootNode.h,
// InternalNode.h, LeafNode.h): a root's tiles and children, internal nodes
// of 32^3 and 16^3 entries, leaves of 8^3 voxels. Each node's topology is
// its masks and values; the leaves' voxel values (the buffers) follow the
// whole topology, leaf by leaf in the same order.
class FloatTreeLayout {
 public:
  FloatTreeLayout(const fs::path& path, VdbLayoutReader* in, uint32_t compression, bool half)
      : path_(path), in_(in), mask_compressed_(compression & kCompressActiveMask), half_(half) {}

  // The transform (the scale-and-translate maps sylva's grids use), then the
  // topology and buffers OpenVDB reads right after it. OpenVDB trusts every
  // field: a root tile's active flag is read straight into a bool (a damaged
  // byte there is undefined behaviour), and each bit set in a damaged child
  // mask allocates a node before the file is found to end (a 10 KB file
  // asked for 1.6 GB; both found by fuzz/vdb_fuzzer.cc). The walk reads
  // every field against the file's size, so a file stating more nodes than
  // its bytes can hold is refused at once.
  void Check() {
    const std::string map = in_->String("a grid's transform");
    // The maps' fields: translation (scale-translate maps), scale, voxel
    // size, inverse scale, inverse squared scale, inverse twice the scale.
    const uint64_t map_bytes = map == "UniformScaleTranslateMap" || map == "ScaleTranslateMap"
                                   ? 6 * 24
                               : map == "UniformScaleMap" || map == "ScaleMap" ? 5 * 24
                                                                               : 0;
    SYLVA_CHECK_INPUT(map_bytes > 0, path_.string())
        << "the grid's transform '" << map
        << "' is not read (sylva's grids are scaled and translated voxels)";
    in_->Skip(map_bytes, "a grid's transform");
    in_->Fail(in_->Read<int32_t>("the tree's buffer count") != 1, "the tree's buffer count");
    in_->Read<float>("the tree's background");
    const uint32_t tiles = in_->Read<uint32_t>("the root's tile count");
    const uint32_t children = in_->Read<uint32_t>("the root's child count");
    // A tile: origin (3 int32), value (float), active flag (1 byte).
    in_->Fail(tiles > (in_->size() - in_->at()) / 17, "the root's tile count");
    for (uint32_t t = 0; t < tiles; ++t) {
      in_->Skip(16, "a root tile");  // origin and value
      const char active = in_->Read<char>("a root tile's active flag");
      in_->Fail(active != 0 && active != 1, "a root tile's active flag");
      RefuseActiveTiles(active);
    }
    // A child: its origin (the root keeps one child per origin, in order:
    // another with the same origin would replace it, and leak), then its
    // topology.
    std::array<int32_t, 3> last{};
    for (uint32_t c = 0; c < children; ++c) {
      std::array<int32_t, 3> origin;
      for (int32_t& coordinate : origin) {
        coordinate = in_->Read<int32_t>("a root child");
        in_->Fail(coordinate % static_cast<int32_t>(UpperNode::DIM) != 0, "a root child's origin");
      }
      in_->Fail(c > 0 && !(last < origin), "a root child's origin");
      last = origin;
      InternalTopology(UpperNode::LOG2DIM);
    }
    for (uint64_t leaf = 0; leaf < leaves_; ++leaf) {
      const uint64_t active = MaskBitsSet(LeafNode::LOG2DIM, "a leaf's value mask");
      Values(LeafNode::LOG2DIM, active, "a leaf's values");
    }
  }

 private:
  // The bits set in a node mask of 2^(3 log2_dim) bits.
  uint64_t MaskBitsSet(int log2_dim, const char* what) {
    uint64_t set = 0;
    for (uint64_t word = 0; word < (uint64_t{1} << (3 * log2_dim)) / 64; ++word) {
      set += std::bitset<64>(in_->Read<uint64_t>(what)).count();
    }
    return set;
  }
  // An internal node: its child and value masks, its values, its children.
  void InternalTopology(int log2_dim) {
    const uint64_t children = MaskBitsSet(log2_dim, "an internal node's child mask");
    RefuseActiveTiles(MaskBitsSet(log2_dim, "an internal node's value mask") > 0);
    Values(log2_dim, 0, "an internal node's values");
    for (uint64_t c = 0; c < children; ++c) {
      if (log2_dim == UpperNode::LOG2DIM) {
        InternalTopology(LowerNode::LOG2DIM);
      } else {
        in_->Skip(LeafNode::NodeMaskType::memUsage(), "a leaf's value mask");
        ++leaves_;
      }
    }
  }
  // A node's values as io::readCompressedValues reads them without zlib or
  // Blosc (io/Compression.h): a byte saying which inactive values and
  // selection mask follow, then the values (only the active ones when the
  // grid is mask-compressed and the byte allows it).
  void Values(int log2_dim, uint64_t active, const char* what) {
    const int8_t kind = in_->Read<int8_t>(what);
    in_->Fail(kind < 0 || kind > 6, what);
    if (kind == 2 || kind == 4) in_->Skip(4, what);  // one inactive value
    if (kind == 5) in_->Skip(8, what);               // two
    if (kind >= 3 && kind <= 5) in_->Skip((uint64_t{1} << (3 * log2_dim)) / 8, what);
    const uint64_t count = mask_compressed_ && kind != 6 ? active : uint64_t{1} << (3 * log2_dim);
    in_->Skip(count * (half_ ? 2 : 4), what);
  }
  // An active tile stands for up to 4096^3 voxels of one value; a density
  // has voxels only (found by fuzz/vdb_fuzzer.cc: a damaged file's tile made
  // the value check of ReadDensityGrid visit ~10^11 voxels).
  void RefuseActiveTiles(bool any) const {
    SYLVA_CHECK_INPUT(!any, path_.string())
        << "the density grid holds active tiles (regions of one value); sylva's density grids "
           "hold voxels only";
  }

  fs::path path_;
  VdbLayoutReader* in_;
  bool mask_compressed_;
  bool half_;
  uint64_t leaves_ = 0;
};

// Checks a .vdb file's whole layout before OpenVDB reads it, and that no
// grid is compressed with zlib or Blosc. OpenVDB 10.0's readers trust the
// sizes a file states: a damaged string length or metadata size allocates
// gigabytes, a damaged node mask nodes, and its zlib and Blosc readers copy a
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
  // The layout walked here is that of the versions from OpenVDB 3 to the
  // linked library's; a later one may differ (OpenVDB itself only warns).
  SYLVA_CHECK_INPUT(
      version >= kFirstVersionWithGridCompression && version <= openvdb::OPENVDB_FILE_VERSION,
      path.string())
      << "OpenVDB file version " << version << " is not read (versions "
      << kFirstVersionWithGridCompression << " to " << openvdb::OPENVDB_FILE_VERSION
      << ": OpenVDB 3 to " << openvdb::OPENVDB_LIBRARY_MAJOR_VERSION << "."
      << openvdb::OPENVDB_LIBRARY_MINOR_VERSION << ")";
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
    const std::string type = in.String("a grid type");
    SYLVA_CHECK_INPUT(type == kFloatTree || type == kFloatTree + kHalfSuffix, path.string())
        << "the file holds a grid of type '" << type << "'; sylva reads float grids (" << kFloatTree
        << ") only";
    SYLVA_CHECK_INPUT(in.String("a grid's instance parent").empty(), path.string())
        << "the file holds an instanced grid (one sharing another's tree); sylva reads "
           "grids with trees of their own";
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
    FloatTreeLayout(path, &in, compression, type != kFloatTree).Check();
    in.Fail(in.at() > end, "a grid's end position");
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
  DensityGrid grid = DensityGridFromVdb(*chosen, path.string());
  bool in_range = true;
  grid.ForEachActive([&](const Eigen::Vector3i&, float alpha) {
    in_range = in_range && alpha >= 0.0f && alpha <= 1.0f;
  });
  SYLVA_CHECK_INPUT(in_range, path.string()) << "density values must be opacities in [0, 1]";
  return grid;
}

}  // namespace sylva
