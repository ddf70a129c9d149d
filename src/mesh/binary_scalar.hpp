// Internal: binary scalar types and byte-order handling shared by the binary
// readers and writers (PLY, STL, VTU, Gmsh MSH).
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

namespace structmesh::detail {

/// The scalar types of the binary formats; each format maps its own type names
/// onto these (PLY has no 64-bit integers, VTU has all of them).
enum class Scalar : std::uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32, Float64 };

inline std::size_t scalar_size(Scalar s) {
  switch (s) {
    case Scalar::Int8:
    case Scalar::UInt8:
      return 1;
    case Scalar::Int16:
    case Scalar::UInt16:
      return 2;
    case Scalar::Int32:
    case Scalar::UInt32:
    case Scalar::Float32:
      return 4;
    case Scalar::Int64:
    case Scalar::UInt64:
    case Scalar::Float64:
      return 8;
  }
  return 8;
}

inline bool is_float(Scalar s) { return s == Scalar::Float32 || s == Scalar::Float64; }

/// The T stored in the sizeof(T) bytes at `bytes`, whose order is reversed first
/// when `swap` (the data's byte order differs from the host's). The caller has
/// checked that the bytes are there.
template <typename T>
T load_scalar(const void* bytes, bool swap) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, bytes, sizeof(T));
  if (swap) std::reverse(b, b + sizeof(T));
  T value;
  std::memcpy(&value, b, sizeof(T));
  return value;
}

/// Appends the bytes of an arithmetic value in little-endian order, whatever the
/// host's byte order.
template <typename T>
void append_le(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(bytes, bytes + sizeof(T));
  out.append(bytes, sizeof(T));
}

}  // namespace structmesh::detail
