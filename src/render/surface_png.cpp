// Pictures of labelled triangle surfaces (guards' faces, star parts): an orthographic,
// flat-shaded, z-buffered view. Written by hand for the same reason as png.cpp: no
// Debian library renders a mesh headlessly without an OpenGL context.
#include "structmesh/error.hpp"
#include "structmesh/render.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace structmesh {

std::array<std::uint8_t, 3> label_color(std::int32_t label) {
  if (label < 0) return {200, 200, 200};
  // Hues a golden angle apart, saturation and value cycling: neighbouring labels differ.
  const double hue = std::fmod(0.61803398875 * label + 0.1, 1.0) * 6.0;
  const double saturation = label % 3 == 0 ? 0.55 : (label % 3 == 1 ? 0.75 : 0.40);
  const double value = label % 2 == 0 ? 0.95 : 0.80;
  const int sector = static_cast<int>(hue) % 6;
  const double f = hue - std::floor(hue);
  const double p = value * (1 - saturation), q = value * (1 - saturation * f), t = value * (1 - saturation * (1 - f));
  double r = 0, g = 0, b = 0;
  switch (sector) {
    case 0:
      r = value, g = t, b = p;
      break;
    case 1:
      r = q, g = value, b = p;
      break;
    case 2:
      r = p, g = value, b = t;
      break;
    case 3:
      r = p, g = q, b = value;
      break;
    case 4:
      r = t, g = p, b = value;
      break;
    default:
      r = value, g = p, b = q;
      break;
  }
  return {static_cast<std::uint8_t>(255 * r), static_cast<std::uint8_t>(255 * g), static_cast<std::uint8_t>(255 * b)};
}

Image surface_image(const TriMesh& surface, std::span<const std::int32_t> face_labels, std::span<const Vec3> markers,
                    const SurfacePictureOptions& options) {
  if (face_labels.size() != surface.triangles.size())
    throw Error("surface_image: one label per triangle expected (" + std::to_string(face_labels.size()) + " for " +
                std::to_string(surface.triangles.size()) + ")");
  if (!options.face_colors.empty() && options.face_colors.size() != surface.triangles.size())
    throw Error("surface_image: one colour per triangle expected (" + std::to_string(options.face_colors.size()) +
                " for " + std::to_string(surface.triangles.size()) + ")");
  if (options.width_px < 16 || options.width_px > 20000) throw InputError("surface_image: width out of range");
  // Camera: looking along -view from azimuth/elevation; right and up span the screen.
  const double azimuth = options.azimuth_deg * M_PI / 180, elevation = options.elevation_deg * M_PI / 180;
  const Vec3 view(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                  std::sin(elevation));
  const Vec3 world_up = std::abs(view.z()) > 0.99 ? Vec3(0, 1, 0) : Vec3(0, 0, 1);
  const Vec3 right = world_up.cross(view).normalized();
  const Vec3 up = view.cross(right);
  BoundingBox2 box;
  for (const Vec3& p : surface.points) box.extend(Vec2(p.dot(right), p.dot(up)));
  Image image = Image::fit(box, options.width_px, 12);
  std::vector<float> depth(static_cast<std::size_t>(image.width) * image.height,
                           -std::numeric_limits<float>::infinity());
  for (std::size_t f = 0; f < surface.triangles.size(); ++f) {
    const auto& t = surface.triangles[f];
    const Vec3 &a = surface.points[t[0]], &b = surface.points[t[1]], &c = surface.points[t[2]];
    const Vec3 normal = (b - a).cross(c - a);
    const double length = normal.norm();
    if (!(length > 0)) continue;
    // Light from the viewer, both sides lit (a back face seen through a hole is not black).
    const double shade = 0.35 + 0.65 * std::abs(normal.dot(view)) / length;
    const auto base = options.face_colors.empty() ? label_color(face_labels[f]) : options.face_colors[f];
    const std::array<std::uint8_t, 3> color{static_cast<std::uint8_t>(base[0] * shade),
                                            static_cast<std::uint8_t>(base[1] * shade),
                                            static_cast<std::uint8_t>(base[2] * shade)};
    Vec2 s[3];
    double z[3];
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = surface.points[t[k]];
      s[k] = image.to_pixel(Vec2(p.dot(right), p.dot(up)));
      z[k] = p.dot(view);
    }
    const double area = (s[1] - s[0]).x() * (s[2] - s[0]).y() - (s[1] - s[0]).y() * (s[2] - s[0]).x();
    if (std::abs(area) < 1e-12) continue;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({s[0].x(), s[1].x(), s[2].x()}))));
    const int x1 = std::min(image.width - 1, static_cast<int>(std::ceil(std::max({s[0].x(), s[1].x(), s[2].x()}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({s[0].y(), s[1].y(), s[2].y()}))));
    const int y1 = std::min(image.height - 1, static_cast<int>(std::ceil(std::max({s[0].y(), s[1].y(), s[2].y()}))));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const Vec2 pixel(x + 0.5, y + 0.5);
        double w[3];
        for (int k = 0; k < 3; ++k) {
          const Vec2& p = s[(k + 1) % 3];
          const Vec2& q = s[(k + 2) % 3];
          w[k] = ((q - p).x() * (pixel - p).y() - (q - p).y() * (pixel - p).x()) / area;
        }
        if (w[0] < 0 || w[1] < 0 || w[2] < 0) continue;
        const auto d = static_cast<float>(w[0] * z[0] + w[1] * z[1] + w[2] * z[2]);
        float& stored = depth[static_cast<std::size_t>(y) * image.width + x];
        if (d <= stored) continue;
        stored = d;
        image.set(x, y, color);
      }
  }
  // Markers (guards) on top, as black-ringed white dots: they lie inside the solid.
  const int radius = std::max(3, options.width_px / 200);
  for (const Vec3& m : markers) {
    const Vec2 c = image.to_pixel(Vec2(m.dot(right), m.dot(up)));
    for (int dy = -radius - 1; dy <= radius + 1; ++dy)
      for (int dx = -radius - 1; dx <= radius + 1; ++dx) {
        const double r = std::hypot(dx, dy);
        if (r > radius + 1) continue;
        image.set(static_cast<int>(c.x()) + dx, static_cast<int>(c.y()) + dy,
                  r > radius - 1.5 ? std::array<std::uint8_t, 3>{0, 0, 0} : std::array<std::uint8_t, 3>{255, 255, 255});
      }
  }
  return image;
}

std::string surface_png(const TriMesh& surface, std::span<const std::int32_t> face_labels,
                        std::span<const Vec3> markers, const SurfacePictureOptions& options) {
  return encode_png(surface_image(surface, face_labels, markers, options));
}

}  // namespace structmesh
