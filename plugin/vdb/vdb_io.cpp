// vdb_io.cpp — OpenVDB <-> CloudVolume (see vdb_io.h).
//
// Why this does not simply use openvdb::io::Stream or io::File to read:
// OpenVDB 10's readers are not safe on damaged input. A short read leaves the
// target uninitialised and reading goes on with garbage sizes (gigabyte
// allocations, std::bad_alloc), and an exception thrown while a RootNode
// child is being read leaks that child and everything under it
// (RootNode::readTopology holds it in a raw pointer). So this file reads the
// archive itself with OpenVDB's own building blocks, in the same order as
// io::Archive::readGrid:
//  * the input is an istream over the caller's bytes with exceptions on, so
//    the first short read throws instead of returning garbage;
//  * strings (grid descriptors) are length-checked against the bytes left;
//  * the root level of a tree is read here, each child node owned by a
//    unique_ptr until the root owns it, so an exception frees everything;
//  * grid offsets (written by io::File and by write_vdb_*) let the reader
//    name a truncated grid and skip grids it does not need without reading
//    their trees.

#include "vdb/vdb_io.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <istream>
#include <limits>
#include <memory>
#include <mutex>
#include <new>
#include <sstream>
#include <streambuf>
#include <type_traits>

#include <openvdb/io/Archive.h>
#include <openvdb/io/io.h>
#include <openvdb/openvdb.h>
#include <tbb/task_arena.h>

namespace atmo::vdb {
namespace {

using openvdb::Coord;
using openvdb::CoordBBox;

void init_openvdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

// Messages from OpenVDB can carry raw file bytes (a garbage-length string
// becomes part of the text): keep them short and printable.
std::string printable(const std::string& s, size_t max_chars = 200) {
  std::string out;
  for (char c : s) {
    if (out.size() >= max_chars) {
      out += "...";
      break;
    }
    const unsigned char u = static_cast<unsigned char>(c);
    out += (u >= 32 && u < 127) ? c : '?';
  }
  return out;
}

std::string quoted(const std::string& s) { return "\"" + printable(s, 100) + "\""; }

template <typename T>
std::string num(T v) {
  std::ostringstream o;
  o << v;
  return o.str();
}

std::string coord_str(const Coord& c) {
  return "(" + num(c.x()) + ", " + num(c.y()) + ", " + num(c.z()) + ")";
}

// Our own findings while reading, with the message already written.
struct ReadError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A read-only, seekable streambuf over bytes the caller keeps alive (no copy).
class MemoryBuffer : public std::streambuf {
 public:
  MemoryBuffer(const char* data, size_t size) {
    char* p = const_cast<char*>(data);  // never written: this is a get area only
    setg(p, p, p + size);
  }
  size_t size() const { return static_cast<size_t>(egptr() - eback()); }
  size_t position() const { return static_cast<size_t>(gptr() - eback()); }
  size_t remaining() const { return static_cast<size_t>(egptr() - gptr()); }

 protected:
  pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode which) override {
    if (!(which & std::ios_base::in)) return pos_type(off_type(-1));
    const off_type base = dir == std::ios_base::beg   ? 0
                          : dir == std::ios_base::cur ? static_cast<off_type>(position())
                                                      : static_cast<off_type>(size());
    const off_type target = base + off;
    if (target < 0 || target > static_cast<off_type>(size())) return pos_type(off_type(-1));
    setg(eback(), eback() + target, egptr());
    return pos_type(target);
  }
  pos_type seekpos(pos_type pos, std::ios_base::openmode which) override {
    return seekoff(off_type(pos), std::ios_base::beg, which);
  }
};

// Exposes the protected pieces of io::Archive that io::Stream uses.
class VdbArchive final : public openvdb::io::Archive {
 public:
  using openvdb::io::Archive::inputHasGridOffsets;
  using openvdb::io::Archive::readGridCompression;
  using openvdb::io::Archive::readHeader;
  openvdb::io::Archive::Ptr copy() const override { return std::make_shared<VdbArchive>(*this); }
  // Seekable output: grid offsets are filled in, as io::File writes them.
  void write_seekable(std::ostream& os, const openvdb::GridCPtrVec& grids,
                      const openvdb::MetaMap& meta) const {
    openvdb::io::Archive::write(os, grids, /*seekable=*/true, meta);
  }
};

// The input stream and the stream metadata OpenVDB keeps raw pointers to
// (io::setStreamMetadataPtr): the stream is declared last so it dies first.
struct Input {
  openvdb::io::StreamMetadata::Ptr file_meta;
  openvdb::io::StreamMetadata::Ptr grid_meta;
  MemoryBuffer buf;
  std::istream is;
  explicit Input(const std::string& bytes) : buf(bytes.data(), bytes.size()), is(&buf) {
    // Every short read throws at once (ios_base::failure), before OpenVDB
    // can use what it did not read.
    is.exceptions(std::ios_base::failbit | std::ios_base::badbit);
  }
};

template <typename T>
void read_pod(std::istream& is, T* v) {
  static_assert(std::is_trivially_copyable_v<T>);
  is.read(reinterpret_cast<char*>(v), sizeof(T));
}

template <typename T>
void read_value(std::istream& is, T* v) {
  if constexpr (std::is_same_v<T, bool>) {
    uint8_t b = 0;  // never load a byte other than 0/1 into a bool
    read_pod(is, &b);
    *v = b != 0;
  } else {
    read_pod(is, v);
  }
}

std::string read_string(Input& in) {
  uint32_t n = 0;
  read_pod(in.is, &n);
  if (n > in.buf.remaining()) {
    throw ReadError("truncated or corrupt: a " + num(n) + "-byte string at byte " +
                    num(in.buf.position()) + " runs past the end of the data (" +
                    num(in.buf.size()) + " bytes)");
  }
  std::string s(n, '\0');
  if (n) in.is.read(&s[0], n);
  return s;
}

// MetaMap::readMeta trusts every length in the data: it allocates (and, for
// strings, zeroes) what a damaged length says before reading it, so a 70 KB
// file took 30 s and a gigabyte (found by fuzz/vdb_fuzz.cpp). Walks the block
// as readMeta will read it, each length checked against the bytes left, then
// rewinds for readMeta.
void check_metadata(Input& in) {
  const std::streampos start = in.is.tellg();
  const size_t at = in.buf.position();
  uint32_t count = 0;
  read_pod(in.is, &count);
  if (count > in.buf.remaining() / 12) {  // each entry holds at least three 4-byte lengths
    throw ReadError("corrupt metadata at byte " + num(at) + ": " + num(count) + " entries cannot fit in the " +
                    num(in.buf.remaining()) + " bytes left");
  }
  for (uint32_t i = 0; i < count; ++i) {
    const size_t entry = in.buf.position();
    try {
      read_string(in);  // the name
    } catch (const ReadError& e) {
      throw ReadError(std::string("metadata name: ") + e.what());
    }
    std::string type;
    try {
      type = read_string(in);
    } catch (const ReadError& e) {
      throw ReadError(std::string("metadata type: ") + e.what());
    }
    uint32_t size = 0;
    read_pod(in.is, &size);
    if (size > in.buf.remaining()) {
      throw ReadError("truncated or corrupt: a " + num(size) + "-byte metadata value (entry at byte " + num(entry) +
                      ", type " + printable(type) + ") runs past the end of the data (" + num(in.buf.size()) +
                      " bytes)");
    }
    // A fixed-size value (float, vec3i, ...) is read at its own size whatever the data says: a size
    // that differs would shift everything after it. Strings and delayed-load masks vary.
    if (type != "string" && type != "__delayedload" && openvdb::Metadata::isRegisteredType(type)) {
      const uint32_t expected = openvdb::Metadata::createMetadata(type)->size();
      if (size != expected) {
        throw ReadError("corrupt metadata (entry at byte " + num(entry) + "): a " + printable(type) + " value of " +
                        num(size) + " bytes, expected " + num(expected));
      }
    }
    in.is.seekg(static_cast<std::streamoff>(size), std::ios_base::cur);
  }
  in.is.seekg(start);
}

// io::GridDescriptor::read, without its exception for unregistered types
// (which comes before the offsets that would let us skip such a grid).
struct Descriptor {
  std::string unique_name;
  std::string name;  // unique name without OpenVDB's "\x1e<n>" suffix
  std::string type;  // without "_HalfFloat"
  bool half = false;
  std::string instance_parent;
  int64_t grid_pos = 0, block_pos = 0, end_pos = 0;
};

Descriptor read_descriptor(Input& in, uint32_t version) {
  Descriptor d;
  d.unique_name = read_string(in);
  d.name = d.unique_name.substr(0, d.unique_name.find('\x1e'));
  d.type = read_string(in);
  const std::string half_suffix = "_HalfFloat";
  if (d.type.size() > half_suffix.size() &&
      d.type.compare(d.type.size() - half_suffix.size(), half_suffix.size(), half_suffix) == 0) {
    d.half = true;
    d.type.resize(d.type.size() - half_suffix.size());
  }
  if (version >= openvdb::OPENVDB_FILE_VERSION_GRID_INSTANCING) d.instance_parent = read_string(in);
  read_pod(in.is, &d.grid_pos);
  read_pod(in.is, &d.block_pos);
  read_pod(in.is, &d.end_pos);
  return d;
}

// OpenVDB 10's bloscFromStream and unzipFromStream read a chunk stored
// uncompressed (a size <= 0) straight into the node's value buffer and only
// then compare its size with the buffer's: a damaged size overflows the heap
// (found by fuzz/vdb_fuzz.cpp, fuzz/findings/). A compressed chunk's size is
// allocated as it stands. So before OpenVDB reads a level of a tree, this
// walks the same bytes in the same order (InternalNode::readTopology,
// LeafNode::readBuffers, io::readCompressedValues and io::readData of the
// installed headers), checks each chunk's size against the values its node
// holds and against the bytes left, then rewinds for OpenVDB.
class ChunkCheck {
 public:
  ChunkCheck(Input& in, std::string grid) : in_(in), grid_(std::move(grid)) {}

  // Before NodeT::readTopology (a child of the root).
  template <typename NodeT>
  void topology(bool from_half) {
    rewinding([&] { node_topology<NodeT>(from_half); });
  }
  // Before Tree::readBuffers: every leaf's buffers, in the stream's order.
  template <typename LeafT>
  void buffers(size_t leaf_count, bool from_half) {
    rewinding([&] {
      for (size_t i = 0; i < leaf_count; ++i) leaf_buffers<LeafT>(from_half);
    });
  }

 private:
  uint32_t version() const { return openvdb::io::getFormatVersion(in_.is); }

  template <typename F>
  void rewinding(F&& walk) {
    const std::streampos start = in_.is.tellg();
    walk();
    in_.is.seekg(start);
  }

  std::string at(size_t byte) const { return "at byte " + num(byte) + " of grid " + quoted(grid_); }

  // Throws unless `bytes` more are left.
  void require(uint64_t bytes, const char* what) const {
    if (bytes > in_.buf.remaining()) {
      throw ReadError("truncated or corrupt: " + std::string(what) + " of " + num(bytes) + " bytes " +
                      at(in_.buf.position()) + " runs past the end of the data (" + num(in_.buf.size()) +
                      " bytes)");
    }
  }

  void skip(uint64_t bytes, const char* what) {
    require(bytes, what);
    in_.is.seekg(static_cast<std::streamoff>(bytes), std::ios_base::cur);
  }

  template <typename MaskT>
  MaskT mask() {
    MaskT m;
    m.load(in_.is);  // a short read throws (Input's exceptions)
    return m;
  }

  // io::readData: count values of value_bytes each, in one chunk. With
  // `decode` (the topology, and bool values anywhere) the chunk is also
  // decoded, by OpenVDB's own decoder into a buffer of the node's size, and
  // bools must be 0 or 1: OpenVDB fills in an internal node's children only
  // after reading its values, so a throw there (a compressed chunk that does
  // not decode) leaves a child mask over tile values, which the node's
  // destructor deletes as pointers; and a bool byte other than 0/1 is UB.
  void data(uint64_t count, size_t value_bytes, uint32_t compression, bool decode, bool booleans) {
    namespace io = openvdb::io;
    const uint64_t expected = count * value_bytes;
    const size_t chunk = in_.buf.position();
    std::vector<char> values;
    auto check_booleans = [&] {
      if (!booleans) return;
      for (char c : values) {
        if (c != 0 && c != 1) {
          throw ReadError("corrupt: a bool value other than 0 or 1 in the chunk " + at(chunk));
        }
      }
    };
    if (!(compression & (io::COMPRESS_BLOSC | io::COMPRESS_ZIP))) {
      if (!decode) {
        skip(expected, "a node's values");
        return;
      }
      require(expected, "a node's values");
      values.resize(expected);
      in_.is.read(values.data(), static_cast<std::streamsize>(expected));
      check_booleans();
      return;
    }
    int64_t size = 0;
    read_pod(in_.is, &size);
    if (size > 0) {
      skip(static_cast<uint64_t>(size), "a compressed chunk");
    } else {
      const uint64_t raw = uint64_t{0} - static_cast<uint64_t>(size);  // no overflow at INT64_MIN
      if (raw != expected) {
        throw ReadError("corrupt: an uncompressed chunk " + at(chunk) + " says " + num(raw) +
                        " bytes where its node holds " + num(expected));
      }
      skip(raw, "an uncompressed chunk");
    }
    if (!decode || expected == 0) return;
    in_.is.seekg(static_cast<std::streamoff>(chunk));
    values.resize(expected);  // at most 32768 values of 24 bytes: the size now checked, OpenVDB reads it safely
    try {
      if (compression & io::COMPRESS_BLOSC) {
        io::bloscFromStream(in_.is, values.data(), expected);
      } else {
        io::unzipFromStream(in_.is, values.data(), expected);
      }
    } catch (const openvdb::Exception& e) {
      throw ReadError("corrupt: the chunk " + at(chunk) + " does not decode (" + printable(e.what(), 120) + ")");
    }
    check_booleans();
  }

  // io::readCompressedValues(is, buf, count, value_mask, from_half).
  template <typename ValueT, typename MaskT>
  void compressed_values(uint64_t count, const MaskT& value_mask, bool from_half, bool decode) {
    namespace io = openvdb::io;
    constexpr bool booleans = std::is_same_v<ValueT, bool>;
    const uint32_t compression = io::getDataCompression(in_.is);
    const bool node_masks = version() >= openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION;
    int8_t meta = io::NO_MASK_AND_ALL_VALS;
    if (node_masks) read_pod(in_.is, &meta);
    const bool inactive = meta == io::NO_MASK_AND_ONE_INACTIVE_VAL || meta == io::MASK_AND_ONE_INACTIVE_VAL ||
                          meta == io::MASK_AND_TWO_INACTIVE_VALS;
    auto inactive_value = [&] {
      if constexpr (booleans) {
        data(1, 1, 0, true, true);  // read raw into a bool
      } else {
        skip(sizeof(ValueT), "an inactive value");
      }
    };
    if (inactive) inactive_value();
    if (meta == io::MASK_AND_TWO_INACTIVE_VALS) inactive_value();
    if (meta == io::MASK_AND_NO_INACTIVE_VALS || meta == io::MASK_AND_ONE_INACTIVE_VAL ||
        meta == io::MASK_AND_TWO_INACTIVE_VALS) {
      skip(MaskT::memUsage(), "a selection mask");
    }
    if ((compression & io::COMPRESS_ACTIVE_MASK) && meta != io::NO_MASK_AND_ALL_VALS && node_masks) {
      count = value_mask.countOn();
    }
    using Half = io::RealToHalf<ValueT>;
    if (from_half && Half::isReal) {
      if (count >= 1) data(count, sizeof(typename Half::HalfT), compression, decode, false);  // HalfReader skips 0
    } else {
      data(count, sizeof(ValueT), compression, decode || booleans, booleans);
    }
  }

  template <typename NodeT>
  void node_topology(bool from_half) {
    using MaskT = typename NodeT::NodeMaskType;
    if constexpr (NodeT::LEVEL == 0) {
      skip(MaskT::memUsage(), "a leaf's value mask");
    } else {
      using ChildT = typename NodeT::ChildNodeType;
      using ValueT = typename NodeT::ValueType;
      const MaskT children = mask<MaskT>();
      const MaskT values = mask<MaskT>();
      if (version() < openvdb::OPENVDB_FILE_VERSION_INTERNALNODE_COMPRESSION) {
        for (openvdb::Index i = 0; i < NodeT::NUM_VALUES; ++i) {
          if (children.isOn(i)) {
            node_topology<ChildT>(false);
          } else {
            skip(sizeof(ValueT), "a tile value");
          }
        }
        return;
      }
      const bool old = version() < openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION;
      compressed_values<ValueT>(old ? children.countOff() : NodeT::NUM_VALUES, values, from_half, /*decode=*/true);
      for (auto it = children.beginOn(); it; ++it) node_topology<ChildT>(from_half);
    }
  }

  template <typename LeafT>
  void leaf_buffers(bool from_half) {
    using MaskT = typename LeafT::NodeMaskType;
    using ValueT = typename LeafT::ValueType;
    constexpr size_t kOrigin = 3 * sizeof(int32_t);
    if constexpr (std::is_same_v<ValueT, openvdb::ValueMask>) {
      skip(MaskT::memUsage() + kOrigin, "a mask leaf");
    } else if constexpr (std::is_same_v<ValueT, bool>) {
      skip(MaskT::memUsage() + kOrigin, "a bool leaf's mask and origin");
      if (version() >= openvdb::OPENVDB_FILE_VERSION_BOOL_LEAF_OPTIMIZATION) {
        skip(MaskT::memUsage(), "a bool leaf's values");
      } else {
        int8_t count = 0;
        read_pod(in_.is, &count);
        // readData(..., isCompressed=true) into bools
        for (int i = 0; i < std::max<int>(count, 1); ++i) data(LeafT::SIZE, sizeof(bool), openvdb::io::COMPRESS_ZIP, true, true);
      }
    } else {
      const MaskT values = mask<MaskT>();
      int8_t count = 1;
      if (version() < openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION) {
        skip(kOrigin, "a leaf origin");
        read_pod(in_.is, &count);
      }
      compressed_values<ValueT>(LeafT::SIZE, values, from_half, /*decode=*/false);
      // Auxiliary buffers of early files: not mask compressed, zipped or raw.
      const uint32_t aux = openvdb::io::getDataCompression(in_.is) & openvdb::io::COMPRESS_ZIP;
      using Half = openvdb::io::RealToHalf<ValueT>;
      const size_t bytes = from_half && Half::isReal ? sizeof(typename Half::HalfT) : sizeof(ValueT);
      for (int i = 1; i < count; ++i) data(LeafT::SIZE, bytes, aux, false, false);
    }
  }

  Input& in_;
  std::string grid_;
};

// Tree::readTopology + RootNode::readTopology (format >= 213), leak-free:
// each child is owned by a unique_ptr until the root owns it.
template <typename GridT>
void read_topology_safely(GridT& grid, std::istream& is, ChunkCheck& check) {
  using TreeT = typename GridT::TreeType;
  using RootT = typename TreeT::RootNodeType;
  using ChildT = typename RootT::ChildNodeType;
  using ValueT = typename TreeT::ValueType;

  int32_t buffer_count = 0;  // always 1 since OpenVDB 1.0
  read_pod(is, &buffer_count);
  RootT& root = grid.tree().root();
  ValueT background{};
  read_value(is, &background);
  root.setBackground(background, /*updateChildNodes=*/false);
  openvdb::io::setGridBackgroundValuePtr(is, &root.background());

  openvdb::Index num_tiles = 0, num_children = 0;
  read_pod(is, &num_tiles);
  read_pod(is, &num_children);
  for (openvdb::Index n = 0; n < num_tiles; ++n) {
    int32_t v[3];
    ValueT value{};
    uint8_t active = 0;
    is.read(reinterpret_cast<char*>(v), sizeof(v));
    read_value(is, &value);
    read_pod(is, &active);
    root.addTile(Coord(v[0], v[1], v[2]), value, active != 0);
  }
  for (openvdb::Index n = 0; n < num_children; ++n) {
    int32_t v[3];
    is.read(reinterpret_cast<char*>(v), sizeof(v));
    check.topology<ChildT>(grid.saveFloatAsHalf());
    std::unique_ptr<ChildT> child(
        new ChildT(openvdb::PartialCreate(), Coord(v[0], v[1], v[2]), root.background()));
    child->readTopology(is, grid.saveFloatAsHalf());
    root.addChild(child.release());
  }
}

// The grid types whose trees we can read (or read past, in a stream without
// grid offsets). Point grids are not among them.
using ReadableGrids =
    openvdb::TypeList<openvdb::FloatGrid, openvdb::DoubleGrid, openvdb::Int32Grid, openvdb::Int64Grid,
                      openvdb::Vec3IGrid, openvdb::Vec3SGrid, openvdb::Vec3DGrid, openvdb::BoolGrid,
                      openvdb::MaskGrid>;
using DensityGrids = openvdb::TypeList<openvdb::FloatGrid, openvdb::DoubleGrid>;

// The part of io::Archive::readGrid after the metadata: transform, topology, buffers.
void read_grid_body(openvdb::GridBase& grid, const Descriptor& d, Input& in, uint32_t version) {
  ChunkCheck check(in, d.name);
  auto read_topology = [&] {
    const bool known = grid.apply<ReadableGrids>([&](auto& g) { read_topology_safely(g, in.is, check); });
    if (!known) {
      throw ReadError("cannot read grid " + quoted(d.name) + " of type " + printable(d.type) +
                      " (not a supported grid type)");
    }
  };
  auto read_buffers = [&] {
    grid.apply<ReadableGrids>([&](auto& g) {
      using LeafT = typename std::decay_t<decltype(g)>::TreeType::LeafNodeType;
      check.buffers<LeafT>(g.tree().leafCount(), g.saveFloatAsHalf());
    });
    grid.readBuffers(in.is);
  };
  if (version >= openvdb::OPENVDB_FILE_VERSION_GRID_INSTANCING) {
    grid.readTransform(in.is);
    if (d.instance_parent.empty()) {
      read_topology();
      read_buffers();
    }
  } else {
    // Older files stored the transform after the topology.
    read_topology();
    grid.readTransform(in.is);
    read_buffers();
  }
}

struct GridInfo {
  std::string name;
  std::string type;
  bool level_set = false;
};

std::string list_grids(const std::vector<GridInfo>& grids) {
  std::string s;
  for (const GridInfo& g : grids) {
    if (!s.empty()) s += ", ";
    s += quoted(g.name) + " (" + printable(g.type, 60) + (g.level_set ? ", level set" : "") + ")";
  }
  return s;
}

const char* kLevelSetMessage = "is a level set (signed distance), not a density fog volume";

// Budget: smallest integer factor f (same on all axes) such that the
// downsampled box plus one voxel of padding per side fits max_voxels.
bool fits(const int64_t dims[3], int64_t f, uint64_t max_voxels, int64_t out[3]) {
  constexpr int64_t kMaxAxis = int64_t{1} << 30;  // DenseGrid axes are int
  uint64_t total = 1;
  for (int a = 0; a < 3; ++a) {
    out[a] = (dims[a] + f - 1) / f + 2;
    if (out[a] > kMaxAxis) return false;
    const uint64_t n = static_cast<uint64_t>(out[a]);
    if (total > std::numeric_limits<uint64_t>::max() / n) return false;
    total *= n;
  }
  return total <= max_voxels;
}

// extract(): one VDB grid -> r->volume, in the steps below. Each step throws
// ReadError for what it refuses and adds its warnings in the order a reader
// meets them (the tests compare messages).

// Step 1. The grid's index-to-world map must be a uniform scale plus a
// translation: CloudVolume has one voxel size, and its rotation belongs to the
// layer (heading), not to the file. Returns the voxel size (file units).
double uniform_voxel_size(const openvdb::math::Transform& xf, const std::string& where) {
  if (!xf.isLinear()) {
    throw ReadError(where + " has a non-linear transform (" + printable(xf.mapType()) +
                    "); only uniform scale + translation is supported");
  }
  const openvdb::Vec3d vs3 = xf.voxelSize();
  if (!xf.hasUniformScale() || std::abs(vs3[0] - vs3[1]) > 1e-9 * std::abs(vs3[0]) ||
      std::abs(vs3[0] - vs3[2]) > 1e-9 * std::abs(vs3[0])) {
    throw ReadError(where + " has a non-uniform voxel size (" + num(vs3[0]) + " x " + num(vs3[1]) +
                    " x " + num(vs3[2]) + "); only uniform voxels are supported");
  }
  const double vs = vs3[0];
  if (!std::isfinite(vs) || !(vs > 0.0)) throw ReadError(where + " has an invalid voxel size " + num(vs));
  const openvdb::Mat3d linear = xf.baseMap()->getAffineMap()->getMat4().getMat3();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (std::abs(linear(i, j) - (i == j ? vs : 0.0)) > 1e-9 * vs) {
        throw ReadError(where +
                        " has a rotated, sheared or mirrored transform; only uniform scale + "
                        "translation is supported (the layer's heading rotates the cloud)");
      }
    }
  }
  return vs;
}

// Where the active voxels go in the dense grid: their bounding box (fine
// voxels), the downsampling factor f, and the dense size n (box / f, plus
// one voxel of zero padding per side).
struct DenseLayout {
  CoordBBox bbox;
  int64_t dims[3] = {0, 0, 0};
  int64_t f = 1;
  int64_t n[3] = {0, 0, 0};
  // The coarse cell (before padding) of fine index c on axis a.
  int64_t coarse(int a, int32_t c) const { return (int64_t{c} - bbox.min()[a]) / f; }
};

// Step 2. The active box, and the smallest factor that fits max_voxels (a
// larger grid is downsampled, never refused).
template <typename GridT>
DenseLayout plan_dense_grid(const GridT& grid, uint64_t max_voxels, const std::string& where) {
  if (grid.activeVoxelCount() == 0) throw ReadError(where + " is empty: no active voxels");
  DenseLayout l;
  l.bbox = grid.evalActiveVoxelBoundingBox();
  for (int a = 0; a < 3; ++a) l.dims[a] = int64_t{l.bbox.max()[a]} - l.bbox.min()[a] + 1;
  // fits() is monotone in f, and f = max(dims) fits (3^3 voxels): the least f
  // by doubling, then bisection (a thin box 2^30 voxels long took 1e9 steps
  // one at a time; found by fuzz/vdb_fuzz.cpp).
  int64_t lo = 0, hi = 1;  // fits(lo) false (f = 0 is no factor), fits(hi) to be found
  const int64_t longest = std::max({l.dims[0], l.dims[1], l.dims[2], int64_t{1}});
  while (hi < longest && !fits(l.dims, hi, max_voxels, l.n)) {
    lo = hi;
    hi = std::min(hi * 2, longest);
  }
  while (hi - lo > 1) {
    const int64_t mid = lo + (hi - lo) / 2;
    if (fits(l.dims, mid, max_voxels, l.n)) hi = mid; else lo = mid;
  }
  l.f = hi;
  // Also sets l.n for this f (the last call may have been a failed mid).
  if (!fits(l.dims, l.f, max_voxels, l.n)) throw ReadError(where + ": no downsampling fits max_voxels " + num(max_voxels));
  return l;
}

// What step 3 saw, for the checks and warnings of step 4.
struct ValueStats {
  uint64_t nan_count = 0;
  uint64_t negative_count = 0;
  Coord first_nan;
  double min_value = 0.0;  // the most negative value (before clamping)
  double max_value = 0.0;  // after clamping and density_scale
};

// A tile (one value over a box of fine voxels) adds v times its overlap, in
// fine voxels, with each coarse cell: the sum is mass, averaged in step 4.
void add_tile(const CoordBBox& box, double v, const DenseLayout& l, clouds::DenseGrid* dense) {
  int64_t lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = l.coarse(a, std::max(box.min()[a], l.bbox.min()[a]));
    hi[a] = l.coarse(a, std::min(box.max()[a], l.bbox.max()[a]));
  }
  const auto overlap = [&](int a, int64_t cell) {
    const int64_t cell_lo = l.bbox.min()[a] + cell * l.f, cell_hi = cell_lo + l.f - 1;
    return std::min<int64_t>(box.max()[a], cell_hi) - std::max<int64_t>(box.min()[a], cell_lo) + 1;
  };
  for (int64_t z = lo[2]; z <= hi[2]; ++z) {
    for (int64_t y = lo[1]; y <= hi[1]; ++y) {
      for (int64_t x = lo[0]; x <= hi[0]; ++x) {
        const double count = static_cast<double>(overlap(0, x)) * static_cast<double>(overlap(1, y)) *
                             static_cast<double>(overlap(2, z));  // up to 2^93: not in int64
        dense->at(static_cast<int>(x + 1), static_cast<int>(y + 1), static_cast<int>(z + 1)) +=
            static_cast<float>(v * count);
      }
    }
  }
}

// Step 3. Sums every active value (voxels and tiles) into its coarse cell,
// negative values clamped to 0, times density_scale. NaNs are counted, not
// summed, so step 4 can name the first one.
template <typename GridT>
ValueStats accumulate_values(const GridT& grid, const DenseLayout& l, double scale, clouds::DenseGrid* dense) {
  ValueStats s;
  for (auto it = grid.cbeginValueOn(); it; ++it) {
    const double raw = static_cast<double>(*it);
    CoordBBox box;
    it.getBoundingBox(box);  // one voxel, or a tile's extent
    if (!std::isfinite(raw)) {
      if (s.nan_count == 0) s.first_nan = box.min();
      s.nan_count += box.volume();
      continue;
    }
    if (raw < 0.0) {
      s.negative_count += box.volume();
      s.min_value = std::min(s.min_value, raw);
    }
    const double v = std::max(raw, 0.0) * scale;
    s.max_value = std::max(s.max_value, v);
    if (v == 0.0) continue;
    if (it.isVoxelValue()) {
      const Coord c = it.getCoord();
      dense->at(static_cast<int>(l.coarse(0, c.x()) + 1), static_cast<int>(l.coarse(1, c.y()) + 1),
                static_cast<int>(l.coarse(2, c.z()) + 1)) += static_cast<float>(v);
      continue;
    }
    add_tile(box, v, l, dense);
  }
  return s;
}

// Step 4. Refuses NaNs; turns the sums into means (downsampling preserves
// mass); warns of downsampling, clamped values, implausible densities and an
// ignored background.
void finish_values(const ValueStats& s, const DenseLayout& l, double voxel_size, double background,
                   const LoadOptions& options, const std::string& label, const std::string& where,
                   clouds::DenseGrid* dense, std::vector<std::string>* warnings) {
  if (s.nan_count > 0) {
    throw ReadError(where + " has " + num(s.nan_count) + " NaN or infinite value(s) (first at index " +
                    coord_str(s.first_nan) + ")");
  }
  if (l.f > 1) {
    const double fine_per_coarse = static_cast<double>(l.f) * l.f * l.f;
    for (float& v : dense->values) v = static_cast<float>(static_cast<double>(v) / fine_per_coarse);
    const double vs_m = voxel_size * options.metres_per_unit;
    warnings->push_back(label + ": " + num(l.dims[0]) + "x" + num(l.dims[1]) + "x" + num(l.dims[2]) +
                        " active voxels exceed max_voxels " + num(options.max_voxels) + ": downsampled by " +
                        num(l.f) + " (box filter, mass preserved) to " + num(l.n[0]) + "x" + num(l.n[1]) + "x" +
                        num(l.n[2]) + " with padding, voxel " + num(vs_m) + " m -> " +
                        num(vs_m * static_cast<double>(l.f)) + " m");
  }
  // Float sums of huge values (or of a huge density_scale) overflow to inf.
  for (const float v : dense->values) {
    if (!std::isfinite(v)) {
      throw ReadError(where + ": densities exceed the float range after density_scale " + num(options.density_scale) +
                      " (max value " + num(s.max_value) + ")");
    }
  }
  if (s.negative_count > 0) {
    warnings->push_back(label + ": " + num(s.negative_count) + " negative value(s) (min " + num(s.min_value) +
                        ") clamped to 0");
  }
  if (s.max_value > 10.0) {
    warnings->push_back(label + ": max density " + num(s.max_value) +
                        " (after density_scale) is above 10; values above 1 are kept (the extinction "
                        "scales them): check the grid and density_scale");
  }
  if (background != 0.0) {
    warnings->push_back(label + ": background " + num(background) +
                        " ignored: voxels outside the active ones are read as 0");
  }
}

// Step 5. Places the dense grid in the scene. Dense voxel d (padding
// included) covers fine voxels bmin + f*(d-1) .. + f-1; OpenVDB voxel centres
// are at integer index coordinates, so its lower corner is at index
// bmin + f*(d-1) - 0.5, i.e. bmin - f - 0.5 for d = 0.
void place_volume(const openvdb::math::Transform& xf, const DenseLayout& l, double voxel_size,
                  double metres_per_unit, clouds::CloudVolume* vol) {
  const Coord bmin = l.bbox.min();
  const openvdb::Vec3d corner = xf.indexToWorld(openvdb::Vec3d(bmin.x(), bmin.y(), bmin.z()) -
                                                openvdb::Vec3d(static_cast<double>(l.f) + 0.5));
  vol->origin_enu_m = glm::dvec3(corner[0], corner[1], corner[2]) * metres_per_unit;
  vol->voxel_size_m = static_cast<float>(voxel_size * metres_per_unit * static_cast<double>(l.f));
  vol->rotation = glm::dquat(1.0, 0.0, 0.0, 0.0);
}

// Step 6. The optics written by write_vdb_* (or by hand) as grid metadata:
// each valid one replaces the default, an invalid one is ignored with a warning.
void restore_optics(const openvdb::GridBase& grid, const std::string& label, clouds::CloudOptics* optics,
                    std::vector<std::string>* warnings) {
  const auto restore = [&](const char* key, float* out, double lo, double hi) {
    const openvdb::Metadata::ConstPtr m = grid[key];
    if (!m) return;
    double v = std::numeric_limits<double>::quiet_NaN();
    if (const auto* fm = dynamic_cast<const openvdb::FloatMetadata*>(m.get())) v = fm->value();
    if (const auto* dm = dynamic_cast<const openvdb::DoubleMetadata*>(m.get())) v = dm->value();
    if (std::isfinite(v) && v >= lo && v <= hi) {
      *out = static_cast<float>(v);
    } else {
      warnings->push_back(label + ": metadata " + key + " (" + printable(m->typeName()) + " " +
                          printable(m->str(), 40) + ") ignored: expected a float in [" + num(lo) + ", " +
                          num(hi) + "]");
    }
  };
  const double big = std::numeric_limits<double>::max();
  restore("atmo_extinction_per_m", &optics->extinction_per_m, 0.0, big);
  restore("atmo_albedo", &optics->albedo, 0.0, 1.0);
  restore("atmo_droplet_diameter_um", &optics->droplet_diameter_um, 0.0, big);
}

template <typename GridT>
void extract(const GridT& grid, const std::string& source, const LoadOptions& options, LoadResult* r) {
  const std::string label = source + ": grid " + quoted(grid.getName());
  const std::string where = "grid " + quoted(grid.getName());
  clouds::CloudVolume& vol = r->volume;
  const openvdb::math::Transform& xf = grid.constTransform();
  const double voxel_size = uniform_voxel_size(xf, where);
  const DenseLayout layout = plan_dense_grid(grid, options.max_voxels, where);
  vol.density = clouds::DenseGrid(static_cast<int>(layout.n[0]), static_cast<int>(layout.n[1]),
                                  static_cast<int>(layout.n[2]));
  const ValueStats stats = accumulate_values(grid, layout, options.density_scale, &vol.density);
  finish_values(stats, layout, voxel_size, static_cast<double>(grid.background()), options, label, where,
                &vol.density, &r->warnings);
  place_volume(xf, layout, voxel_size, options.metres_per_unit, &vol);
  vol.name = source + ":" + grid.getName();
  restore_optics(grid, label, &vol.optics, &r->warnings);
}

void load_impl(const std::string& bytes, const std::string& source, const LoadOptions& options, Input& in,
               LoadResult* r) {
  std::istream& is = in.is;
  VdbArchive archive;
  archive.readHeader(is);  // magic, versions, UUID; throws on a bad header
  const uint32_t version = archive.fileVersion();
  if (version < openvdb::OPENVDB_FILE_VERSION_ROOTNODE_MAP) {
    throw ReadError("VDB file format version " + num(version) +
                    " predates OpenVDB 1.0 (format 213); re-save it with a current OpenVDB");
  }
  // As io::Stream: tag the stream with the versions and compression.
  in.file_meta = std::make_shared<openvdb::io::StreamMetadata>();
  openvdb::io::setStreamMetadataPtr(is, in.file_meta, /*transfer=*/false);
  openvdb::io::setVersion(is, archive.libraryVersion(), version);
  openvdb::io::setDataCompression(is, archive.compression());

  openvdb::MetaMap file_metadata;
  check_metadata(in);
  file_metadata.readMeta(is);
  int32_t grid_count = 0;
  read_pod(is, &grid_count);
  if (grid_count == 0) throw ReadError("contains no grids");
  if (grid_count < 0) throw ReadError("corrupt: negative grid count " + num(grid_count));

  const bool offsets = archive.inputHasGridOffsets();
  const std::string& want = options.grid_name;
  std::vector<GridInfo> seen;
  for (int32_t i = 0; i < grid_count; ++i) {
    const Descriptor d = read_descriptor(in, version);
    const bool named = !want.empty() && d.name == want;
    if (offsets) {
      if (d.end_pos > static_cast<int64_t>(bytes.size())) {
        throw ReadError("truncated: grid " + quoted(d.name) + " ends at byte " + num(d.end_pos) +
                        " but the data has only " + num(bytes.size()) + " bytes");
      }
      if (d.end_pos < static_cast<int64_t>(in.buf.position())) {
        throw ReadError("corrupt: grid " + quoted(d.name) + " has an end offset (" + num(d.end_pos) +
                        ") before its start (" + num(in.buf.position()) + ")");
      }
    }
    GridInfo info{d.name, d.type, false};
    if (!openvdb::GridBase::isRegistered(d.type)) {
      if (named) throw ReadError("grid " + quoted(d.name) + " has type " + printable(d.type) + ", which OpenVDB does not know");
      if (!offsets) {
        throw ReadError("grid " + quoted(d.name) + " has unknown type " + printable(d.type) +
                        " and the data has no grid offsets to skip it");
      }
      seen.push_back(info);
      is.seekg(d.end_pos);
      continue;
    }
    openvdb::GridBase::Ptr grid = openvdb::GridBase::createGrid(d.type);
    grid->setSaveFloatAsHalf(d.half);

    // As io::Archive::readGrid: per-grid compression and stream metadata.
    VdbArchive::readGridCompression(is);
    in.grid_meta = std::make_shared<openvdb::io::StreamMetadata>(*in.file_meta);
    in.grid_meta->setHalfFloat(d.half);
    openvdb::io::setStreamMetadataPtr(is, in.grid_meta, /*transfer=*/false);
    openvdb::io::setGridClass(is, openvdb::GRID_UNKNOWN);
    openvdb::io::setGridBackgroundValuePtr(is, nullptr);
    check_metadata(in);
    grid->readMeta(is);
    in.grid_meta->gridMetadata() = static_cast<openvdb::MetaMap&>(*grid);
    openvdb::io::setGridClass(is, grid->getGridClass());
    // Files before format 219 kept names only in the descriptor.
    if (grid->getName().empty()) grid->setName(d.name);

    info.type = grid->valueType();
    info.level_set = grid->getGridClass() == openvdb::GRID_LEVEL_SET;
    const bool scalar = grid->isType<openvdb::FloatGrid>() || grid->isType<openvdb::DoubleGrid>();
    bool selected = false;
    if (named) {
      if (!scalar) {
        throw ReadError("grid " + quoted(d.name) + " has value type " + printable(info.type) +
                        ", not a float density (fog volume) grid");
      }
      if (info.level_set) throw ReadError("grid " + quoted(d.name) + " " + kLevelSetMessage);
      selected = true;
    } else if (want.empty() && scalar && !info.level_set) {
      selected = true;
    }
    if (selected && !d.instance_parent.empty()) {
      throw ReadError("grid " + quoted(d.name) + " shares the tree of grid " + quoted(d.instance_parent) +
                      " (an instance); instanced grids are not supported");
    }
    if (selected) {
      read_grid_body(*grid, d, in, version);
      openvdb::io::setStreamMetadataPtr(is, in.file_meta, /*transfer=*/false);
      grid->apply<DensityGrids>([&](const auto& g) { extract(g, source, options, r); });
      r->ok = true;
      return;
    }
    if (offsets) {
      is.seekg(d.end_pos);
    } else {
      read_grid_body(*grid, d, in, version);
    }
    openvdb::io::setStreamMetadataPtr(is, in.file_meta, /*transfer=*/false);
    seen.push_back(info);
  }

  if (!want.empty()) throw ReadError("no float grid named " + quoted(want) + " (grids: " + list_grids(seen) + ")");
  for (const GridInfo& g : seen) {
    if (g.level_set && (g.type == "float" || g.type == "double")) {
      throw ReadError("no float fog-volume grid: grid " + quoted(g.name) + " " + kLevelSetMessage +
                      " (grids: " + list_grids(seen) + ")");
    }
  }
  throw ReadError("no float grid (grids: " + list_grids(seen) + ")");
}

std::string check_options(const LoadOptions& o) {
  if (!std::isfinite(o.metres_per_unit) || !(o.metres_per_unit > 0.0)) {
    return "invalid metres_per_unit " + num(o.metres_per_unit) + " (must be > 0)";
  }
  if (!std::isfinite(o.density_scale) || o.density_scale < 0.0) {
    return "invalid density_scale " + num(o.density_scale) + " (must be >= 0)";
  }
  if (o.max_voxels < 27) return "invalid max_voxels " + num(o.max_voxels) + " (must be at least 27 = 3^3)";
  return "";
}

std::string volume_label(const clouds::CloudVolume& v, size_t i) {
  return "volume " + num(i) + (v.name.empty() ? std::string() : " (" + quoted(v.name) + ")");
}

std::string check_volume(const clouds::CloudVolume& v, size_t i) {
  const std::string label = volume_label(v, i);
  const clouds::DenseGrid& g = v.density;
  if (g.nx <= 0 || g.ny <= 0 || g.nz <= 0) return label + ": empty density grid";
  if (g.values.size() != static_cast<size_t>(g.nx) * g.ny * g.nz) {
    return label + ": density has " + num(g.values.size()) + " values for " + num(g.nx) + "x" + num(g.ny) +
           "x" + num(g.nz);
  }
  if (!std::isfinite(v.voxel_size_m) || !(v.voxel_size_m > 0.0f)) {
    return label + ": invalid voxel_size_m " + num(v.voxel_size_m);
  }
  if (!std::isfinite(v.origin_enu_m.x) || !std::isfinite(v.origin_enu_m.y) || !std::isfinite(v.origin_enu_m.z)) {
    return label + ": non-finite origin_enu_m";
  }
  const glm::dquat& q = v.rotation;
  if (std::abs(std::abs(q.w) - 1.0) > 1e-9 || std::abs(q.x) > 1e-9 || std::abs(q.y) > 1e-9 ||
      std::abs(q.z) > 1e-9) {
    return label + ": rotated volumes are not supported yet (rotation must be identity)";
  }
  size_t bad = 0;
  for (float x : g.values) bad += std::isfinite(x) ? 0 : 1;
  if (bad) return label + ": " + num(bad) + " NaN or infinite density value(s)";
  return "";
}

}  // namespace

LoadResult load_vdb_from_memory(const std::string& bytes, const std::string& source_name,
                                const LoadOptions& options) {
  LoadResult r;
  const auto fail = [&](const std::string& msg) {
    LoadResult f;
    f.error = source_name + ": " + msg;
    return f;
  };
  if (const std::string e = check_options(options); !e.empty()) return fail(e);
  if (bytes.empty()) return fail("file is empty");
  int64_t magic = 0;
  if (bytes.size() >= sizeof(magic)) std::memcpy(&magic, bytes.data(), sizeof(magic));
  if (bytes.size() < sizeof(magic) || magic != openvdb::OPENVDB_MAGIC) {
    return fail("not a VDB file (bad magic number)");
  }
  init_openvdb();
  try {
    Input in(bytes);
    try {
      // OpenVDB's tools (active voxel count, bounding box) run on TBB, whose
      // worker threads would outlive the call (and a plugin must start none:
      // docs/ABI.md). An arena of one slot, the caller's: TBB starts no
      // worker; the reading itself is serial anyway.
      tbb::task_arena one_slot(1);
      one_slot.execute([&] { load_impl(bytes, source_name, options, in, &r); });
      return r;
    } catch (const ReadError& e) {
      return fail(e.what());
    } catch (const std::bad_alloc&) {
      return fail("corrupt VDB data: out of memory while reading (a size field is probably garbage)");
    } catch (const std::exception& e) {
      // The stream throws (ios_base::failure) at the first short read; the
      // exception type itself is unreliable across libstdc++ ABIs, the eof bit is not.
      if (in.is.eof() || in.buf.remaining() == 0) {
        return fail("truncated: the data (" + num(bytes.size()) + " bytes) ends inside the VDB structure");
      }
      return fail("corrupt VDB data (" + num(bytes.size()) + " bytes): " + printable(e.what()));
    }
  } catch (const std::bad_alloc&) {
    return fail("out of memory while reading");
  } catch (const std::exception& e) {
    return fail("error while reading: " + printable(e.what()));
  } catch (...) {
    return fail("unknown error while reading");
  }
}

LoadResult load_vdb_file(const std::string& path, const LoadOptions& options) {
  LoadResult r;
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    r.error = path + ": cannot read: is a directory";
    return r;
  }
  std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) {
    const int e = errno;
    r.error = path + ": cannot open: " + std::strerror(e);
    return r;
  }
  std::string bytes;
  try {
    char chunk[1 << 16];
    size_t got = 0;
    while ((got = std::fread(chunk, 1, sizeof(chunk), file.get())) > 0) bytes.append(chunk, got);
  } catch (const std::bad_alloc&) {
    r.error = path + ": out of memory reading the file";
    return r;
  }
  if (std::ferror(file.get())) {
    const int e = errno;
    r.error = path + ": read error: " + std::strerror(e);
    return r;
  }
  return load_vdb_from_memory(bytes, path, options);
}

std::string write_vdb_to_memory(const std::vector<clouds::CloudVolume>& volumes, std::string* out_bytes) {
  if (!out_bytes) return "write_vdb_to_memory: out_bytes is null";
  out_bytes->clear();
  if (volumes.empty()) return "nothing to write: no volumes";
  for (size_t i = 0; i < volumes.size(); ++i) {
    if (const std::string e = check_volume(volumes[i], i); !e.empty()) return e;
  }
  init_openvdb();
  try {
    openvdb::GridCPtrVec grids;
    for (size_t i = 0; i < volumes.size(); ++i) {
      const clouds::CloudVolume& v = volumes[i];
      openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
      grid->setName(i == 0 ? std::string("density") : "density_" + num(i));
      grid->setGridClass(openvdb::GRID_FOG_VOLUME);
      // CloudVolume voxel d has its centre at origin + (d + 0.5) * size;
      // OpenVDB voxel ijk has its centre at transform(ijk): shift by half a voxel.
      const double vs = static_cast<double>(v.voxel_size_m);
      openvdb::math::Transform::Ptr xf = openvdb::math::Transform::createLinearTransform(vs);
      xf->postTranslate(openvdb::Vec3d(v.origin_enu_m.x + 0.5 * vs, v.origin_enu_m.y + 0.5 * vs,
                                       v.origin_enu_m.z + 0.5 * vs));
      grid->setTransform(xf);
      openvdb::FloatGrid::Accessor acc = grid->getAccessor();
      const clouds::DenseGrid& g = v.density;
      for (int z = 0; z < g.nz; ++z) {
        for (int y = 0; y < g.ny; ++y) {
          for (int x = 0; x < g.nx; ++x) {
            const float d = g.at(x, y, z);
            if (d >= 1e-4f) acc.setValue(Coord(x, y, z), d);  // the rest stays inactive background
          }
        }
      }
      grid->insertMeta("atmo_name", openvdb::StringMetadata(v.name));
      grid->insertMeta("atmo_extinction_per_m", openvdb::FloatMetadata(v.optics.extinction_per_m));
      grid->insertMeta("atmo_albedo", openvdb::FloatMetadata(v.optics.albedo));
      grid->insertMeta("atmo_droplet_diameter_um", openvdb::FloatMetadata(v.optics.droplet_diameter_um));
      grids.push_back(grid);
    }
    openvdb::MetaMap file_meta;
    file_meta.insertMeta("creator", openvdb::StringMetadata("atmo"));
    std::ostringstream os(std::ios_base::out | std::ios_base::binary);
    VdbArchive archive;
    archive.write_seekable(os, grids, file_meta);
    if (!os) return "failed to serialise the VDB data";
    *out_bytes = os.str();
    return "";
  } catch (const std::bad_alloc&) {
    out_bytes->clear();
    return "out of memory while writing VDB data";
  } catch (const std::exception& e) {
    out_bytes->clear();
    return "error while writing VDB data: " + printable(e.what());
  }
}

std::string write_vdb_file(const std::string& path, const std::vector<clouds::CloudVolume>& volumes) {
  std::string bytes;
  if (std::string e = write_vdb_to_memory(volumes, &bytes); !e.empty()) return path + ": " + e;
  std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(path.c_str(), "wb"), &std::fclose);
  if (!file) {
    const int e = errno;
    return path + ": cannot open for writing: " + std::strerror(e);
  }
  if (std::fwrite(bytes.data(), 1, bytes.size(), file.get()) != bytes.size()) {
    const int e = errno;
    return path + ": write error: " + std::strerror(e);
  }
  FILE* f = file.release();
  if (std::fclose(f) != 0) {
    const int e = errno;
    return path + ": write error on close: " + std::strerror(e);
  }
  return "";
}

}  // namespace atmo::vdb
