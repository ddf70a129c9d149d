// VTK XML unstructured grid (.vtu) reader and writer, and the .pvtu index writer.
//
// Written: one Piece, raw appended binary data (little endian, UInt64 block headers),
// Float64 points, Int64 connectivity and offsets, UInt8 cell types; cells in bundle
// order (triangles, quads, tets, hexes); the bundle's labels as an Int32 array "label".
// Read: what VTK's vtkXMLUnstructuredGridWriter produces, uncompressed or with its
// default vtkZLibDataCompressor: ascii, inline base64 ("binary") and appended raw or
// base64 data, UInt32 or UInt64 headers, either byte order, any numeric type, several
// pieces (concatenated). Cell types 5 (triangle), 9 (quad), 10 (tet), 12 (hex) and,
// reordered, 8 (pixel) and 11 (voxel).
// An Int cell-data array named "part" (or else "label") becomes the element labels.
// XML has no line structure worth recording per element, so mesh.lines stays empty.
//
// The XML is scanned by a small hand-written tag scanner: no XML library is among
// structmesh's dependencies, VTU needs only tags, attributes and the text between
// tags, and appended raw data is arbitrary bytes that a general XML parser rejects.
#include "mesh/binary_scalar.hpp"
#include "mesh/io_volume_common.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <utility>
#include <vector>

#include <zlib.h>

namespace structmesh {
namespace {

// ---------------------------------------------------------------------------
// Errors with a line number computed from a byte position (only when failing).

class Source {
 public:
  Source(std::string_view data, const std::string& name) : data_(data), name_(name) {}
  std::string_view data() const { return data_; }
  [[noreturn]] void fail(std::size_t pos, const std::string& message) const {
    pos = std::min(pos, data_.size());
    const auto line = 1 + std::count(data_.begin(), data_.begin() + static_cast<std::ptrdiff_t>(pos), '\n');
    throw InputError(located_message(name_, static_cast<std::uint64_t>(line), message));
  }

 private:
  std::string_view data_;
  const std::string& name_;
};

std::string clip(std::string_view s) { return s.size() <= 40 ? std::string(s) : std::string(s.substr(0, 40)) + "..."; }

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

// ---------------------------------------------------------------------------
// XML tag scanner.

struct XmlTag {
  enum class Kind { Open, Close, Empty };
  Kind kind = Kind::Open;
  std::string_view name;
  std::vector<std::pair<std::string_view, std::string_view>> attributes;
  std::size_t begin = 0;  // position of '<'
  std::size_t end = 0;    // position after '>'

  std::optional<std::string_view> attribute(std::string_view key) const {
    for (const auto& [k, v] : attributes)
      if (k == key) return v;
    return std::nullopt;
  }
};

class XmlScanner {
 public:
  explicit XmlScanner(const Source& source) : source_(source), data_(source.data()) {}

  /// Reads the next tag, skipping text, comments, <?...?> and <!...> declarations.
  /// Returns false at the end of the input.
  bool next(XmlTag& tag) {
    while (true) {
      const std::size_t lt = data_.find('<', pos_);
      if (lt == std::string_view::npos) {
        pos_ = data_.size();
        return false;
      }
      pos_ = lt;
      if (starts_with("<!--")) {
        skip_past("-->", "unterminated comment");
      } else if (starts_with("<?")) {
        skip_past("?>", "unterminated <? declaration");
      } else if (starts_with("<!")) {
        skip_past(">", "unterminated <! declaration");
      } else {
        read_tag(tag);
        return true;
      }
    }
  }
  std::size_t position() const { return pos_; }

 private:
  bool starts_with(std::string_view s) const { return data_.substr(pos_, s.size()) == s; }
  void skip_past(std::string_view terminator, const char* message) {
    const std::size_t end = data_.find(terminator, pos_);
    if (end == std::string_view::npos) source_.fail(pos_, message);
    pos_ = end + terminator.size();
  }
  void skip_spaces() {
    while (pos_ < data_.size() && is_space(data_[pos_])) ++pos_;
  }
  std::string_view read_name() {
    const std::size_t start = pos_;
    while (pos_ < data_.size() && !is_space(data_[pos_]) && data_[pos_] != '/' && data_[pos_] != '>' &&
           data_[pos_] != '=' && data_[pos_] != '<')
      ++pos_;
    return data_.substr(start, pos_ - start);
  }

  void read_tag(XmlTag& tag) {
    tag.begin = pos_;
    tag.attributes.clear();
    ++pos_;  // '<'
    tag.kind = XmlTag::Kind::Open;
    if (pos_ < data_.size() && data_[pos_] == '/') {
      tag.kind = XmlTag::Kind::Close;
      ++pos_;
    }
    tag.name = read_name();
    if (tag.name.empty()) source_.fail(tag.begin, "malformed XML tag");
    while (true) {
      skip_spaces();
      if (pos_ >= data_.size()) source_.fail(tag.begin, "unterminated XML tag <" + clip(tag.name));
      const char c = data_[pos_];
      if (c == '>') {
        ++pos_;
        break;
      }
      if (c == '/' && tag.kind == XmlTag::Kind::Open) {
        ++pos_;
        if (pos_ >= data_.size() || data_[pos_] != '>') source_.fail(tag.begin, "malformed XML tag <" + clip(tag.name));
        ++pos_;
        tag.kind = XmlTag::Kind::Empty;
        break;
      }
      if (tag.kind == XmlTag::Kind::Close) source_.fail(tag.begin, "malformed closing tag </" + clip(tag.name));
      const std::string_view key = read_name();
      skip_spaces();
      if (key.empty() || pos_ >= data_.size() || data_[pos_] != '=')
        source_.fail(tag.begin, "malformed attribute in XML tag <" + clip(tag.name));
      ++pos_;
      skip_spaces();
      if (pos_ >= data_.size() || (data_[pos_] != '"' && data_[pos_] != '\''))
        source_.fail(tag.begin, "attribute value without quotes in XML tag <" + clip(tag.name));
      const char quote = data_[pos_++];
      const std::size_t close = data_.find(quote, pos_);
      if (close == std::string_view::npos) source_.fail(tag.begin, "unterminated attribute value");
      tag.attributes.emplace_back(key, data_.substr(pos_, close - pos_));
      pos_ = close + 1;
    }
    tag.end = pos_;
  }

  const Source& source_;
  std::string_view data_;
  std::size_t pos_ = 0;
};

// ---------------------------------------------------------------------------
// Data arrays.

using detail::append_le;
using detail::is_float;
using detail::Scalar;
using detail::scalar_size;

std::optional<Scalar> parse_scalar(std::string_view name) {
  static constexpr std::pair<std::string_view, Scalar> kTypes[] = {
      {"Int8", Scalar::Int8},       {"UInt8", Scalar::UInt8},    {"Int16", Scalar::Int16}, {"UInt16", Scalar::UInt16},
      {"Int32", Scalar::Int32},     {"UInt32", Scalar::UInt32},  {"Int64", Scalar::Int64}, {"UInt64", Scalar::UInt64},
      {"Float32", Scalar::Float32}, {"Float64", Scalar::Float64}};
  for (const auto& [n, s] : kTypes)
    if (n == name) return s;
  return std::nullopt;
}

struct ArrayInfo {
  std::size_t tag_pos = 0;  // for error messages
  Scalar type = Scalar::Float64;
  std::string_view format;  // ascii | binary | appended
  std::uint64_t components = 1;
  std::uint64_t offset = 0;                        // appended
  std::size_t content_begin = 0, content_end = 0;  // inline data
};

struct PieceInfo {
  std::size_t tag_pos = 0;
  std::uint64_t point_count = 0, cell_count = 0;
  std::optional<ArrayInfo> points, connectivity, offsets, types, part, label;
};

struct FileInfo {
  bool big_endian = false;
  bool zlib = false;            // compressor="vtkZLibDataCompressor"
  std::size_t header_size = 4;  // UInt32 unless header_type says UInt64
  bool appended_base64 = false;
  std::optional<std::size_t> appended_begin;  // position after the '_'
  std::vector<PieceInfo> pieces;
};

int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

/// Decodes base64 group by group. '=' padding may end any 4-character group because VTK
/// writers differ: VTK 9 encodes a block's header and data as one stream, older VTK and
/// other tools as two separately padded streams; group-wise decoding reads both.
class Base64Reader {
 public:
  Base64Reader(std::string_view text, std::size_t pos) : text_(text), pos_(pos) {}

  /// Appends decoded bytes until `out` holds at least `target` bytes; false when the
  /// text ends or stops being base64 first.
  bool read_until(std::vector<unsigned char>& out, std::size_t target) {
    while (out.size() < target) {
      int values[4];
      int count = 0;
      int padding = 0;
      while (count < 4) {
        while (pos_ < text_.size() && is_space(text_[pos_])) ++pos_;
        if (pos_ >= text_.size()) return false;
        const char c = text_[pos_];
        if (c == '=') {
          if (count < 2) return false;
          ++padding;
          values[count++] = 0;
        } else {
          const int v = base64_value(c);
          if (v < 0 || padding > 0) return false;
          values[count++] = v;
        }
        ++pos_;
      }
      const std::uint32_t bits = (static_cast<std::uint32_t>(values[0]) << 18) |
                                 (static_cast<std::uint32_t>(values[1]) << 12) |
                                 (static_cast<std::uint32_t>(values[2]) << 6) | static_cast<std::uint32_t>(values[3]);
      out.push_back(static_cast<unsigned char>(bits >> 16));
      if (padding < 2) out.push_back(static_cast<unsigned char>((bits >> 8) & 0xFF));
      if (padding < 1) out.push_back(static_cast<unsigned char>(bits & 0xFF));
    }
    return true;
  }
  std::size_t remaining() const { return text_.size() - std::min(pos_, text_.size()); }

 private:
  std::string_view text_;
  std::size_t pos_;
};

/// Bytes the arrays of one file may still take, so that a small hostile file cannot
/// demand gigabytes.
struct Budget {
  std::uint64_t stored = 0;    // binary bytes read from the file (at most its size)
  std::uint64_t inflated = 0;  // bytes produced by decompression
};

/// VTK's compressed data (vtkXMLWriter, read back by vtkXMLDataParser): a header of
/// header_type integers [blocks, block size, size of a partial last block (0: full),
/// compressed size of each block], then the blocks' zlib streams back to back.
struct CompressedBlocks {
  std::uint64_t count = 0, size = 0, last_size = 0;
  std::vector<std::uint64_t> compressed;
  std::uint64_t compressed_total = 0, inflated_total = 0;

  std::uint64_t inflated_size(std::uint64_t block) const {
    return block + 1 == count && last_size != 0 ? last_size : size;
  }
};

/// Values of one array, widened to double (points) or int64 (everything else).
template <typename Out>
class ArrayDecoder {
 public:
  /// `budget` is shared by all arrays of the file.
  ArrayDecoder(const Source& source, const FileInfo& file, Budget& budget)
      : source_(source), file_(file), budget_(budget) {}

  std::vector<Out> decode(const ArrayInfo& array, const char* what) {
    what_ = what;
    array_ = &array;
    if constexpr (std::is_integral_v<Out>) {
      if (is_float(array.type)) fail(std::string(what) + " must be an integer array, not floating point");
    }
    if (array.format == "ascii") return decode_ascii();
    if (array.format == "binary")
      return file_.zlib ? decode_base64_compressed(array.content_begin, array.content_end)
                        : decode_base64(array.content_begin, array.content_end);
    if (array.format == "appended") {
      if (!file_.appended_begin) fail(std::string(what) + " is appended but the file has no <AppendedData>");
      const std::size_t begin = *file_.appended_begin;
      const std::size_t size = source_.data().size();
      if (array.offset > size - begin) fail(std::string(what) + ": appended offset beyond the end of the file");
      const std::size_t start = begin + static_cast<std::size_t>(array.offset);
      if (file_.appended_base64) return file_.zlib ? decode_base64_compressed(start, size) : decode_base64(start, size);
      return file_.zlib ? decode_raw_compressed(source_.data().substr(start))
                        : decode_raw_block(source_.data().substr(start));
    }
    fail(std::string(what) + ": unknown DataArray format '" + clip(array.format) + "'");
  }

 private:
  [[noreturn]] void fail(const std::string& message) const { source_.fail(array_->tag_pos, message); }

  std::uint64_t header_value(const unsigned char* bytes) const {
    if (file_.header_size == 4) return detail::load_scalar<std::uint32_t>(bytes, file_.big_endian);
    return detail::load_scalar<std::uint64_t>(bytes, file_.big_endian);
  }

  template <typename T>
  T load(const unsigned char* p) const {
    // Files are little endian unless byte_order says otherwise; swap when the host differs.
    return detail::load_scalar<T>(p, file_.big_endian != (std::endian::native == std::endian::big));
  }

  /// `bytes` holds whole values of the array's type (checked by the callers).
  std::vector<Out> from_bytes(const unsigned char* bytes, std::size_t size) const {
    const std::size_t width = scalar_size(array_->type);
    const std::size_t n = size / width;
    std::vector<Out> values(n);
    for (std::size_t i = 0; i < n; ++i) {
      const unsigned char* p = bytes + i * width;
      switch (array_->type) {
        case Scalar::Int8:
          values[i] = static_cast<Out>(static_cast<std::int8_t>(p[0]));
          break;
        case Scalar::UInt8:
          values[i] = static_cast<Out>(p[0]);
          break;
        case Scalar::Int16:
          values[i] = static_cast<Out>(load<std::int16_t>(p));
          break;
        case Scalar::UInt16:
          values[i] = static_cast<Out>(load<std::uint16_t>(p));
          break;
        case Scalar::Int32:
          values[i] = static_cast<Out>(load<std::int32_t>(p));
          break;
        case Scalar::UInt32:
          values[i] = static_cast<Out>(load<std::uint32_t>(p));
          break;
        case Scalar::Int64:
          values[i] = static_cast<Out>(load<std::int64_t>(p));
          break;
        case Scalar::UInt64: {
          const std::uint64_t v = load<std::uint64_t>(p);
          if constexpr (std::is_integral_v<Out>) {
            if (v > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
              fail(std::string(what_) + " holds a value too large for 64-bit signed integers");
          }
          values[i] = static_cast<Out>(v);
          break;
        }
        case Scalar::Float32:
          values[i] = static_cast<Out>(load<float>(p));
          break;
        case Scalar::Float64:
          values[i] = static_cast<Out>(load<double>(p));
          break;
      }
    }
    return values;
  }

  void check_block(std::uint64_t byte_count, std::uint64_t available) {
    if (byte_count > available)
      fail(std::string(what_) + ": data block of " + std::to_string(byte_count) +
           " bytes runs past the end (truncated?)");
    take_stored(byte_count);
    check_value_size(byte_count);
  }

  // Arrays (of several pieces) could all point at one large appended block; without
  // this cap a small file could demand gigabytes. Valid files never share blocks.
  void take_stored(std::uint64_t byte_count) {
    if (byte_count > budget_.stored)
      fail(std::string(what_) + ": data blocks add up to more than the file holds (do appended offsets overlap?)");
    budget_.stored -= byte_count;
  }

  void check_value_size(std::uint64_t byte_count) const {
    if (byte_count % scalar_size(array_->type) != 0)
      fail(std::string(what_) + ": data block size " + std::to_string(byte_count) +
           " is not a multiple of the value size");
  }

  /// Length of a compression header whose first three integers are at `prefix`, with
  /// `available` bytes after those three.
  std::uint64_t compression_header_length(const unsigned char* prefix, std::uint64_t available) const {
    const std::uint64_t count = header_value(prefix);
    if (count > available / file_.header_size)
      fail(std::string(what_) + ": compression header for " + std::to_string(count) +
           " blocks runs past the end (truncated?)");
    return (3 + count) * file_.header_size;
  }

  /// Reads a whole compression header and checks its sizes against the `available`
  /// bytes after it and against the budget.
  CompressedBlocks read_compression_header(const unsigned char* header, std::uint64_t available) {
    const std::size_t h = file_.header_size;
    CompressedBlocks blocks;
    blocks.count = header_value(header);
    blocks.size = header_value(header + h);
    blocks.last_size = header_value(header + 2 * h);
    blocks.compressed.resize(static_cast<std::size_t>(blocks.count));
    for (std::size_t b = 0; b < blocks.compressed.size(); ++b) {
      blocks.compressed[b] = header_value(header + (3 + b) * h);
      if (blocks.compressed[b] > available - blocks.compressed_total)
        fail(std::string(what_) + ": compressed block " + std::to_string(b) + " of " + std::to_string(blocks.count) +
             " runs past the end (truncated?)");
      blocks.compressed_total += blocks.compressed[b];
    }
    take_stored(blocks.compressed_total);
    if (blocks.count == 0) return blocks;
    if (blocks.last_size > blocks.size)
      fail(std::string(what_) + ": compression header gives a last block of " + std::to_string(blocks.last_size) +
           " bytes, larger than the block size " + std::to_string(blocks.size));
    // Every block but the last inflates to the block size; checked before anything is allocated.
    const std::uint64_t last = blocks.inflated_size(blocks.count - 1);
    const bool plausible = last <= budget_.inflated &&
                           (blocks.count == 1 || (budget_.inflated - last) / (blocks.count - 1) >= blocks.size);
    if (!plausible)
      fail(std::string(what_) + ": decompressed size implausible (" + std::to_string(blocks.count) + " blocks of " +
           std::to_string(blocks.size) + " bytes for a file of " + std::to_string(source_.data().size()) + " bytes)");
    blocks.inflated_total = (blocks.count - 1) * blocks.size + last;
    budget_.inflated -= blocks.inflated_total;
    check_value_size(blocks.inflated_total);
    return blocks;
  }

  /// Inflates the blocks whose zlib streams start at `data` into the array's values.
  std::vector<Out> inflate(const CompressedBlocks& blocks, const unsigned char* data) const {
    std::vector<unsigned char> bytes(static_cast<std::size_t>(blocks.inflated_total));
    std::size_t in = 0, out = 0;
    for (std::uint64_t b = 0; b < blocks.count; ++b) {
      const std::uint64_t compressed = blocks.compressed[static_cast<std::size_t>(b)];
      const std::uint64_t expected = blocks.inflated_size(b);
      if constexpr (sizeof(uLong) < sizeof(std::uint64_t)) {
        if (compressed > std::numeric_limits<uLong>::max() || expected > std::numeric_limits<uLong>::max())
          fail(std::string(what_) + ": compressed block " + std::to_string(b) + " is too large for zlib here");
      }
      uLongf length = static_cast<uLongf>(expected);
      const int status = uncompress(bytes.data() + out, &length, data + in, static_cast<uLong>(compressed));
      if (status != Z_OK || length != expected)
        fail(std::string(what_) + ": compressed block " + std::to_string(b) + " of " + std::to_string(blocks.count) +
             " is corrupt (zlib: " + (status == Z_OK ? "wrong size" : zError(status)) + ")");
      in += static_cast<std::size_t>(compressed);
      out += static_cast<std::size_t>(expected);
    }
    return from_bytes(bytes.data(), bytes.size());
  }

  std::vector<Out> decode_raw_compressed(std::string_view block) {
    const std::size_t h = file_.header_size;
    if (block.size() < 3 * h) fail(std::string(what_) + ": compression header runs past the end (truncated?)");
    const auto* bytes = reinterpret_cast<const unsigned char*>(block.data());
    const std::uint64_t length = compression_header_length(bytes, block.size() - 3 * h);
    const CompressedBlocks blocks = read_compression_header(bytes, block.size() - length);
    return inflate(blocks, bytes + length);
  }

  // VTK encodes the header and the blocks as two base64 streams, each padded on its own;
  // the group-wise reader takes that and a single stream alike.
  std::vector<Out> decode_base64_compressed(std::size_t begin, std::size_t end) {
    Base64Reader reader(source_.data().substr(begin, end - begin), 0);
    std::vector<unsigned char> bytes;
    const std::size_t h = file_.header_size;
    // Bytes decoded beyond `used` plus what the remaining text can still hold.
    const auto available = [&](std::uint64_t used) { return (reader.remaining() / 4) * 3 + (bytes.size() - used); };
    if (!reader.read_until(bytes, 3 * h)) fail(std::string(what_) + ": bad or truncated base64 compression header");
    const std::uint64_t length = compression_header_length(bytes.data(), available(3 * h));
    if (!reader.read_until(bytes, static_cast<std::size_t>(length)))
      fail(std::string(what_) + ": bad or truncated base64 compression header");
    const CompressedBlocks blocks = read_compression_header(bytes.data(), available(length));
    const std::size_t total = static_cast<std::size_t>(length + blocks.compressed_total);
    bytes.reserve(total + 2);
    if (!reader.read_until(bytes, total)) fail(std::string(what_) + ": bad or truncated base64 data");
    return inflate(blocks, bytes.data() + length);
  }

  std::vector<Out> decode_raw_block(std::string_view block) {
    const std::size_t h = file_.header_size;
    if (block.size() < h) fail(std::string(what_) + ": appended data block header runs past the end (truncated?)");
    const auto* bytes = reinterpret_cast<const unsigned char*>(block.data());
    const std::uint64_t byte_count = header_value(bytes);
    check_block(byte_count, block.size() - h);
    return from_bytes(bytes + h, static_cast<std::size_t>(byte_count));
  }

  std::vector<Out> decode_base64(std::size_t begin, std::size_t end) {
    Base64Reader reader(source_.data().substr(begin, end - begin), 0);
    std::vector<unsigned char> bytes;
    const std::size_t h = file_.header_size;
    if (!reader.read_until(bytes, h)) fail(std::string(what_) + ": bad or truncated base64 data block header");
    const std::uint64_t byte_count = header_value(bytes.data());
    // Four base64 characters carry three bytes: check before decoding the block.
    check_block(byte_count, (reader.remaining() / 4) * 3 + (bytes.size() - h));
    const std::size_t total = h + static_cast<std::size_t>(byte_count);
    bytes.reserve(total + 2);
    if (!reader.read_until(bytes, total)) fail(std::string(what_) + ": bad or truncated base64 data");
    return from_bytes(bytes.data() + h, static_cast<std::size_t>(byte_count));
  }

  std::vector<Out> decode_ascii() const {
    std::vector<Out> values;
    const std::string_view text =
        source_.data().substr(array_->content_begin, array_->content_end - array_->content_begin);
    std::size_t pos = 0;
    while (true) {
      while (pos < text.size() && is_space(text[pos])) ++pos;
      if (pos >= text.size()) break;
      const std::size_t start = pos;
      while (pos < text.size() && !is_space(text[pos])) ++pos;
      const std::string_view token = text.substr(start, pos - start);
      const char* first = token.data();
      const char* last = token.data() + token.size();
      if (*first == '+') ++first;
      Out value{};
      const std::from_chars_result result = std::from_chars(first, last, value);
      if (result.ec != std::errc() || result.ptr != last)
        fail(std::string(what_) + ": expected a number, found '" + clip(token) + "'");
      values.push_back(value);
    }
    return values;
  }

  const Source& source_;
  const FileInfo& file_;
  Budget& budget_;
  const ArrayInfo* array_ = nullptr;
  const char* what_ = "";
};

// ---------------------------------------------------------------------------
// Structure scan.

std::uint64_t parse_count(const Source& source, const XmlTag& tag, std::string_view key) {
  const auto value = tag.attribute(key);
  if (!value) source.fail(tag.begin, "<" + std::string(tag.name) + "> has no " + std::string(key));
  std::uint64_t n = 0;
  const auto [ptr, ec] = std::from_chars(value->data(), value->data() + value->size(), n);
  if (ec != std::errc() || ptr != value->data() + value->size())
    source.fail(tag.begin, std::string(key) + " must be a non-negative integer, found '" + clip(*value) + "'");
  return n;
}

ArrayInfo read_array_info(const Source& source, const XmlTag& tag) {
  ArrayInfo info;
  info.tag_pos = tag.begin;
  const auto type = tag.attribute("type");
  if (!type) source.fail(tag.begin, "<DataArray> has no type");
  const auto scalar = parse_scalar(*type);
  if (!scalar) source.fail(tag.begin, "unsupported DataArray type '" + clip(*type) + "'");
  info.type = *scalar;
  info.format = tag.attribute("format").value_or("ascii");
  if (tag.attribute("NumberOfComponents")) info.components = parse_count(source, tag, "NumberOfComponents");
  if (info.format == "appended") {
    info.offset = parse_count(source, tag, "offset");
  } else if (tag.kind == XmlTag::Kind::Open) {
    // Inline data is the text up to the next tag (VTK may add <InformationKey> children after it).
    info.content_begin = tag.end;
    const std::size_t lt = source.data().find('<', tag.end);
    if (lt == std::string_view::npos) source.fail(tag.begin, "unterminated <DataArray>");
    info.content_end = lt;
  }
  return info;
}

FileInfo scan_structure(const Source& source) {
  XmlScanner xml(source);
  XmlTag tag;
  FileInfo file;
  if (!xml.next(tag)) source.fail(0, source.data().empty() ? "empty file" : "no XML tags: not a VTK XML file");
  if (tag.name != "VTKFile" || tag.kind != XmlTag::Kind::Open)
    source.fail(tag.begin, "not a VTK XML file: expected <VTKFile>");
  const std::string_view type = tag.attribute("type").value_or("");
  if (type == "PUnstructuredGrid")
    source.fail(tag.begin, "this is a parallel .pvtu index; read its .vtu pieces instead");
  if (type != "UnstructuredGrid")
    source.fail(tag.begin, "VTK file type '" + clip(type) + "' is not an unstructured grid");
  const std::string_view order = tag.attribute("byte_order").value_or("LittleEndian");
  if (order == "BigEndian")
    file.big_endian = true;
  else if (order != "LittleEndian")
    source.fail(tag.begin, "unknown byte_order '" + clip(order) + "'");
  const std::string_view header = tag.attribute("header_type").value_or("UInt32");
  if (header == "UInt64")
    file.header_size = 8;
  else if (header != "UInt32")
    source.fail(tag.begin, "unsupported header_type '" + clip(header) + "'");
  if (const auto compressor = tag.attribute("compressor"); compressor && !compressor->empty()) {
    if (*compressor != "vtkZLibDataCompressor")
      source.fail(tag.begin, "VTU compressor '" + clip(*compressor) +
                                 "' is not supported; structmesh reads zlib-compressed or uncompressed files "
                                 "(ParaView: Compressor Type ZLib or None; Python: writer.SetCompressorTypeToZLib())");
    file.zlib = true;
  }

  // Open elements below <VTKFile>; depth is bounded so hostile nesting costs nothing.
  std::vector<std::string_view> stack{"VTKFile"};
  while (xml.next(tag)) {
    if (tag.kind == XmlTag::Kind::Close) {
      if (stack.empty() || stack.back() != tag.name)
        source.fail(tag.begin, "mismatched closing tag </" + clip(tag.name) + ">");
      stack.pop_back();
      if (stack.empty()) break;  // </VTKFile>
      continue;
    }
    if (stack.empty()) break;
    const std::string_view parent = stack.back();
    if (tag.name == "AppendedData") {
      if (parent != "VTKFile") source.fail(tag.begin, "<AppendedData> outside <VTKFile>");
      const std::string_view encoding = tag.attribute("encoding").value_or("raw");
      if (encoding == "base64")
        file.appended_base64 = true;
      else if (encoding != "raw")
        source.fail(tag.begin, "unknown AppendedData encoding '" + clip(encoding) + "'");
      // The data starts after an underscore; stop scanning there because raw data is arbitrary bytes.
      std::size_t p = tag.end;
      while (p < source.data().size() && is_space(source.data()[p])) ++p;
      if (p >= source.data().size() || source.data()[p] != '_')
        source.fail(tag.begin, "<AppendedData> must start with '_'");
      file.appended_begin = p + 1;
      break;
    }
    if (tag.name == "Piece" && parent == "UnstructuredGrid") {
      PieceInfo piece;
      piece.tag_pos = tag.begin;
      piece.point_count = parse_count(source, tag, "NumberOfPoints");
      piece.cell_count = parse_count(source, tag, "NumberOfCells");
      file.pieces.push_back(piece);
    } else if (tag.name == "DataArray" && stack.size() >= 3 && stack[stack.size() - 2] == "Piece" &&
               stack[stack.size() - 3] == "UnstructuredGrid" && !file.pieces.empty()) {
      PieceInfo& piece = file.pieces.back();
      const std::string_view name = tag.attribute("Name").value_or("");
      std::optional<ArrayInfo>* slot = nullptr;
      if (parent == "Points") {
        slot = &piece.points;
      } else if (parent == "Cells") {
        if (name == "connectivity") slot = &piece.connectivity;
        if (name == "offsets") slot = &piece.offsets;
        if (name == "types") slot = &piece.types;
        if (name == "faces" || name == "faceoffsets")
          source.fail(tag.begin, "polyhedron cells (faces/faceoffsets) are not supported");
      } else if (parent == "CellData") {
        if (name == "part") slot = &piece.part;
        if (name == "label") slot = &piece.label;
      }
      if (slot != nullptr) {
        if (slot->has_value())
          source.fail(tag.begin, "repeated DataArray '" + clip(name) + "' in <" + std::string(parent) + ">");
        *slot = read_array_info(source, tag);
      }
    }
    if (tag.kind == XmlTag::Kind::Open) {
      if (stack.size() >= 64) source.fail(tag.begin, "XML nested too deeply");
      stack.push_back(tag.name);
    }
  }
  if (file.pieces.empty()) source.fail(source.data().size(), "no <Piece> in <UnstructuredGrid>");
  return file;
}

// ---------------------------------------------------------------------------
// Cells.

enum class Target { Triangle, Quad, Tet, Hex };

struct CellKind {
  int nodes = 0;
  Target target = Target::Triangle;
  const char* name = "";
  std::array<int, 8> order{};  // file node k goes to element slot order[k]
};

std::optional<CellKind> cell_kind(std::int64_t type) {
  // Pixels and voxels list their nodes in x-then-y(-then-z) order, not as rings.
  static constexpr std::pair<int, CellKind> kKinds[] = {{5, {3, Target::Triangle, "triangle", {0, 1, 2}}},
                                                        {9, {4, Target::Quad, "quad", {0, 1, 2, 3}}},
                                                        {8, {4, Target::Quad, "pixel", {0, 1, 3, 2}}},
                                                        {10, {4, Target::Tet, "tetrahedron", {0, 1, 2, 3}}},
                                                        {12, {8, Target::Hex, "hexahedron", {0, 1, 2, 3, 4, 5, 6, 7}}},
                                                        {11, {8, Target::Hex, "voxel", {0, 1, 3, 2, 4, 5, 7, 6}}}};
  for (const auto& [id, kind] : kKinds)
    if (id == type) return kind;
  return std::nullopt;
}

std::string unsupported_cell_message(std::int64_t type) {
  static constexpr std::pair<int, const char*> kNames[] = {{1, "vertex"},
                                                           {2, "poly-vertex"},
                                                           {3, "line"},
                                                           {4, "poly-line"},
                                                           {6, "triangle strip"},
                                                           {7, "polygon"},
                                                           {13, "wedge"},
                                                           {14, "pyramid"},
                                                           {21, "quadratic edge"},
                                                           {22, "quadratic triangle"},
                                                           {23, "quadratic quad"},
                                                           {24, "quadratic tetrahedron"},
                                                           {25, "quadratic hexahedron"},
                                                           {42, "polyhedron"}};
  std::string message = "VTK cell type " + std::to_string(type);
  for (const auto& [id, name] : kNames)
    if (id == type) message += std::string(" (") + name + ")";
  return message + " is not supported; structmesh reads triangles (5), quads (9), tetrahedra (10), hexahedra (12)";
}

void read_piece(const Source& source, const FileInfo& file, const PieceInfo& piece, Budget& budget, MeshBundle& mesh,
                bool& any_labels) {
  const auto fail = [&](const std::string& message) { source.fail(piece.tag_pos, message); };
  if (!piece.points && piece.point_count > 0) fail("<Piece> has no <Points> array");
  if (piece.cell_count > 0 && (!piece.connectivity || !piece.offsets || !piece.types))
    fail("<Cells> needs connectivity, offsets and types arrays");
  if (piece.point_count >= kInvalidIndex - mesh.points.size()) fail("too many points for 32-bit indices");
  const auto point_base = static_cast<Index>(mesh.points.size());

  if (piece.points) {
    if (piece.points->components != 3) source.fail(piece.points->tag_pos, "Points must have NumberOfComponents=\"3\"");
    const std::vector<double> xyz = ArrayDecoder<double>(source, file, budget).decode(*piece.points, "Points");
    if (xyz.size() != 3 * piece.point_count)
      source.fail(piece.points->tag_pos, "Points holds " + std::to_string(xyz.size()) + " values, expected 3 x " +
                                             std::to_string(piece.point_count));
    mesh.points.reserve(mesh.points.size() + piece.point_count);
    for (std::size_t i = 0; i < xyz.size(); i += 3) {
      if (!std::isfinite(xyz[i]) || !std::isfinite(xyz[i + 1]) || !std::isfinite(xyz[i + 2]))
        source.fail(piece.points->tag_pos, "point " + std::to_string(i / 3) + " has a coordinate that is not finite");
      mesh.points.emplace_back(xyz[i], xyz[i + 1], xyz[i + 2]);
    }
  }
  if (piece.cell_count == 0) return;

  ArrayDecoder<std::int64_t> ints(source, file, budget);
  const std::vector<std::int64_t> types = ints.decode(*piece.types, "types");
  if (types.size() != piece.cell_count)
    source.fail(piece.types->tag_pos, "types holds " + std::to_string(types.size()) + " values for " +
                                          std::to_string(piece.cell_count) + " cells");
  std::vector<std::int64_t> offsets = ints.decode(*piece.offsets, "offsets");
  // VTK's XML offsets are end offsets (n values); accept a leading 0 (n + 1 values) too.
  if (offsets.size() == piece.cell_count + 1 && offsets.front() == 0) offsets.erase(offsets.begin());
  if (offsets.size() != piece.cell_count)
    source.fail(piece.offsets->tag_pos, "offsets holds " + std::to_string(offsets.size()) + " values for " +
                                            std::to_string(piece.cell_count) + " cells");
  const std::vector<std::int64_t> connectivity = ints.decode(*piece.connectivity, "connectivity");

  // Labels come from an integer "part" array, else an integer "label" array; a
  // floating-point array of that name is ordinary cell data, not labels.
  const auto integer = [](const std::optional<ArrayInfo>& a) { return a && !is_float(a->type); };
  const std::optional<ArrayInfo>& label_info = integer(piece.part) ? piece.part : piece.label;
  std::vector<std::int64_t> labels;
  if (integer(label_info)) {
    const char* what = integer(piece.part) ? "cell data 'part'" : "cell data 'label'";
    if (label_info->components != 1) source.fail(label_info->tag_pos, std::string(what) + " must have one component");
    labels = ints.decode(*label_info, what);
    if (labels.size() != piece.cell_count)
      source.fail(label_info->tag_pos, std::string(what) + " holds " + std::to_string(labels.size()) + " values for " +
                                           std::to_string(piece.cell_count) + " cells");
    for (const std::int64_t v : labels)
      if (v < std::numeric_limits<std::int32_t>::min() || v > std::numeric_limits<std::int32_t>::max())
        source.fail(label_info->tag_pos,
                    std::string(what) + " value " + std::to_string(v) + " does not fit in 32 bits");
    any_labels = true;
  }

  std::int64_t start = 0;
  for (std::size_t c = 0; c < types.size(); ++c) {
    const std::optional<CellKind> kind = cell_kind(types[c]);
    if (!kind)
      source.fail(piece.types->tag_pos, "cell " + std::to_string(c) + ": " + unsupported_cell_message(types[c]));
    const std::int64_t end = offsets[c];
    if (end < start || end > static_cast<std::int64_t>(connectivity.size()) || end - start != kind->nodes)
      source.fail(piece.offsets->tag_pos, "cell " + std::to_string(c) + " (" + kind->name + "): offsets give " +
                                              std::to_string(end - start) + " nodes, expected " +
                                              std::to_string(kind->nodes) + " (or connectivity is too short)");
    std::array<Index, 8> nodes{};
    for (int k = 0; k < kind->nodes; ++k) {
      const std::int64_t v = connectivity[static_cast<std::size_t>(start + k)];
      if (v < 0 || static_cast<std::uint64_t>(v) >= piece.point_count)
        source.fail(piece.connectivity->tag_pos, "cell " + std::to_string(c) + " (" + kind->name +
                                                     ") refers to point " + std::to_string(v) + " of " +
                                                     std::to_string(piece.point_count));
      nodes[static_cast<std::size_t>(kind->order[static_cast<std::size_t>(k)])] = point_base + static_cast<Index>(v);
    }
    const std::int32_t label = labels.empty() ? 0 : static_cast<std::int32_t>(labels[c]);
    switch (kind->target) {
      case Target::Triangle:
        mesh.triangles.push_back({nodes[0], nodes[1], nodes[2]});
        mesh.triangle_labels.push_back(label);
        break;
      case Target::Quad:
        mesh.quads.push_back({nodes[0], nodes[1], nodes[2], nodes[3]});
        mesh.quad_labels.push_back(label);
        break;
      case Target::Tet:
        mesh.tets.push_back({nodes[0], nodes[1], nodes[2], nodes[3]});
        mesh.tet_labels.push_back(label);
        break;
      case Target::Hex:
        mesh.hexes.push_back(nodes);
        mesh.hex_labels.push_back(label);
        break;
    }
    start = end;
  }
  if (start != static_cast<std::int64_t>(connectivity.size()))
    source.fail(piece.connectivity->tag_pos, "connectivity holds " + std::to_string(connectivity.size()) +
                                                 " values but the cells use " + std::to_string(start));
}

// ---------------------------------------------------------------------------
// Writer helpers.

std::string xml_escape(std::string_view s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

void check_arrays(const std::vector<DataArray>& arrays, std::size_t expected, const char* where) {
  for (std::size_t i = 0; i < arrays.size(); ++i) {
    const DataArray& a = arrays[i];
    if (a.name.empty()) throw Error(std::string("VTU ") + where + " array " + std::to_string(i) + " has no name");
    if (!a.f64.empty() && !a.i32.empty())
      throw Error(std::string("VTU ") + where + " array '" + a.name + "' fills both f64 and i32");
    if (a.size() != expected)
      throw Error(std::string("VTU ") + where + " array '" + a.name + "' has " + std::to_string(a.size()) +
                  " values, expected " + std::to_string(expected));
    for (std::size_t j = 0; j < i; ++j)
      if (arrays[j].name == a.name)
        throw Error(std::string("VTU ") + where + " array name '" + a.name + "' is used twice");
  }
}

// An array holds doubles unless only its i32 values are filled.
bool is_int_array(const DataArray& a) { return a.f64.empty() && !a.i32.empty(); }

std::vector<const DataArray*> pointers(const std::vector<DataArray>& arrays) {
  std::vector<const DataArray*> result;
  for (const DataArray& a : arrays) result.push_back(&a);
  return result;
}

void declare_arrays(std::string& out, const std::vector<const DataArray*>& arrays, std::string_view indent,
                    const char* tag, const char* element, std::uint64_t* offset) {
  out += indent;
  out += "<";
  out += tag;
  out += ">\n";
  for (const DataArray* array : arrays) {
    const DataArray& a = *array;
    out += indent;
    out += "  <";
    out += element;
    out += is_int_array(a) ? " type=\"Int32\"" : " type=\"Float64\"";
    out += " Name=\"" + xml_escape(a.name) + "\"";
    if (offset != nullptr) {
      out += " format=\"appended\" offset=\"" + std::to_string(*offset) + "\"";
      *offset += 8 + a.size() * (is_int_array(a) ? 4 : 8);
    }
    out += "/>\n";
  }
  out += indent;
  out += "</";
  out += tag;
  out += ">\n";
}

void append_array_block(std::string& out, const DataArray& a) {
  const bool ints = is_int_array(a);
  append_le<std::uint64_t>(out, a.size() * (ints ? 4 : 8));
  if (ints)
    for (const std::int32_t v : a.i32) append_le(out, v);
  else
    for (const double v : a.f64) append_le(out, v);
}

/// The bundle's element labels in cell order (0 for kinds without labels), named "label"
/// so that read_vtu() restores them; nothing when the bundle has no labels or the caller
/// already supplies a "label" or "part" cell array.
std::optional<DataArray> label_array(const MeshBundle& mesh, const std::vector<DataArray>& cell_data) {
  if (mesh.triangle_labels.empty() && mesh.quad_labels.empty() && mesh.tet_labels.empty() && mesh.hex_labels.empty())
    return std::nullopt;
  for (const DataArray& a : cell_data)
    if (a.name == "label" || a.name == "part") return std::nullopt;
  DataArray labels{"label", {}, {}};
  labels.i32.reserve(mesh.cell_count());
  const auto append = [&labels](const std::vector<std::int32_t>& kind_labels, std::size_t count) {
    for (std::size_t i = 0; i < count; ++i) labels.i32.push_back(detail::volume_io::label_at(kind_labels, i));
  };
  append(mesh.triangle_labels, mesh.triangles.size());
  append(mesh.quad_labels, mesh.quads.size());
  append(mesh.tet_labels, mesh.tets.size());
  append(mesh.hex_labels, mesh.hexes.size());
  return labels;
}

}  // namespace

MeshBundle read_vtu(std::string_view data, const std::string& source_name) {
  const Source source(data, source_name);
  const FileInfo file = scan_structure(source);
  MeshBundle mesh;
  mesh.source_name = source_name;
  bool any_labels = false;
  // zlib inflates at most about 1000:1, but real meshes compress less than 10:1.
  Budget budget{data.size(), std::min<std::uint64_t>(64 * static_cast<std::uint64_t>(data.size()), 8ull << 30)};
  for (const PieceInfo& piece : file.pieces) read_piece(source, file, piece, budget, mesh, any_labels);
  if (!any_labels) {
    mesh.triangle_labels.clear();
    mesh.quad_labels.clear();
    mesh.tet_labels.clear();
    mesh.hex_labels.clear();
  }
  return mesh;
}

std::string write_vtu(const MeshBundle& mesh, const WriteOptions& options) {
  detail::volume_io::check_writable(mesh, "VTU");
  const std::size_t cells = mesh.cell_count();
  check_arrays(options.cell_data, cells, "cell data");
  check_arrays(options.point_data, mesh.points.size(), "point data");
  const std::optional<DataArray> labels = label_array(mesh, options.cell_data);
  std::vector<const DataArray*> cell_data = pointers(options.cell_data);
  if (labels) cell_data.push_back(&*labels);
  const std::vector<const DataArray*> point_data = pointers(options.point_data);
  const std::size_t connectivity_size =
      3 * mesh.triangles.size() + 4 * mesh.quads.size() + 4 * mesh.tets.size() + 8 * mesh.hexes.size();

  std::string out;
  out += "<?xml version=\"1.0\"?>\n";
  out += "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
  out += "  <UnstructuredGrid>\n";
  out += "    <Piece NumberOfPoints=\"" + std::to_string(mesh.points.size()) + "\" NumberOfCells=\"" +
         std::to_string(cells) + "\">\n";
  // Appended blocks in this order: point data, cell data, points, connectivity, offsets, types.
  std::uint64_t offset = 0;
  declare_arrays(out, point_data, "      ", "PointData", "DataArray", &offset);
  declare_arrays(out, cell_data, "      ", "CellData", "DataArray", &offset);
  out += "      <Points>\n        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"appended\" offset=\"" +
         std::to_string(offset) + "\"/>\n      </Points>\n";
  offset += 8 + 24 * mesh.points.size();
  out += "      <Cells>\n";
  out += "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"appended\" offset=\"" +
         std::to_string(offset) + "\"/>\n";
  offset += 8 + 8 * connectivity_size;
  out += "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"appended\" offset=\"" + std::to_string(offset) +
         "\"/>\n";
  offset += 8 + 8 * cells;
  out += "        <DataArray type=\"UInt8\" Name=\"types\" format=\"appended\" offset=\"" + std::to_string(offset) +
         "\"/>\n";
  offset += 8 + cells;
  out += "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n   _";
  out.reserve(out.size() + offset + 64);

  for (const DataArray* a : point_data) append_array_block(out, *a);
  for (const DataArray* a : cell_data) append_array_block(out, *a);
  append_le<std::uint64_t>(out, 24 * mesh.points.size());
  for (const Vec3& p : mesh.points) {
    append_le(out, p.x());
    append_le(out, p.y());
    append_le(out, p.z());
  }
  append_le<std::uint64_t>(out, 8 * connectivity_size);
  const auto append_cells = [&out](const auto& elements) {
    for (const auto& element : elements)
      for (const Index v : element) append_le<std::int64_t>(out, v);
  };
  append_cells(mesh.triangles);
  append_cells(mesh.quads);
  append_cells(mesh.tets);
  append_cells(mesh.hexes);
  append_le<std::uint64_t>(out, 8 * cells);
  std::int64_t end = 0;
  const auto append_offsets = [&](std::size_t count, int nodes) {
    for (std::size_t i = 0; i < count; ++i) append_le<std::int64_t>(out, end += nodes);
  };
  append_offsets(mesh.triangles.size(), 3);
  append_offsets(mesh.quads.size(), 4);
  append_offsets(mesh.tets.size(), 4);
  append_offsets(mesh.hexes.size(), 8);
  append_le<std::uint64_t>(out, cells);
  out.append(mesh.triangles.size(), static_cast<char>(5));
  out.append(mesh.quads.size(), static_cast<char>(9));
  out.append(mesh.tets.size(), static_cast<char>(10));
  out.append(mesh.hexes.size(), static_cast<char>(12));
  out += "\n  </AppendedData>\n</VTKFile>\n";
  return out;
}

std::string write_pvtu(const std::vector<std::string>& piece_files, const WriteOptions& options) {
  if (piece_files.empty()) throw Error("a .pvtu needs at least one piece file");
  // Sizes are per piece, so only names and types are checked here.
  const auto check_names = [](const std::vector<DataArray>& arrays, const char* where) {
    for (std::size_t i = 0; i < arrays.size(); ++i) {
      if (arrays[i].name.empty()) throw Error(std::string("PVTU ") + where + " array has no name");
      if (!arrays[i].f64.empty() && !arrays[i].i32.empty())
        throw Error(std::string("PVTU ") + where + " array '" + arrays[i].name + "' fills both f64 and i32");
    }
  };
  check_names(options.cell_data, "cell data");
  check_names(options.point_data, "point data");
  std::string out;
  out += "<?xml version=\"1.0\"?>\n";
  out += "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
  out += "  <PUnstructuredGrid GhostLevel=\"0\">\n";
  declare_arrays(out, pointers(options.point_data), "    ", "PPointData", "PDataArray", nullptr);
  declare_arrays(out, pointers(options.cell_data), "    ", "PCellData", "PDataArray", nullptr);
  out += "    <PPoints>\n      <PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n    </PPoints>\n";
  for (const std::string& file : piece_files) out += "    <Piece Source=\"" + xml_escape(file) + "\"/>\n";
  out += "  </PUnstructuredGrid>\n</VTKFile>\n";
  return out;
}

}  // namespace structmesh
