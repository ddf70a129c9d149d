// Format dispatch, whole-file reads, atomic writes and bundle <-> typed mesh conversions.
#include "structmesh/io.hpp"
#include "structmesh/error.hpp"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <random>
#include <sstream>
#include <system_error>

namespace structmesh {

FileFormat format_from_path(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".obj") return FileFormat::Obj;
  if (ext == ".off") return FileFormat::Off;
  if (ext == ".ply") return FileFormat::Ply;
  if (ext == ".stl") return FileFormat::Stl;
  if (ext == ".mesh") return FileFormat::Medit;
  if (ext == ".msh") return FileFormat::Msh;
  if (ext == ".vtu") return FileFormat::Vtu;
  if (ext == ".pvtu") return FileFormat::Pvtu;
  if (ext == ".geojson" || ext == ".json") return FileFormat::GeoJson;
  if (ext == ".poly") return FileFormat::Poly;
  if (ext == ".svg") return FileFormat::Svg;
  if (ext == ".png") return FileFormat::Png;
  return FileFormat::Unknown;
}

std::string format_name(FileFormat format) {
  switch (format) {
    case FileFormat::Obj:
      return "OBJ";
    case FileFormat::Off:
      return "OFF";
    case FileFormat::Ply:
      return "PLY";
    case FileFormat::Stl:
      return "STL";
    case FileFormat::Medit:
      return "MEDIT";
    case FileFormat::Msh:
      return "Gmsh MSH";
    case FileFormat::Vtu:
      return "VTK XML unstructured grid";
    case FileFormat::Pvtu:
      return "VTK XML parallel unstructured grid";
    case FileFormat::GeoJson:
      return "GeoJSON";
    case FileFormat::Poly:
      return "Triangle .poly";
    case FileFormat::Svg:
      return "SVG";
    case FileFormat::Png:
      return "PNG";
    case FileFormat::Unknown:
      break;
  }
  return "unknown";
}

std::string read_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(located_message(path.string(), 0, "is a directory"));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(located_message(path.string(), 0, "cannot open file"));
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw InputError(located_message(path.string(), 0, "read error"));
  return std::move(buffer).str();
}

void write_file_atomic(const std::filesystem::path& path, std::string_view content) {
  // A unique temporary name beside the target, so the rename is atomic on one file system.
  std::random_device device;
  const std::filesystem::path temp =
      path.parent_path() / ("." + path.filename().string() + ".tmp" + std::to_string(device() % 1000000));
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    if (!out) throw Error(located_message(path.string(), 0, "cannot create output file"));
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) {
      out.close();
      std::error_code ignored;
      std::filesystem::remove(temp, ignored);
      throw Error(located_message(path.string(), 0, "write failed (disk full?)"));
    }
  }
  std::error_code ec;
  std::filesystem::rename(temp, path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);
    throw Error(located_message(path.string(), 0, "cannot move output into place: " + ec.message()));
  }
}

MeshBundle read_mesh_buffer(std::string_view data, FileFormat format, const std::string& source_name) {
  MeshBundle mesh;
  switch (format) {
    case FileFormat::Obj:
      mesh = read_obj(data, source_name);
      break;
    case FileFormat::Off:
      mesh = read_off(data, source_name);
      break;
    case FileFormat::Ply:
      mesh = read_ply(data, source_name);
      break;
    case FileFormat::Stl:
      mesh = read_stl(data, source_name);
      break;
    case FileFormat::Medit:
      mesh = read_medit(data, source_name);
      break;
    case FileFormat::Msh:
      mesh = read_msh(data, source_name);
      break;
    case FileFormat::Vtu:
      mesh = read_vtu(data, source_name);
      break;
    default:
      throw InputError(located_message(
          source_name, 0,
          "not a mesh format structmesh reads (" + format_name(format) + "); use .obj .off .ply .stl .mesh .msh .vtu"));
  }
  mesh.source_name = source_name;
  return mesh;
}

MeshBundle read_mesh(const std::filesystem::path& path) {
  const FileFormat format = format_from_path(path);
  if (format == FileFormat::Unknown)
    throw InputError(located_message(path.string(), 0, "unknown file extension '" + path.extension().string() + "'"));
  const std::string data = read_file(path);
  return read_mesh_buffer(data, format, path.string());
}

void write_mesh(const std::filesystem::path& path, const MeshBundle& mesh, const WriteOptions& options) {
  const FileFormat format = format_from_path(path);
  std::string content;
  switch (format) {
    case FileFormat::Obj:
      content = write_obj(mesh);
      break;
    case FileFormat::Off:
      content = write_off(mesh);
      break;
    case FileFormat::Ply:
      content = write_ply(mesh);
      break;
    case FileFormat::Stl:
      content = write_stl(mesh);
      break;
    case FileFormat::Medit:
      content = write_medit(mesh);
      break;
    case FileFormat::Msh:
      content = write_msh(mesh);
      break;
    case FileFormat::Vtu:
      content = write_vtu(mesh, options);
      break;
    default:
      throw InputError(located_message(
          path.string(), 0,
          "cannot write a mesh as " + format_name(format) + "; use .obj .off .ply .stl .mesh .msh .vtu"));
  }
  write_file_atomic(path, content);
}

namespace {

template <typename Elements>
void require_kind(const MeshBundle& mesh, const Elements& elements, const char* kind, bool others_present) {
  if (elements.empty()) throw InputError(located_message(mesh.source_name, 0, std::string("holds no ") + kind));
  if (others_present)
    throw InputError(located_message(mesh.source_name, 0, std::string("holds other element kinds beside ") + kind));
}

}  // namespace

TriMesh to_tri_mesh(const MeshBundle& mesh) {
  require_kind(mesh, mesh.triangles, "triangles", !mesh.quads.empty() || !mesh.tets.empty() || !mesh.hexes.empty());
  return TriMesh{mesh.points, mesh.triangles};
}

QuadMesh to_quad_mesh(const MeshBundle& mesh) {
  require_kind(mesh, mesh.quads, "quads", !mesh.triangles.empty() || !mesh.tets.empty() || !mesh.hexes.empty());
  return QuadMesh{mesh.points, mesh.quads};
}

TetMesh to_tet_mesh(const MeshBundle& mesh) {
  require_kind(mesh, mesh.tets, "tetrahedra", !mesh.hexes.empty());
  return TetMesh{mesh.points, mesh.tets};
}

HexMesh to_hex_mesh(const MeshBundle& mesh) {
  require_kind(mesh, mesh.hexes, "hexahedra", !mesh.tets.empty());
  return HexMesh{mesh.points, mesh.hexes};
}

MeshBundle to_bundle(const TriMesh& mesh) {
  MeshBundle b;
  b.points = mesh.points;
  b.triangles = mesh.triangles;
  return b;
}
MeshBundle to_bundle(const QuadMesh& mesh) {
  MeshBundle b;
  b.points = mesh.points;
  b.quads = mesh.quads;
  return b;
}
MeshBundle to_bundle(const TetMesh& mesh) {
  MeshBundle b;
  b.points = mesh.points;
  b.tets = mesh.tets;
  return b;
}
MeshBundle to_bundle(const HexMesh& mesh) {
  MeshBundle b;
  b.points = mesh.points;
  b.hexes = mesh.hexes;
  return b;
}

std::vector<Polygon2> read_region(const std::filesystem::path& path) {
  const FileFormat format = format_from_path(path);
  if (format != FileFormat::GeoJson && format != FileFormat::Poly)
    throw InputError(located_message(path.string(), 0, "not a region format; use .geojson or .poly"));
  const std::string data = read_file(path);
  return format == FileFormat::GeoJson ? read_geojson(data, path.string()) : read_poly(data, path.string());
}

void write_region(const std::filesystem::path& path, const std::vector<Polygon2>& polygons) {
  const FileFormat format = format_from_path(path);
  if (format == FileFormat::GeoJson) return write_file_atomic(path, write_geojson(polygons));
  if (format == FileFormat::Poly) return write_file_atomic(path, write_poly(polygons));
  throw InputError(
      located_message(path.string(), 0, "cannot write a region as " + format_name(format) + "; use .geojson or .poly"));
}

}  // namespace structmesh
