// Readers and writers. The format is chosen from the file extension.
//
// Every reader has two entry points: one that reads a file and one that parses
// an in-memory buffer (used by the fuzz targets and by tests). Both throw
// InputError with "file:line: problem" for malformed input: truncated data,
// NaN/Inf coordinates, indices out of range, wrong counts, empty files.
// Every writer writes to a temporary file next to the target and renames it, so a
// failed write never leaves a half-written file behind.
#pragma once

#include "structmesh/mesh.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace structmesh {

enum class FileFormat {
  Unknown,
  Obj,      // .obj  surface (v / f lines; quads stay quads, larger polygons are fan-triangulated)
  Off,      // .off  surface
  Ply,      // .ply  surface, ASCII and binary (little and big endian)
  Stl,      // .stl  surface, ASCII and binary
  Medit,    // .mesh MEDIT: triangles, quads, tets, hexes
  Msh,      // .msh  Gmsh v4.1 (ASCII written; ASCII and binary read)
  Vtu,      // .vtu  VTK XML unstructured grid (written appended raw; read: ascii, base64, raw, zlib)
  Pvtu,     // .pvtu VTK XML parallel unstructured grid (written only)
  GeoJson,  // .geojson / .json regions: Polygon / MultiPolygon
  Poly,     // .poly Triangle's planar straight line graph with holes
  Svg,      // .svg pictures (written only)
  Png,      // .png pictures (written only)
};

FileFormat format_from_path(const std::filesystem::path& path);
std::string format_name(FileFormat format);

/// Per-element source line numbers (1-based) for text formats, so checks can say
/// where a problem is. Empty vectors for binary formats.
struct SourceLines {
  std::vector<std::uint32_t> point_lines;
  std::vector<std::uint32_t> triangle_lines, quad_lines, tet_lines, hex_lines;
};

/// What a mesh file holds: points and any mix of the four element kinds.
/// Cell order wherever cells are numbered across kinds (VTU cell data, reports):
/// all triangles, then quads, then tets, then hexes.
struct MeshBundle {
  std::vector<Vec3> points;
  std::vector<std::array<Index, 3>> triangles;
  std::vector<std::array<Index, 4>> quads;
  std::vector<std::array<Index, 4>> tets;
  std::vector<std::array<Index, 8>> hexes;
  /// Optional per-element integer labels (MEDIT reference, Gmsh entity tag, VTU "part").
  std::vector<std::int32_t> triangle_labels, quad_labels, tet_labels, hex_labels;
  SourceLines lines;
  std::string source_name;  // file name used in messages

  std::size_t cell_count() const { return triangles.size() + quads.size() + tets.size() + hexes.size(); }
};

/// A named per-cell or per-point data array for VTU output (exactly one of f64 / i32 filled).
struct DataArray {
  std::string name;
  std::vector<double> f64;
  std::vector<std::int32_t> i32;
  std::size_t size() const { return f64.empty() ? i32.size() : f64.size(); }
};

struct WriteOptions {
  std::vector<DataArray> cell_data;   // one value per cell, in MeshBundle cell order
  std::vector<DataArray> point_data;  // one value per point
};

// --- generic mesh I/O (format from extension) ---
MeshBundle read_mesh(const std::filesystem::path& path);
MeshBundle read_mesh_buffer(std::string_view data, FileFormat format, const std::string& source_name);
void write_mesh(const std::filesystem::path& path, const MeshBundle& mesh, const WriteOptions& options = {});

// --- conversions between a bundle and the typed meshes ---
// Each throws InputError naming the file when the bundle holds no elements of the
// requested kind or also holds other element kinds (lower-dimensional boundary
// elements of a volume mesh, e.g. triangles beside tets, are ignored).
TriMesh to_tri_mesh(const MeshBundle& mesh);
QuadMesh to_quad_mesh(const MeshBundle& mesh);
TetMesh to_tet_mesh(const MeshBundle& mesh);
HexMesh to_hex_mesh(const MeshBundle& mesh);
MeshBundle to_bundle(const TriMesh& mesh);
MeshBundle to_bundle(const QuadMesh& mesh);
MeshBundle to_bundle(const TetMesh& mesh);
MeshBundle to_bundle(const HexMesh& mesh);

// --- per-format entry points (used by the generic functions above and the fuzzers) ---
MeshBundle read_obj(std::string_view data, const std::string& source_name);
MeshBundle read_off(std::string_view data, const std::string& source_name);
MeshBundle read_ply(std::string_view data, const std::string& source_name);
MeshBundle read_stl(std::string_view data, const std::string& source_name);
MeshBundle read_medit(std::string_view data, const std::string& source_name);
MeshBundle read_msh(std::string_view data, const std::string& source_name);
MeshBundle read_vtu(std::string_view data, const std::string& source_name);

enum class Encoding { Ascii, Binary };
// Writers produce the whole file content; write_mesh() stores it atomically.
std::string write_obj(const MeshBundle& mesh);
std::string write_off(const MeshBundle& mesh);
std::string write_ply(const MeshBundle& mesh, Encoding encoding = Encoding::Binary);
std::string write_stl(const MeshBundle& mesh, Encoding encoding = Encoding::Binary);
std::string write_medit(const MeshBundle& mesh);
std::string write_msh(const MeshBundle& mesh);
/// Also writes the bundle's labels as Int32 cell data "label" unless options.cell_data has "label" or "part".
std::string write_vtu(const MeshBundle& mesh, const WriteOptions& options = {});
/// A .pvtu that references `piece_files` (relative paths) with the arrays of `options`.
std::string write_pvtu(const std::vector<std::string>& piece_files, const WriteOptions& options);

// --- regions ---
/// Reads a GeoJSON (Polygon, MultiPolygon, Feature, FeatureCollection) or .poly file.
/// Returns one Polygon2 per polygon. GeoJSON input is marked LonLat when every
/// coordinate lies within [-180,180]x[-90,90] and the file does not say otherwise.
std::vector<Polygon2> read_region(const std::filesystem::path& path);
std::vector<Polygon2> read_geojson(std::string_view data, const std::string& source_name);
std::vector<Polygon2> read_poly(std::string_view data, const std::string& source_name);
void write_region(const std::filesystem::path& path, const std::vector<Polygon2>& polygons);
std::string write_geojson(const std::vector<Polygon2>& polygons);
std::string write_poly(const std::vector<Polygon2>& polygons);

// --- files ---
/// Reads a whole file; InputError if it cannot be opened.
std::string read_file(const std::filesystem::path& path);
/// Writes `content` to a temporary file beside `path` and renames it into place.
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

}  // namespace structmesh
