// Gmsh .msh reader (4.1 ASCII and binary, 2.2 ASCII) and writer (4.1 ASCII).
//
// Element types kept: 2 (3-node triangle), 3 (4-node quad), 4 (4-node tet), 5 (8-node
// hex); 15 (point) and 1 (line) are skipped; anything else is an InputError naming the
// type, because dropping prisms or higher-order cells would silently lose volume.
// The element's entity tag (4.1) or elementary tag (2.2) becomes its label.
//
// Node order: Gmsh's linear tet and hex use VTK's order. Checked on Gmsh 4.8.4: every
// tet of a meshed box has det(p1-p0, p2-p0, p3-p0) > 0 and the hexes of an extruded
// transfinite box have nodes 0-3 counter-clockwise at the bottom, node i+4 above i
// (tests/mesh/test_io_volume.cpp repeats the check on a freshly meshed box).
//
// Gmsh node tags may be sparse and in any order, so they are mapped to dense indices
// (a lookup table when the tags are nearly dense, else a sorted table).
#include "mesh/binary_scalar.hpp"
#include "mesh/io_volume_common.hpp"
#include "mesh/text_scanner.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace structmesh {
namespace {

using detail::TextScanner;

enum class Kind { Skip, Triangle, Quad, Tet, Hex };

struct ElementType {
  int nodes = 0;
  Kind kind = Kind::Skip;
  const char* name = "";
};

/// The element types structmesh reads or skips; false for every other type.
bool known_element_type(std::int64_t type, ElementType& info) {
  static constexpr std::pair<int, ElementType> kKnown[] = {
      {15, {1, Kind::Skip, "point"}},        {1, {2, Kind::Skip, "line"}},       {2, {3, Kind::Triangle, "triangle"}},
      {3, {4, Kind::Quad, "quadrilateral"}}, {4, {4, Kind::Tet, "tetrahedron"}}, {5, {8, Kind::Hex, "hexahedron"}}};
  for (const auto& [id, known] : kKnown)
    if (id == type) {
      info = known;
      return true;
    }
  return false;
}

/// Names the Gmsh element types users are likely to meet.
std::string unsupported_type_message(std::int64_t type) {
  static constexpr std::pair<int, const char*> kNames[] = {{6, "6-node prism"},
                                                           {7, "5-node pyramid"},
                                                           {8, "3-node second-order line"},
                                                           {9, "6-node second-order triangle"},
                                                           {10, "9-node second-order quadrilateral"},
                                                           {11, "10-node second-order tetrahedron"},
                                                           {12, "27-node second-order hexahedron"},
                                                           {13, "18-node second-order prism"},
                                                           {14, "14-node second-order pyramid"},
                                                           {16, "8-node second-order quadrilateral"},
                                                           {17, "20-node second-order hexahedron"},
                                                           {18, "15-node second-order prism"},
                                                           {19, "13-node second-order pyramid"}};
  std::string message = "element type " + std::to_string(type);
  for (const auto& [id, name] : kNames)
    if (id == type) message += std::string(" (") + name + ")";
  message +=
      " is not supported; structmesh reads linear triangles, quadrilaterals, tetrahedra and hexahedra "
      "(types 2, 3, 4, 5)";
  // Types 8 and above (except the point, 15) are higher-order elements.
  if (type >= 8 && type != 15) message += "; for higher-order meshes export with Mesh.ElementOrder = 1";
  return message;
}

/// Gmsh node tag -> point index.
class NodeMap {
 public:
  /// `tags[i]` is the tag of point i. Throws (through `fail`) on a repeated tag.
  template <typename Fail>
  void build(const std::vector<std::uint64_t>& tags, Fail&& fail) {
    dense_.clear();
    sorted_.clear();
    if (tags.empty()) return;
    const auto [lo, hi] = std::minmax_element(tags.begin(), tags.end());
    min_ = *lo;
    const std::uint64_t range = *hi - *lo;
    // A table over the tag range is fastest; use it unless the tags are very sparse.
    use_dense_ = range < 2 * static_cast<std::uint64_t>(tags.size()) + 1024;
    if (use_dense_) {
      dense_.assign(static_cast<std::size_t>(range) + 1, kInvalidIndex);
      for (std::size_t i = 0; i < tags.size(); ++i) {
        Index& slot = dense_[static_cast<std::size_t>(tags[i] - min_)];
        if (slot != kInvalidIndex) fail("node tag " + std::to_string(tags[i]) + " appears twice in $Nodes");
        slot = static_cast<Index>(i);
      }
    } else {
      sorted_.reserve(tags.size());
      for (std::size_t i = 0; i < tags.size(); ++i) sorted_.emplace_back(tags[i], static_cast<Index>(i));
      std::sort(sorted_.begin(), sorted_.end());
      for (std::size_t i = 1; i < sorted_.size(); ++i)
        if (sorted_[i].first == sorted_[i - 1].first)
          fail("node tag " + std::to_string(sorted_[i].first) + " appears twice in $Nodes");
    }
  }

  /// The point index of `tag`, kInvalidIndex when no node has that tag.
  Index find(std::uint64_t tag) const {
    if (use_dense_) {
      if (tag < min_ || tag - min_ >= dense_.size()) return kInvalidIndex;
      return dense_[static_cast<std::size_t>(tag - min_)];
    }
    const auto it = std::lower_bound(sorted_.begin(), sorted_.end(), std::pair<std::uint64_t, Index>{tag, 0});
    return it != sorted_.end() && it->first == tag ? it->second : kInvalidIndex;
  }

 private:
  bool use_dense_ = true;
  std::uint64_t min_ = 0;
  std::vector<Index> dense_;
  std::vector<std::pair<std::uint64_t, Index>> sorted_;
};

/// Bounds-checked reads of a binary section (every read checks the remaining size).
class ByteReader {
 public:
  ByteReader(std::string_view data, std::size_t pos, bool swap, int size_bytes, const std::string& source)
      : data_(data), pos_(pos), swap_(swap), size_bytes_(size_bytes), source_(source) {}

  std::size_t position() const { return pos_; }
  std::size_t remaining() const { return data_.size() - pos_; }
  int size_bytes() const { return size_bytes_; }

  std::int32_t int32(const char* what) { return load<std::int32_t>(what); }
  double real(const char* what) { return load<double>(what); }
  /// A size_t field of the file (4 or 8 bytes, from the data-size of $MeshFormat).
  std::uint64_t size(const char* what) {
    return size_bytes_ == 8 ? load<std::uint64_t>(what) : std::uint64_t{load<std::uint32_t>(what)};
  }
  void skip(std::uint64_t bytes, const char* what) {
    if (bytes > remaining()) fail(std::string("truncated binary data: ") + what);
    pos_ += static_cast<std::size_t>(bytes);
  }
  [[noreturn]] void fail(const std::string& message) const {
    throw InputError(located_message(source_, 0, message + " (at byte " + std::to_string(pos_) + ")"));
  }

 private:
  template <typename T>
  T load(const char* what) {
    if (remaining() < sizeof(T)) fail(std::string("truncated binary data: expected ") + what);
    const T value = detail::load_scalar<T>(data_.data() + pos_, swap_);
    pos_ += sizeof(T);
    return value;
  }

  std::string_view data_;
  std::size_t pos_;
  bool swap_;
  int size_bytes_;
  const std::string& source_;
};

class MshReader {
 public:
  MshReader(std::string_view data, const std::string& source) : data_(data), source_(source), in_(data, source) {}

  MeshBundle read() {
    mesh_.source_name = source_;
    if (in_.at_end()) fail("empty file");
    if (in_.token() != "$MeshFormat") fail("not a Gmsh .msh file: expected '$MeshFormat' on the first line");
    read_format();
    while (!in_.at_end()) {
      const std::string_view section = in_.token();
      if (section.size() < 2 || section.front() != '$')
        fail("expected a section line such as '$Nodes', found '" + TextScanner::clip(section) + "'");
      if (section == "$Nodes") {
        if (have_nodes_) fail("second $Nodes section");
        if (version_ == 4)
          binary_ ? read_nodes_v4_binary() : read_nodes_v4_ascii();
        else
          read_nodes_v2();
        have_nodes_ = true;
      } else if (section == "$Elements") {
        if (!have_nodes_) fail("$Elements before $Nodes");
        if (have_elements_) fail("second $Elements section");
        if (version_ == 4)
          binary_ ? read_elements_v4_binary() : read_elements_v4_ascii();
        else
          read_elements_v2();
        have_elements_ = true;
      } else {
        skip_section(section.substr(1));
      }
    }
    if (!have_nodes_) fail("no $Nodes section");
    return std::move(mesh_);
  }

 private:
  [[noreturn]] void fail(const std::string& message) const {
    // Line numbers mean nothing inside a binary file.
    throw InputError(located_message(source_, binary_ ? 0 : in_.line(), message));
  }
  std::size_t absolute() const { return origin_ + in_.position(); }
  /// Continues text scanning at an absolute position (after a binary payload).
  void restart_at(std::size_t pos) {
    origin_ = pos;
    in_ = TextScanner(data_.substr(pos), source_);
  }
  void expect_end(std::string_view section) {
    const std::string_view token = in_.token();
    if (token.size() != section.size() + 4 || token.substr(0, 4) != "$End" || token.substr(4) != section)
      fail("expected '$End" + std::string(section) + "', found '" + TextScanner::clip(token) +
           "' (do the section's counts match its contents?)");
  }
  std::int32_t entity_tag(std::int64_t tag) const {
    if (tag < std::numeric_limits<std::int32_t>::min() || tag > std::numeric_limits<std::int32_t>::max())
      fail("entity tag " + std::to_string(tag) + " does not fit in 32 bits");
    return static_cast<std::int32_t>(tag);
  }
  /// A count read from the file, checked against what the rest of the file can hold
  /// (`min_bytes` per item) before anything is reserved for it.
  std::size_t checked_count(std::int64_t count, std::uint64_t min_bytes, std::size_t remaining, const char* what) {
    if (count < 0) fail(std::string("negative ") + what + " count " + std::to_string(count));
    if (static_cast<std::uint64_t>(count) > (remaining + 1) / min_bytes)
      fail(std::string(what) + " count " + std::to_string(count) + " exceeds what the file holds (truncated?)");
    return static_cast<std::size_t>(count);
  }

  void read_format() {
    const std::string_view version = in_.token();
    if (version == "4.1") {
      version_ = 4;
    } else if (version.size() >= 2 && version.substr(0, 2) == "2.") {
      version_ = 2;
    } else if (version == "4" || version == "4.0") {
      fail("MSH 4.0 is not supported; save as MSH 4.1 (Gmsh: -format msh41)");
    } else {
      fail("unsupported MSH version '" + TextScanner::clip(version) + "'; structmesh reads 4.1 and 2.2");
    }
    const std::int64_t file_type = in_.integer("file type (0 = ASCII, 1 = binary)");
    const std::int64_t data_size = in_.integer("data size");
    if (file_type != 0 && file_type != 1) fail("file type must be 0 (ASCII) or 1 (binary)");
    if (data_size != 4 && data_size != 8) fail("data size must be 4 or 8, found " + std::to_string(data_size));
    size_bytes_ = static_cast<int>(data_size);
    if (file_type == 1) {
      if (version_ != 4) fail("binary MSH 2 is not supported; save as MSH 4.1 (Gmsh: -format msh41)");
      in_.skip_line();
      // The integer 1 written in the file's byte order tells the endianness.
      ByteReader bytes(data_, absolute(), false, size_bytes_, source_);
      const std::int32_t one = bytes.int32("endianness marker");
      if (one == 1)
        swap_ = false;
      else if (one == 0x01000000)
        swap_ = true;
      else
        fail("bad endianness marker in binary $MeshFormat");
      binary_ = true;
      restart_at(bytes.position());
    }
    expect_end("MeshFormat");
  }

  /// Skips a section structmesh does not need ($Entities, $PhysicalNames, $NodeData...)
  /// line by line, which also works for binary sections: Gmsh ends them with "\n$EndX\n".
  void skip_section(std::string_view name) {
    const std::string end = "$End" + std::string(name);
    const std::uint32_t start_line = in_.line();
    in_.skip_line();
    while (!in_.at_end()) {
      std::string_view line = in_.read_line();
      while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
      while (!line.empty() && (line.back() == ' ' || line.back() == '\t')) line.remove_suffix(1);
      if (line == end) return;
    }
    throw InputError(located_message(source_, binary_ ? 0 : start_line,
                                     "section $" + std::string(name) + " has no " + end + " (truncated?)"));
  }

  void finish_nodes(std::uint64_t declared) {
    if (node_tags_.size() != declared)
      fail("$Nodes declares " + std::to_string(declared) + " nodes but its blocks hold " +
           std::to_string(node_tags_.size()));
    node_map_.build(node_tags_, [this](const std::string& message) { fail(message); });
    node_tags_ = {};
  }

  void read_nodes_v4_ascii() {
    const std::int64_t blocks = in_.integer("number of node blocks");
    const std::int64_t declared = in_.integer("number of nodes");
    in_.integer("minimum node tag");
    in_.integer("maximum node tag");
    if (blocks < 0 || declared < 0) fail("negative count in $Nodes");
    for (std::int64_t b = 0; b < blocks; ++b) {
      const std::int64_t dim = in_.integer("entity dimension");
      in_.integer("entity tag");
      const std::int64_t parametric = in_.integer("parametric flag");
      // A tag and three coordinates need at least 8 bytes per node.
      const std::size_t n = checked_count(in_.integer("number of nodes in block"), 8, in_.rest().size(), "node");
      if (dim < 0 || dim > 3) fail("entity dimension must be 0..3, found " + std::to_string(dim));
      if (parametric != 0 && parametric != 1) fail("parametric flag must be 0 or 1");
      if (node_tags_.size() + n >= kInvalidIndex) fail("too many nodes for 32-bit indices");
      const std::size_t first = node_tags_.size();
      node_tags_.reserve(first + n);
      for (std::size_t i = 0; i < n; ++i) {
        const std::int64_t tag = in_.integer("node tag");
        if (tag < 0) fail("negative node tag " + std::to_string(tag));
        node_tags_.push_back(static_cast<std::uint64_t>(tag));
      }
      mesh_.points.reserve(first + n);
      const int extra = parametric != 0 ? static_cast<int>(dim) : 0;
      for (std::size_t i = 0; i < n; ++i) {
        in_.skip_space();
        const std::uint32_t line = in_.line();
        const double x = in_.real("node x coordinate");
        const double y = in_.real("node y coordinate");
        const double z = in_.real("node z coordinate");
        for (int k = 0; k < extra; ++k) in_.real("parametric coordinate");
        mesh_.points.emplace_back(x, y, z);
        mesh_.lines.point_lines.push_back(line);
      }
    }
    finish_nodes(static_cast<std::uint64_t>(declared));
    expect_end("Nodes");
  }

  void read_nodes_v4_binary() {
    in_.skip_line();
    ByteReader bytes(data_, absolute(), swap_, size_bytes_, source_);
    const std::uint64_t blocks = bytes.size("number of node blocks");
    const std::uint64_t declared = bytes.size("number of nodes");
    bytes.size("minimum node tag");
    bytes.size("maximum node tag");
    for (std::uint64_t b = 0; b < blocks; ++b) {
      const std::int32_t dim = bytes.int32("entity dimension");
      bytes.int32("entity tag");
      const std::int32_t parametric = bytes.int32("parametric flag");
      const std::uint64_t n = bytes.size("number of nodes in block");
      if (dim < 0 || dim > 3) bytes.fail("entity dimension must be 0..3, found " + std::to_string(dim));
      if (parametric != 0 && parametric != 1) bytes.fail("parametric flag must be 0 or 1");
      const std::uint64_t per_node = static_cast<std::uint64_t>(size_bytes_) + 8 * (3 + (parametric ? dim : 0));
      if (n > bytes.remaining() / per_node)
        bytes.fail("node block declares " + std::to_string(n) + " nodes but the file is too short (truncated?)");
      if (node_tags_.size() + n >= kInvalidIndex) bytes.fail("too many nodes for 32-bit indices");
      const std::size_t count = static_cast<std::size_t>(n);
      node_tags_.reserve(node_tags_.size() + count);
      for (std::size_t i = 0; i < count; ++i) node_tags_.push_back(bytes.size("node tag"));
      mesh_.points.reserve(mesh_.points.size() + count);
      for (std::size_t i = 0; i < count; ++i) {
        const double x = bytes.real("node x coordinate");
        const double y = bytes.real("node y coordinate");
        const double z = bytes.real("node z coordinate");
        if (parametric != 0) bytes.skip(8 * static_cast<std::uint64_t>(dim), "parametric coordinates");
        if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
          bytes.fail("node " + std::to_string(node_tags_[mesh_.points.size()]) +
                     " has a coordinate that is not finite");
        mesh_.points.emplace_back(x, y, z);
      }
    }
    restart_at(bytes.position());
    finish_nodes(declared);
    expect_end("Nodes");
  }

  void add_element(const ElementType& type, const std::uint64_t* nodes, std::int32_t label, std::uint64_t tag,
                   std::uint32_t line) {
    if (type.kind == Kind::Skip) return;
    Index indices[8];
    for (int k = 0; k < type.nodes; ++k) {
      indices[k] = node_map_.find(nodes[k]);
      if (indices[k] == kInvalidIndex) {
        const std::string message = "element " + std::to_string(tag) + " (" + type.name + ") refers to node " +
                                    std::to_string(nodes[k]) + ", which is not in $Nodes";
        throw InputError(located_message(source_, binary_ ? 0 : line, message));
      }
    }
    switch (type.kind) {
      case Kind::Triangle:
        push(mesh_.triangles, mesh_.triangle_labels, mesh_.lines.triangle_lines, indices, label, line);
        break;
      case Kind::Quad:
        push(mesh_.quads, mesh_.quad_labels, mesh_.lines.quad_lines, indices, label, line);
        break;
      case Kind::Tet:
        push(mesh_.tets, mesh_.tet_labels, mesh_.lines.tet_lines, indices, label, line);
        break;
      case Kind::Hex:
        push(mesh_.hexes, mesh_.hex_labels, mesh_.lines.hex_lines, indices, label, line);
        break;
      case Kind::Skip:
        break;
    }
  }
  template <std::size_t N>
  void push(std::vector<std::array<Index, N>>& elements, std::vector<std::int32_t>& labels,
            std::vector<std::uint32_t>& lines, const Index* indices, std::int32_t label, std::uint32_t line) {
    std::array<Index, N> element;
    std::copy(indices, indices + N, element.begin());
    elements.push_back(element);
    labels.push_back(label);
    if (!binary_) lines.push_back(line);
  }

  void read_elements_v4_ascii() {
    const std::int64_t blocks = in_.integer("number of element blocks");
    const std::int64_t declared = in_.integer("number of elements");
    in_.integer("minimum element tag");
    in_.integer("maximum element tag");
    if (blocks < 0 || declared < 0) fail("negative count in $Elements");
    std::uint64_t total = 0;
    for (std::int64_t b = 0; b < blocks; ++b) {
      in_.integer("entity dimension");
      const std::int32_t label = entity_tag(in_.integer("entity tag"));
      const std::int64_t type_id = in_.integer("element type");
      ElementType type;
      if (!known_element_type(type_id, type)) fail(unsupported_type_message(type_id));
      const std::size_t n =
          checked_count(in_.integer("number of elements in block"), 2 * (1 + type.nodes), in_.rest().size(), "element");
      total += n;
      std::uint64_t nodes[8];
      for (std::size_t i = 0; i < n; ++i) {
        in_.skip_space();
        const std::uint32_t line = in_.line();
        const std::int64_t tag = in_.integer("element tag");
        for (int k = 0; k < type.nodes; ++k) {
          const std::int64_t node = in_.integer("element node tag");
          if (node < 0) fail("element " + std::to_string(tag) + " refers to negative node tag " + std::to_string(node));
          nodes[k] = static_cast<std::uint64_t>(node);
        }
        add_element(type, nodes, label, static_cast<std::uint64_t>(tag), line);
      }
    }
    if (total != static_cast<std::uint64_t>(declared))
      fail("$Elements declares " + std::to_string(declared) + " elements but its blocks hold " + std::to_string(total));
    expect_end("Elements");
  }

  void read_elements_v4_binary() {
    in_.skip_line();
    ByteReader bytes(data_, absolute(), swap_, size_bytes_, source_);
    const std::uint64_t blocks = bytes.size("number of element blocks");
    const std::uint64_t declared = bytes.size("number of elements");
    bytes.size("minimum element tag");
    bytes.size("maximum element tag");
    std::uint64_t total = 0;
    for (std::uint64_t b = 0; b < blocks; ++b) {
      bytes.int32("entity dimension");
      const std::int32_t label = bytes.int32("entity tag");
      const std::int32_t type_id = bytes.int32("element type");
      const std::uint64_t n = bytes.size("number of elements in block");
      ElementType type;
      if (!known_element_type(type_id, type)) bytes.fail(unsupported_type_message(type_id));
      const std::uint64_t per_element = static_cast<std::uint64_t>(size_bytes_) * (1 + type.nodes);
      if (n > bytes.remaining() / per_element)
        bytes.fail("element block declares " + std::to_string(n) + " elements but the file is too short (truncated?)");
      total += n;
      std::uint64_t nodes[8];
      for (std::uint64_t i = 0; i < n; ++i) {
        const std::uint64_t tag = bytes.size("element tag");
        for (int k = 0; k < type.nodes; ++k) nodes[k] = bytes.size("element node tag");
        add_element(type, nodes, label, tag, 0);
      }
    }
    if (total != declared)
      bytes.fail("$Elements declares " + std::to_string(declared) + " elements but its blocks hold " +
                 std::to_string(total));
    restart_at(bytes.position());
    expect_end("Elements");
  }

  void read_nodes_v2() {
    // "tag x y z" per line: at least 8 bytes per node.
    const std::size_t n = checked_count(in_.integer("number of nodes"), 8, in_.rest().size(), "node");
    if (n >= kInvalidIndex) fail("too many nodes for 32-bit indices");
    node_tags_.reserve(n);
    mesh_.points.reserve(n);
    mesh_.lines.point_lines.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
      in_.skip_space();
      const std::uint32_t line = in_.line();
      const std::int64_t tag = in_.integer("node tag");
      if (tag < 0) fail("negative node tag " + std::to_string(tag));
      node_tags_.push_back(static_cast<std::uint64_t>(tag));
      const double x = in_.real("node x coordinate");
      const double y = in_.real("node y coordinate");
      const double z = in_.real("node z coordinate");
      mesh_.points.emplace_back(x, y, z);
      mesh_.lines.point_lines.push_back(line);
    }
    finish_nodes(n);
    expect_end("Nodes");
  }

  void read_elements_v2() {
    // "tag type ntags nodes..." per line: at least 8 bytes per element.
    const std::size_t n = checked_count(in_.integer("number of elements"), 8, in_.rest().size(), "element");
    std::uint64_t nodes[8];
    for (std::size_t i = 0; i < n; ++i) {
      in_.skip_space();
      const std::uint32_t line = in_.line();
      const std::int64_t tag = in_.integer("element tag");
      const std::int64_t type_id = in_.integer("element type");
      ElementType type;
      if (!known_element_type(type_id, type)) fail(unsupported_type_message(type_id));
      const std::int64_t tag_count = in_.integer("number of tags");
      if (tag_count < 0 || static_cast<std::uint64_t>(tag_count) > in_.rest().size())
        fail("bad number of tags " + std::to_string(tag_count));
      // Tags are physical, elementary, then partition data: the elementary tag is
      // the geometric entity, the same thing MSH 4 stores per block.
      std::int32_t label = 0;
      for (std::int64_t t = 0; t < tag_count; ++t) {
        const std::int64_t value = in_.integer("element tag value");
        if (t == 1) label = entity_tag(value);
      }
      for (int k = 0; k < type.nodes; ++k) {
        const std::int64_t node = in_.integer("element node tag");
        if (node < 0) fail("element " + std::to_string(tag) + " refers to negative node tag " + std::to_string(node));
        nodes[k] = static_cast<std::uint64_t>(node);
      }
      add_element(type, nodes, label, static_cast<std::uint64_t>(tag), line);
    }
    expect_end("Elements");
  }

  std::string_view data_;
  const std::string& source_;
  TextScanner in_;
  std::size_t origin_ = 0;  // absolute position of in_'s first character
  int version_ = 0;
  bool binary_ = false;
  bool swap_ = false;
  int size_bytes_ = 8;
  bool have_nodes_ = false;
  bool have_elements_ = false;
  std::vector<std::uint64_t> node_tags_;
  NodeMap node_map_;
  MeshBundle mesh_;
};

// --- writer ---

struct Block {
  int dim;
  int type;
  std::int32_t entity;
  std::size_t begin, end;  // element range within its kind
};

/// Consecutive elements with the same label form one entity block, so the file keeps
/// the bundle's element order (reading it back gives the same element numbering).
template <std::size_t N>
void add_blocks(std::vector<Block>& blocks, const std::vector<std::array<Index, N>>& elements,
                const std::vector<std::int32_t>& labels, int dim, int type) {
  for (std::size_t e = 0; e < elements.size();) {
    const std::int32_t label = detail::volume_io::label_at(labels, e);
    std::size_t end = e + 1;
    while (end < elements.size() && detail::volume_io::label_at(labels, end) == label) ++end;
    blocks.push_back({dim, type, label, e, end});
    e = end;
  }
}

template <std::size_t N>
void write_block(std::string& out, const Block& block, const std::vector<std::array<Index, N>>& elements,
                 std::uint64_t& next_tag) {
  using detail::volume_io::append_int;
  append_int(out, block.dim);
  out += ' ';
  append_int(out, block.entity);
  out += ' ';
  append_int(out, block.type);
  out += ' ';
  append_int(out, static_cast<std::int64_t>(block.end - block.begin));
  out += '\n';
  for (std::size_t e = block.begin; e < block.end; ++e) {
    append_int(out, static_cast<std::int64_t>(next_tag++));
    for (const Index v : elements[e]) {
      out += ' ';
      append_int(out, std::int64_t{v} + 1);
    }
    out += '\n';
  }
}

}  // namespace

MeshBundle read_msh(std::string_view data, const std::string& source_name) {
  return MshReader(data, source_name).read();
}

std::string write_msh(const MeshBundle& mesh) {
  using detail::volume_io::append_int;
  using detail::volume_io::append_real;
  detail::volume_io::check_writable(mesh, "Gmsh MSH");

  std::vector<Block> blocks;
  add_blocks(blocks, mesh.triangles, mesh.triangle_labels, 2, 2);
  add_blocks(blocks, mesh.quads, mesh.quad_labels, 2, 3);
  add_blocks(blocks, mesh.tets, mesh.tet_labels, 3, 4);
  add_blocks(blocks, mesh.hexes, mesh.hex_labels, 3, 5);

  // One entity per distinct label and dimension: Gmsh needs every block's entity in
  // $Entities. Labels may be 0 or negative; Gmsh 4.8 accepts such entity tags.
  std::vector<std::int32_t> surfaces, volumes;
  for (const Block& b : blocks) (b.dim == 2 ? surfaces : volumes).push_back(b.entity);
  for (auto* tags : {&surfaces, &volumes}) {
    std::sort(tags->begin(), tags->end());
    tags->erase(std::unique(tags->begin(), tags->end()), tags->end());
  }
  // All nodes go into one block on an entity of the highest dimension present.
  int node_dim = 3;
  std::int32_t node_entity = 0;
  if (!volumes.empty()) {
    node_entity = volumes.front();
  } else if (!surfaces.empty()) {
    node_dim = 2;
    node_entity = surfaces.front();
  } else {
    volumes.push_back(0);  // no elements: an empty volume entity carries the nodes
  }

  std::string out;
  out.reserve(256 + 64 * mesh.points.size() + 48 * mesh.cell_count());
  out += "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 0 ";
  append_int(out, static_cast<std::int64_t>(surfaces.size()));
  out += ' ';
  append_int(out, static_cast<std::int64_t>(volumes.size()));
  out += '\n';
  const BoundingBox3 box = bounding_box(mesh.points);
  std::string extent;  // "minX minY minZ maxX maxY maxZ", the same for every entity
  for (int k = 0; k < 6; ++k) {
    append_real(extent, box.empty() ? 0.0 : (k < 3 ? box.min[k] : box.max[k - 3]));
    extent += ' ';
  }
  for (const auto* tags : {&surfaces, &volumes})
    for (const std::int32_t tag : *tags) {
      append_int(out, tag);
      out += ' ';
      out += extent;
      out += "0 0\n";  // no physical tags, no bounding entities
    }
  out += "$EndEntities\n$Nodes\n";

  const auto n = static_cast<std::int64_t>(mesh.points.size());
  if (n == 0) {
    out += "0 0 0 0\n";
  } else {
    out += "1 ";
    append_int(out, n);
    out += " 1 ";
    append_int(out, n);
    out += '\n';
    append_int(out, node_dim);
    out += ' ';
    append_int(out, node_entity);
    out += " 0 ";
    append_int(out, n);
    out += '\n';
    for (std::int64_t i = 1; i <= n; ++i) {
      append_int(out, i);
      out += '\n';
    }
    for (const Vec3& p : mesh.points) {
      append_real(out, p.x());
      out += ' ';
      append_real(out, p.y());
      out += ' ';
      append_real(out, p.z());
      out += '\n';
    }
  }
  out += "$EndNodes\n$Elements\n";
  const auto m = static_cast<std::int64_t>(mesh.cell_count());
  append_int(out, static_cast<std::int64_t>(blocks.size()));
  out += ' ';
  append_int(out, m);
  out += m == 0 ? " 0 0\n" : " 1 ";
  if (m != 0) {
    append_int(out, m);
    out += '\n';
  }
  std::uint64_t next_tag = 1;
  for (const Block& b : blocks) {
    switch (b.type) {
      case 2:
        write_block(out, b, mesh.triangles, next_tag);
        break;
      case 3:
        write_block(out, b, mesh.quads, next_tag);
        break;
      case 4:
        write_block(out, b, mesh.tets, next_tag);
        break;
      default:
        write_block(out, b, mesh.hexes, next_tag);
        break;
    }
  }
  out += "$EndElements\n";
  return out;
}

}  // namespace structmesh
