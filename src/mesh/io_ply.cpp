// Stanford PLY, ASCII and binary (both byte orders). Only vertex x/y/z and the
// face vertex index lists are kept; every other property and element is skipped
// with its declared size, so files with normals, colours or extra elements read.
#include "mesh/binary_scalar.hpp"
#include "mesh/surface_io.hpp"
#include "mesh/text_scanner.hpp"
#include "structmesh/io.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace structmesh {

namespace {

using detail::Scalar;
using detail::scalar_size;

// PLY has no 64-bit integer types.
std::optional<Scalar> scalar_from_name(std::string_view name) {
  if (name == "char" || name == "int8") return Scalar::Int8;
  if (name == "uchar" || name == "uint8") return Scalar::UInt8;
  if (name == "short" || name == "int16") return Scalar::Int16;
  if (name == "ushort" || name == "uint16") return Scalar::UInt16;
  if (name == "int" || name == "int32") return Scalar::Int32;
  if (name == "uint" || name == "uint32") return Scalar::UInt32;
  if (name == "float" || name == "float32") return Scalar::Float32;
  if (name == "double" || name == "float64") return Scalar::Float64;
  return std::nullopt;
}

// What the reader does with a property's values.
enum class Role : std::uint8_t { Skip, X, Y, Z, FaceIndices };

struct Property {
  Scalar type = Scalar::Float32;  // the item type for lists
  Scalar count_type = Scalar::UInt8;
  bool is_list = false;
  Role role = Role::Skip;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
};

enum class Layout : std::uint8_t { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct Header {
  Layout layout = Layout::Ascii;
  std::vector<Element> elements;
  std::uint64_t vertex_count = 0;
};

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (true) {
    i = line.find_first_not_of(" \t\r", i);
    if (i == std::string_view::npos) break;
    const std::size_t end = std::min(line.find_first_of(" \t\r", i), line.size());
    tokens.push_back(line.substr(i, end - i));
    i = end;
  }
  return tokens;
}

// Reads the header up to and including the end_header line; `in` is left at the first data byte.
Header read_header(detail::TextScanner& in) {
  const std::string& source = in.source();
  const auto fail_at = [&](std::uint32_t line, const std::string& message) {
    throw InputError(located_message(source, line, message));
  };
  if (in.read_line() != "ply") fail_at(1, "not a PLY file: the first line must be 'ply'");
  Header header;
  bool have_format = false;
  bool have_vertex = false;
  bool have_face = false;
  while (true) {
    if (in.rest().empty()) fail_at(in.line(), "the header has no end_header line");
    const std::uint32_t line = in.line();
    const std::vector<std::string_view> tokens = split(in.read_line());
    if (tokens.empty() || tokens[0] == "comment" || tokens[0] == "obj_info") continue;
    const std::string_view keyword = tokens[0];
    if (keyword == "end_header") {
      if (tokens.size() != 1) fail_at(line, "unexpected text after end_header");
      break;
    }
    if (keyword == "format") {
      if (tokens.size() != 3) fail_at(line, "expected 'format <ascii|binary_little_endian|binary_big_endian> 1.0'");
      if (tokens[1] == "ascii") {
        header.layout = Layout::Ascii;
      } else if (tokens[1] == "binary_little_endian") {
        header.layout = Layout::BinaryLittleEndian;
      } else if (tokens[1] == "binary_big_endian") {
        header.layout = Layout::BinaryBigEndian;
      } else {
        fail_at(line, "unknown PLY format '" + in.clip(tokens[1]) + "'");
      }
      have_format = true;
    } else if (keyword == "element") {
      if (tokens.size() != 3) fail_at(line, "expected 'element <name> <count>'");
      Element element;
      element.name = tokens[1];
      const auto [ptr, ec] = std::from_chars(tokens[2].data(), tokens[2].data() + tokens[2].size(), element.count);
      if (ec != std::errc() || ptr != tokens[2].data() + tokens[2].size())
        fail_at(line, "expected an element count, found '" + in.clip(tokens[2]) + "'");
      if (element.name == "vertex" || element.name == "face") {
        bool& seen = element.name == "vertex" ? have_vertex : have_face;
        if (seen) fail_at(line, "a second '" + element.name + "' element");
        seen = true;
        if (element.count > detail::kMaxCount)
          fail_at(line, element.name + " count " + std::to_string(element.count) + " does not fit 32-bit indices");
        if (element.name == "vertex") header.vertex_count = element.count;
      }
      header.elements.push_back(std::move(element));
    } else if (keyword == "property") {
      if (header.elements.empty()) fail_at(line, "a property before any element");
      Element& element = header.elements.back();
      Property property;
      std::string_view name;
      if (tokens.size() == 5 && tokens[1] == "list") {
        const auto count_type = scalar_from_name(tokens[2]);
        const auto item_type = scalar_from_name(tokens[3]);
        if (!count_type || detail::is_float(*count_type))
          fail_at(line, "list count type must be an integer type, found '" + in.clip(tokens[2]) + "'");
        if (!item_type) fail_at(line, "unknown property type '" + in.clip(tokens[3]) + "'");
        property.is_list = true;
        property.count_type = *count_type;
        property.type = *item_type;
        name = tokens[4];
      } else if (tokens.size() == 3) {
        const auto type = scalar_from_name(tokens[1]);
        if (!type) fail_at(line, "unknown property type '" + in.clip(tokens[1]) + "'");
        property.type = *type;
        name = tokens[2];
      } else {
        fail_at(line, "expected 'property <type> <name>' or 'property list <count type> <item type> <name>'");
      }
      if (element.name == "vertex" && !property.is_list) {
        if (name == "x") property.role = Role::X;
        if (name == "y") property.role = Role::Y;
        if (name == "z") property.role = Role::Z;
      }
      if (element.name == "face" && property.is_list && (name == "vertex_indices" || name == "vertex_index")) {
        if (detail::is_float(property.type)) fail_at(line, "face vertex indices must have an integer type");
        property.role = Role::FaceIndices;
      }
      if (property.role != Role::Skip)
        for (const Property& other : element.properties)
          if (other.role == property.role) fail_at(line, "property '" + in.clip(name) + "' declared twice");
      element.properties.push_back(property);
    } else {
      fail_at(line, "unknown header line '" + in.clip(keyword) + "'");
    }
  }
  const auto fail = [&](const std::string& message) { throw InputError(located_message(source, 0, message)); };
  if (!have_format) fail("the header has no format line");
  if (!have_vertex) fail("the header declares no vertex element");
  for (const Element& element : header.elements) {
    const auto has = [&](Role role) {
      for (const Property& p : element.properties)
        if (p.role == role) return true;
      return false;
    };
    if (element.name == "vertex" && !(has(Role::X) && has(Role::Y) && has(Role::Z)))
      fail("the vertex element lacks one of the properties x, y, z");
    if (element.name == "face" && !has(Role::FaceIndices))
      fail("the face element has no 'vertex_indices' list property");
  }
  if (header.vertex_count == 0) fail("the header announces no vertices");
  return header;
}

// Binary values: every read is bounds-checked by ByteReader.
class BinarySource {
 public:
  BinarySource(std::string_view data, const std::string& source, bool big_endian)
      : reader_(data, source, big_endian), source_(source) {}

  std::uint32_t begin_instance() { return 0; }  // binary data has no lines
  std::uint64_t remaining() const { return reader_.remaining(); }
  // Binary instances are never shorter than their fixed-size parts.
  static std::uint64_t min_instance_size(const Element& element) {
    std::uint64_t size = 0;
    for (const Property& p : element.properties) size += scalar_size(p.is_list ? p.count_type : p.type);
    return size;
  }
  double real(Scalar type) {
    switch (type) {
      case Scalar::Float32:
        return reader_.read<float>("a vertex coordinate");
      case Scalar::Float64:
        return reader_.read<double>("a vertex coordinate");
      default:
        return static_cast<double>(integer(type));
    }
  }
  std::int64_t integer(Scalar type) {
    switch (type) {
      case Scalar::Int8:
        return reader_.read<std::int8_t>("a value");
      case Scalar::UInt8:
        return reader_.read<std::uint8_t>("a value");
      case Scalar::Int16:
        return reader_.read<std::int16_t>("a value");
      case Scalar::UInt16:
        return reader_.read<std::uint16_t>("a value");
      case Scalar::Int32:
        return reader_.read<std::int32_t>("a value");
      case Scalar::UInt32:
        return reader_.read<std::uint32_t>("a value");
      case Scalar::Int64:  // no PLY type name maps to these (scalar_from_name)
      case Scalar::UInt64:
      case Scalar::Float32:
      case Scalar::Float64:
        break;
    }
    fail("a count or index has a floating-point type");
  }
  void skip(Scalar type, std::uint64_t count) { reader_.skip(count * scalar_size(type), "a property value"); }
  /// Bounds-checks a whole list before its items are read one by one.
  void require_list(Scalar type, std::uint64_t count) { reader_.require(count * scalar_size(type), "a list"); }
  void finish() {
    if (!detail::is_blank(reader_.rest()))
      fail(std::to_string(reader_.remaining()) + " bytes of unexpected data after the last element");
  }
  [[noreturn]] void fail(const std::string& message) const { throw InputError(located_message(source_, 0, message)); }

 private:
  detail::ByteReader reader_;
  const std::string& source_;
};

// ASCII values: whitespace-separated tokens (the PLY specification does not tie
// instances to lines, though writers put one per line; its first line is recorded).
class AsciiSource {
 public:
  explicit AsciiSource(detail::TextScanner& in) : in_(in) {}

  std::uint32_t begin_instance() {
    in_.skip_space();
    return in_.line();
  }
  std::uint64_t remaining() const { return in_.rest().size(); }
  // Every value takes at least one character and one separator (the last one may end the file).
  static std::uint64_t min_instance_size(const Element& element) { return 2 * element.properties.size(); }
  double real(Scalar) { return in_.real("vertex coordinate"); }
  std::int64_t integer(Scalar) { return in_.integer("integer"); }
  void skip(Scalar, std::uint64_t count) {
    for (std::uint64_t i = 0; i < count; ++i)
      if (in_.token().empty()) in_.fail("unexpected end of file inside an element");
  }
  void require_list(Scalar, std::uint64_t) {}  // tokens are checked as they are read
  void finish() {
    if (!in_.at_end()) in_.fail("unexpected data after the last element");
  }
  [[noreturn]] void fail(const std::string& message) const { in_.fail(message); }

 private:
  detail::TextScanner& in_;
};

template <typename Source>
void read_body(const Header& header, Source& source, MeshBundle& mesh) {
  std::vector<Index> corners;
  for (const Element& element : header.elements) {
    const std::uint64_t min_size = Source::min_instance_size(element);
    if (min_size == 0) continue;  // no properties: its instances occupy no data
    // Checked before anything is reserved: a lying count must not allocate.
    if (element.count > (source.remaining() + 1) / min_size)
      source.fail("element '" + detail::TextScanner::clip(element.name) + "' announces " +
                  std::to_string(element.count) + " instances, more than the remaining " +
                  std::to_string(source.remaining()) + " bytes can hold");
    const bool is_vertex = element.name == "vertex";
    const bool is_face = element.name == "face";
    if (is_vertex) mesh.points.reserve(element.count);
    if (is_face) mesh.triangles.reserve(element.count);
    for (std::uint64_t i = 0; i < element.count; ++i) {
      const std::uint32_t line = source.begin_instance();
      Vec3 p = Vec3::Zero();
      for (const Property& property : element.properties) {
        if (property.role == Role::X || property.role == Role::Y || property.role == Role::Z) {
          const double value = source.real(property.type);
          if (!std::isfinite(value)) source.fail("vertex " + std::to_string(i) + " has a non-finite coordinate");
          p[static_cast<int>(property.role) - static_cast<int>(Role::X)] = value;
          continue;
        }
        if (!property.is_list) {
          source.skip(property.type, 1);
          continue;
        }
        const std::int64_t count = source.integer(property.count_type);
        if (count < 0) source.fail("negative list length " + std::to_string(count));
        const auto length = static_cast<std::uint64_t>(count);
        if (property.role != Role::FaceIndices) {
          source.skip(property.type, length);
          continue;
        }
        if (length < 3)
          source.fail("face " + std::to_string(i) + " has " + std::to_string(length) +
                      " vertices; at least 3 are needed");
        source.require_list(property.type, length);
        corners.clear();
        for (std::uint64_t j = 0; j < length; ++j) {
          const std::int64_t v = source.integer(property.type);
          if (v < 0 || static_cast<std::uint64_t>(v) >= header.vertex_count)
            source.fail("face " + std::to_string(i) + " refers to vertex " + std::to_string(v) +
                        ", but vertices are numbered 0 to " + std::to_string(header.vertex_count - 1));
          corners.push_back(static_cast<Index>(v));
        }
        detail::add_polygon(mesh, corners, line);
      }
      if (is_vertex) {
        mesh.points.push_back(p);
        if (line != 0) mesh.lines.point_lines.push_back(line);
      }
    }
  }
  source.finish();
  if (mesh.cell_count() > detail::kMaxCount) source.fail("too many faces for 32-bit indices");
}

}  // namespace

MeshBundle read_ply(std::string_view data, const std::string& source_name) {
  if (detail::is_blank(data)) throw InputError(located_message(source_name, 0, "empty file"));
  detail::TextScanner in(data, source_name);
  const Header header = read_header(in);
  MeshBundle mesh;
  mesh.source_name = source_name;
  if (header.layout == Layout::Ascii) {
    AsciiSource source(in);
    read_body(header, source, mesh);
  } else {
    BinarySource source(in.rest(), source_name, header.layout == Layout::BinaryBigEndian);
    read_body(header, source, mesh);
  }
  return mesh;
}

std::string write_ply(const MeshBundle& mesh, Encoding encoding) {
  detail::check_writable_surface(mesh, "PLY");
  const bool binary = encoding == Encoding::Binary;
  std::string out;
  out.reserve(mesh.points.size() * (binary ? 24 : 64) + mesh.triangles.size() * 24 + mesh.quads.size() * 32 + 256);
  out += binary ? "ply\nformat binary_little_endian 1.0\n" : "ply\nformat ascii 1.0\n";
  out += "comment written by structmesh\nelement vertex ";
  detail::append_integer(out, mesh.points.size());
  // Doubles, so that both encodings round-trip exactly.
  out += "\nproperty double x\nproperty double y\nproperty double z\nelement face ";
  detail::append_integer(out, mesh.triangles.size() + mesh.quads.size());
  // "int" is what most tools expect; "uint" only when the indices need it.
  out += mesh.points.size() <= 0x7fffffffu ? "\nproperty list uchar int vertex_indices\nend_header\n"
                                           : "\nproperty list uchar uint vertex_indices\nend_header\n";
  if (!binary) {
    detail::append_point_lines(out, mesh.points);
    detail::append_counted_face_lines(out, mesh);
    return out;
  }
  for (const Vec3& p : mesh.points)
    for (int k = 0; k < 3; ++k) detail::append_le<double>(out, p[k]);
  const auto write_faces = [&](const auto& elements) {
    for (const auto& element : elements) {
      detail::append_le<std::uint8_t>(out, static_cast<std::uint8_t>(element.size()));
      for (const Index v : element) detail::append_le<std::uint32_t>(out, v);
    }
  };
  write_faces(mesh.triangles);
  write_faces(mesh.quads);
  return out;
}

}  // namespace structmesh
