// Pictures of quad meshes coloured by a per-quad value (scaled Jacobian maps of
// §3.4.3). Our own rasterizer, like png.cpp: the meshes of ch. 3.4 have millions of
// quads and must render in seconds, headless, without a graphics stack; a scanline
// fill over the flat point and quad arrays does that.
//
// Parallel and deterministic: the picture's rows are cut into bands of kBandRows
// rows, each band owns its rows and draws the quads touching it in ascending quad
// order, so the bytes are those of a serial run whatever the thread count. Quads are
// bucketed by band with a counting sort over fixed-size chunks (also independent of
// the thread count).
#include "structmesh/error.hpp"
#include "structmesh/render.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string_view>

namespace structmesh {
namespace {

using Rgb = std::array<std::uint8_t, 3>;

constexpr Rgb kInvertedColor{215, 25, 28};  // red: not in viridis, so inverted quads stand out
constexpr Rgb kNanColor{190, 190, 190};
constexpr Rgb kEdgeColor{45, 45, 45};
constexpr Rgb kTextColor{0, 0, 0};

constexpr int kMarginPx = 10;
constexpr int kTitleRows = 28;
constexpr int kLegendRows = 52;
constexpr int kBandRows = 16;
constexpr std::size_t kChunkQuads = std::size_t{1} << 15;
// Edges are drawn for every quad of at least kEdgeMinSizePx (sqrt of its pixel area)
// when the median quad in view reaches kEdgeMedianSizePx; otherwise only for quads of
// kEdgeLargeSizePx and more. A single per-quad threshold drew the edges of about half
// the quads of a mesh whose quads are near it, a patchwork that looked like missing
// elements.
constexpr double kEdgeMinSizePx = 2;
constexpr double kEdgeMedianSizePx = 5;
constexpr double kEdgeLargeSizePx = 10;
constexpr std::size_t kEdgeSampleQuads = 100000;

// Viridis (matplotlib's perceptually uniform, colour-blind-safe map; van der Walt &
// Smith 2015) sampled at 0, 0.1, ..., 1 and interpolated linearly in sRGB: dark
// violet for low values, yellow for high ones (a good scaled Jacobian is yellow).
constexpr std::array<Rgb, 11> kViridis{{{68, 1, 84},
                                        {72, 36, 117},
                                        {65, 68, 135},
                                        {53, 95, 141},
                                        {42, 120, 142},
                                        {33, 145, 140},
                                        {34, 168, 132},
                                        {68, 191, 112},
                                        {122, 209, 81},
                                        {189, 223, 38},
                                        {253, 231, 37}}};

Rgb viridis(double t) {
  const double s = std::clamp(t, 0.0, 1.0) * (kViridis.size() - 1);
  const std::size_t i = std::min(static_cast<std::size_t>(s), kViridis.size() - 2);
  const double f = s - static_cast<double>(i);
  Rgb c{};
  for (int k = 0; k < 3; ++k)
    c[k] = static_cast<std::uint8_t>(std::lround((1 - f) * kViridis[i][k] + f * kViridis[i + 1][k]));
  return c;
}

// Value -> colour through a 1024-entry table (finer than the 8-bit output needs).
class Palette {
 public:
  explicit Palette(const QuadPictureOptions& o) : lo_(o.value_min), mark_inverted_(o.mark_inverted) {
    scale_ = (kSize - 1) / (o.value_max - o.value_min);
    for (int i = 0; i < kSize; ++i) table_[i] = viridis(static_cast<double>(i) / (kSize - 1));
  }
  Rgb operator()(double v) const {
    if (std::isnan(v)) return kNanColor;
    if (mark_inverted_ && v <= 0) return kInvertedColor;
    const double s = std::clamp((v - lo_) * scale_, 0.0, kSize - 1.0);
    return table_[static_cast<int>(s + 0.5)];
  }

 private:
  static constexpr int kSize = 1024;
  std::array<Rgb, kSize> table_{};
  double lo_, scale_;
  bool mark_inverted_;
};

// Pixels whose squares meet the view; inclusive bounds.
struct PixelRect {
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
};

// World -> pixel as Image::to_pixel, with the constants folded.
struct ToPixel {
  double scale, ax, ay;
  explicit ToPixel(const Image& image)
      : scale(image.scale), ax(-image.origin.x() * image.scale), ay(image.height + image.origin.y() * image.scale) {}
};

struct QuadPixels {
  std::array<double, 4> x, y;
  double min_x, max_x, min_y, max_y;
};

QuadPixels quad_pixels(const QuadMesh& mesh, const ToPixel& t, Index q) {
  QuadPixels p;
  const auto& quad = mesh.quads[q];
  for (int k = 0; k < 4; ++k) {
    const Vec3& w = mesh.points[quad[k]];
    p.x[k] = w.x() * t.scale + t.ax;
    p.y[k] = t.ay - w.y() * t.scale;
  }
  p.min_x = std::min(std::min(p.x[0], p.x[1]), std::min(p.x[2], p.x[3]));
  p.max_x = std::max(std::max(p.x[0], p.x[1]), std::max(p.x[2], p.x[3]));
  p.min_y = std::min(std::min(p.y[0], p.y[1]), std::min(p.y[2], p.y[3]));
  p.max_y = std::max(std::max(p.y[0], p.y[1]), std::max(p.y[2], p.y[3]));
  return p;
}

// The rows [first, last] of `clip` a quad may touch (its pixel-square rows), or
// false when it lies outside the clip (or has non-finite coordinates).
bool quad_rows(const QuadPixels& p, const PixelRect& clip, int& first, int& last) {
  if (!(p.min_x < clip.x1 + 1.0 && p.max_x >= clip.x0 && p.min_y < clip.y1 + 1.0 && p.max_y >= clip.y0)) return false;
  first = std::max(clip.y0, static_cast<int>(std::floor(std::max(p.min_y, -1.0))));
  last = std::min(clip.y1, static_cast<int>(std::floor(std::min(p.max_y, clip.y1 + 1.0))));
  return first <= last;
}

inline void put(Image& image, int x, int y, const Rgb& c) {
  std::uint8_t* pixel = &image.rgb[(static_cast<std::size_t>(y) * image.width + x) * 3];
  pixel[0] = c[0];
  pixel[1] = c[1];
  pixel[2] = c[2];
}

// Scanline fill with the even-odd rule, sampling pixel centres (y + 0.5) against
// half-open edge spans, so a pixel centre on an edge shared by two quads belongs to
// exactly one of them and convex, concave and bow-tie quads are all handled. Scans
// rows [scan_first, scan_last] and writes those within [write_first, write_last]
// and the clip's columns; returns whether the quad covers a pixel centre in the
// scanned rows (inside or outside the clip).
bool fill_quad(Image& image, const QuadPixels& p, const Rgb& c, const PixelRect& clip, int scan_first, int scan_last,
               int write_first, int write_last) {
  bool covered = false;
  const double first_y = std::max(static_cast<double>(scan_first), std::ceil(p.min_y - 0.5));
  const double last_y = std::min(static_cast<double>(scan_last), std::ceil(p.max_y - 0.5) - 1);
  for (int y = static_cast<int>(first_y); y <= static_cast<int>(last_y); ++y) {
    const double yc = y + 0.5;
    std::array<double, 4> xs;
    int n = 0;
    for (int e = 0; e < 4; ++e) {
      const int f = (e + 1) & 3;
      if ((p.y[e] <= yc) != (p.y[f] <= yc)) xs[n++] = p.x[e] + (yc - p.y[e]) * (p.x[f] - p.x[e]) / (p.y[f] - p.y[e]);
    }
    for (int i = 1; i < n; ++i)  // insertion sort of at most 4 crossings
      for (int k = i; k > 0 && xs[k] < xs[k - 1]; --k) std::swap(xs[k], xs[k - 1]);
    const bool write = y >= write_first && y <= write_last;
    for (int k = 0; k + 1 < n; k += 2) {
      const double a = std::ceil(xs[k] - 0.5), b = std::ceil(xs[k + 1] - 0.5) - 1;
      if (b < a) continue;
      covered = true;
      if (!write) continue;
      const int x0 = static_cast<int>(std::max(a, static_cast<double>(clip.x0)));
      const int x1 = static_cast<int>(std::min(b, static_cast<double>(clip.x1)));
      for (int x = x0; x <= x1; ++x) put(image, x, y, c);
    }
  }
  return covered;
}

// A 1-pixel line (one pixel per step along the major axis, the pixel under the
// line at the step's centre), limited to `rect` before walking so that lines of a
// deep zoom reaching far outside cost nothing. Endpoints are ordered along the major
// axis, so a shared edge draws the same pixels from both quads.
void draw_segment(Image& image, double ax, double ay, double bx, double by, const Rgb& c, const PixelRect& rect) {
  const bool x_major = std::abs(bx - ax) >= std::abs(by - ay);
  // Walk along u (the major axis) with v = v(u); (u, v) = (x, y) or (y, x).
  double au = x_major ? ax : ay, av = x_major ? ay : ax, bu = x_major ? bx : by, bv = x_major ? by : bx;
  if (bu < au) {
    std::swap(au, bu);
    std::swap(av, bv);
  }
  const int u_lo = x_major ? rect.x0 : rect.y0, u_hi = x_major ? rect.x1 : rect.y1;
  const int v_lo = x_major ? rect.y0 : rect.x0, v_hi = x_major ? rect.y1 : rect.x1;
  const double du = bu - au;
  if (du == 0) {
    const double u = std::floor(au), v = std::floor(av);
    if (u >= u_lo && u <= u_hi && v >= v_lo && v <= v_hi)
      put(image, static_cast<int>(x_major ? u : v), static_cast<int>(x_major ? v : u), c);
    return;
  }
  const double slope = (bv - av) / du;
  double first = std::max(std::ceil(au - 0.5), static_cast<double>(u_lo));
  double last = std::min(std::ceil(bu - 0.5) - 1, static_cast<double>(u_hi));
  if (slope != 0) {
    // Steps where v stays within [v_lo, v_hi + 1), with a step of slack either side.
    double s0 = au + (v_lo - av) / slope - 0.5, s1 = au + (v_hi + 1 - av) / slope - 0.5;
    if (s1 < s0) std::swap(s0, s1);
    first = std::max(first, std::floor(s0) - 1);
    last = std::min(last, std::ceil(s1) + 1);
  }
  for (double u = first; u <= last; ++u) {
    const double v = std::floor(av + (u + 0.5 - au) * slope);
    if (v < v_lo || v > v_hi) continue;
    put(image, static_cast<int>(x_major ? u : v), static_cast<int>(x_major ? v : u), c);
  }
}

// ---------------------------------------------------------------------------
// Text: a 3x5 bitmap font (our own glyphs) for captions and legend labels; lower
// case is drawn as upper case and unknown characters as '?'.

struct Glyph {
  char c;
  const char* bits;  // 5 rows of 3, top row first
};
constexpr Glyph kFont[] = {
    {' ', "000000000000000"}, {'0', "111101101101111"}, {'1', "010110010010111"}, {'2', "111001111100111"},
    {'3', "111001111001111"}, {'4', "101101111001001"}, {'5', "111100111001111"}, {'6', "111100111101111"},
    {'7', "111001010010010"}, {'8', "111101111101111"}, {'9', "111101111001111"}, {'.', "000000000000010"},
    {'-', "000000111000000"}, {'+', "000010111010000"}, {'<', "001010100010001"}, {'>', "100010001010100"},
    {'=', "000111000111000"}, {':', "000010000010000"}, {',', "000000000010100"}, {'/', "001001010100100"},
    {'(', "010100100100010"}, {')', "010001001001010"}, {'%', "101001010100101"}, {'_', "000000000000111"},
    {'#', "101111101111101"}, {'?', "111001010000010"}, {'A', "010101111101101"}, {'B', "110101110101110"},
    {'C', "011100100100011"}, {'D', "110101101101110"}, {'E', "111100110100111"}, {'F', "111100110100100"},
    {'G', "011100101101011"}, {'H', "101101111101101"}, {'I', "111010010010111"}, {'J', "001001001101010"},
    {'K', "101101110101101"}, {'L', "100100100100111"}, {'M', "101111111101101"}, {'N', "110101101101101"},
    {'O', "010101101101010"}, {'P', "110101110100100"}, {'Q', "010101101110011"}, {'R', "110101110101101"},
    {'S', "011100010001110"}, {'T', "111010010010010"}, {'U', "101101101101111"}, {'V', "101101101101010"},
    {'W', "101101111111101"}, {'X', "101101010101101"}, {'Y', "101101010010010"}, {'Z', "111001010100111"},
};

const char* glyph_bits(char c) {
  if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
  for (const Glyph& g : kFont)
    if (g.c == c) return g.bits;
  return glyph_bits('?');
}

constexpr int kTextScale = 2;                  // font pixels per glyph bit
constexpr int kGlyphAdvance = 4 * kTextScale;  // 3 columns + 1 of spacing
constexpr int kTextHeight = 5 * kTextScale;

int text_width(std::string_view text) { return static_cast<int>(text.size()) * kGlyphAdvance - kTextScale; }

void draw_text(Image& image, int x, int y, std::string_view text, const Rgb& c) {
  for (const char ch : text) {
    const char* bits = glyph_bits(ch);
    for (int r = 0; r < 5; ++r)
      for (int col = 0; col < 3; ++col)
        if (bits[r * 3 + col] == '1')
          for (int dy = 0; dy < kTextScale; ++dy)
            for (int dx = 0; dx < kTextScale; ++dx) image.set(x + col * kTextScale + dx, y + r * kTextScale + dy, c);
    x += kGlyphAdvance;
  }
}

void fill_rect(Image& image, int x0, int y0, int x1, int y1, const Rgb& c) {
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) image.set(x, y, c);
}

std::string tick_label(double v) {
  if (std::abs(v) < 1e-12) v = 0;  // no "-0" or "1.2e-17" from rounding
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", v);
  return buffer;
}

// Colour bar below the map: value_min..value_max with 5 labelled ticks, and the
// inverted and NaN swatches.
void draw_legend(Image& image, const QuadPictureOptions& o, const Palette& palette, int top) {
  const int bar_x0 = 2 * kMarginPx, bar_y0 = top + 8, bar_h = 14;
  const int bar_w = std::max(32, std::min(image.width * 3 / 5, image.width - 260));
  for (int i = 0; i < bar_w; ++i) {
    const double t = (i + 0.5) / bar_w;
    const Rgb c = viridis(t);
    for (int y = bar_y0; y < bar_y0 + bar_h; ++y) image.set(bar_x0 + i, y, c);
  }
  for (int i = -1; i <= bar_w; ++i) {
    image.set(bar_x0 + i, bar_y0 - 1, kTextColor);
    image.set(bar_x0 + i, bar_y0 + bar_h, kTextColor);
  }
  for (int y = bar_y0 - 1; y <= bar_y0 + bar_h; ++y) {
    image.set(bar_x0 - 1, y, kTextColor);
    image.set(bar_x0 + bar_w, y, kTextColor);
  }
  for (int k = 0; k <= 4; ++k) {
    const int x = bar_x0 + static_cast<int>(std::lround(k * (bar_w - 1) / 4.0));
    fill_rect(image, x, bar_y0 + bar_h, x, bar_y0 + bar_h + 4, kTextColor);
    const std::string label = tick_label(o.value_min + k * (o.value_max - o.value_min) / 4);
    draw_text(image, x - text_width(label) / 2, bar_y0 + bar_h + 7, label, kTextColor);
  }
  int x = bar_x0 + bar_w + 24;
  const auto swatch = [&](const Rgb& c, std::string_view label) {
    fill_rect(image, x, bar_y0, x + bar_h - 1, bar_y0 + bar_h - 1, c);
    draw_text(image, x + bar_h + 6, bar_y0 + (bar_h - kTextHeight) / 2, label, kTextColor);
    x += bar_h + 6 + text_width(label) + 24;
  };
  if (o.mark_inverted) swatch(palette(0.0), "<=0 INVERTED");
  swatch(kNanColor, "NAN");
}

BoundingBox2 points_box(const QuadMesh& mesh) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, mesh.points.size(), 1 << 16), BoundingBox2{},
      [&](const tbb::blocked_range<std::size_t>& r, BoundingBox2 box) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) box.extend(mesh.points[i].head<2>());
        return box;
      },
      [](BoundingBox2 a, const BoundingBox2& b) {
        if (!b.empty()) {
          a.extend(b.min);
          a.extend(b.max);
        }
        return a;
      });
}

// Counting sort of the visible quads by band: bands[band_start[b] .. band_start[b+1])
// lists the quads touching band b in ascending order.
struct BandLists {
  std::vector<std::uint64_t> band_start;
  std::vector<Index> quads;
};

BandLists bucket_by_band(const QuadMesh& mesh, const ToPixel& t, const PixelRect& clip, int band_count) {
  const std::size_t quad_count = mesh.quads.size();
  const std::size_t chunk_count = (quad_count + kChunkQuads - 1) / kChunkQuads;
  const std::size_t bands = static_cast<std::size_t>(band_count);
  std::vector<std::uint64_t> offsets(chunk_count * bands, 0);
  // Pass 1: each quad's band range (first, last; first > last when culled) and the
  // counts per chunk and band. Bands fit in 16 bits: at most 4 * 65536 rows / 16.
  std::vector<std::array<std::uint16_t, 2>> band_range(quad_count);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunk_count, 1), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t chunk = r.begin(); chunk != r.end(); ++chunk) {
      const std::size_t end = std::min(quad_count, (chunk + 1) * kChunkQuads);
      for (std::size_t q = chunk * kChunkQuads; q < end; ++q) {
        int first = 0, last = 0;
        if (!quad_rows(quad_pixels(mesh, t, static_cast<Index>(q)), clip, first, last)) {
          band_range[q] = {1, 0};
          continue;
        }
        band_range[q] = {static_cast<std::uint16_t>((first - clip.y0) / kBandRows),
                         static_cast<std::uint16_t>((last - clip.y0) / kBandRows)};
        for (std::size_t b = band_range[q][0]; b <= band_range[q][1]; ++b) ++offsets[chunk * bands + b];
      }
    }
  });
  BandLists lists;
  lists.band_start.assign(bands + 1, 0);
  std::uint64_t total = 0;
  for (std::size_t b = 0; b < bands; ++b) {
    lists.band_start[b] = total;
    for (std::size_t chunk = 0; chunk < chunk_count; ++chunk) {
      const std::uint64_t n = offsets[chunk * bands + b];
      offsets[chunk * bands + b] = total;
      total += n;
    }
  }
  lists.band_start[bands] = total;
  lists.quads.resize(total);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunk_count, 1), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t chunk = r.begin(); chunk != r.end(); ++chunk)
      for (std::size_t q = chunk * kChunkQuads; q < std::min(quad_count, (chunk + 1) * kChunkQuads); ++q)
        for (std::size_t b = band_range[q][0]; b <= band_range[q][1]; ++b)
          lists.quads[offsets[chunk * bands + b]++] = static_cast<Index>(q);
  });
  return lists;
}

double quad_pixel_area(const QuadPixels& p) {
  return 0.5 * std::abs((p.x[2] - p.x[0]) * (p.y[3] - p.y[1]) - (p.x[3] - p.x[1]) * (p.y[2] - p.y[0]));
}

/// The smallest pixel size (sqrt of area) of a quad whose edges are drawn: from the
/// median over an evenly spaced sample of the quads that meet the view.
double edge_min_size_px(const QuadMesh& mesh, const ToPixel& t, const PixelRect& clip) {
  const std::size_t step = std::max<std::size_t>(1, mesh.quads.size() / kEdgeSampleQuads);
  std::vector<double> sizes;
  for (std::size_t q = 0; q < mesh.quads.size(); q += step) {
    const QuadPixels p = quad_pixels(mesh, t, static_cast<Index>(q));
    if (p.max_x < clip.x0 || p.min_x > clip.x1 + 1 || p.max_y < clip.y0 || p.min_y > clip.y1 + 1) continue;
    sizes.push_back(std::sqrt(quad_pixel_area(p)));
  }
  if (sizes.empty()) return kEdgeLargeSizePx;
  auto middle = sizes.begin() + static_cast<std::ptrdiff_t>(sizes.size() / 2);
  std::nth_element(sizes.begin(), middle, sizes.end());
  return *middle >= kEdgeMedianSizePx ? kEdgeMinSizePx : kEdgeLargeSizePx;
}

void draw_band(Image& image, const QuadMesh& mesh, std::span<const double> values, const Palette& palette,
               const ToPixel& t, const PixelRect& clip, std::span<const Index> quads, int row_first, int row_last,
               double edge_size_px) {
  for (const Index q : quads) {
    const QuadPixels p = quad_pixels(mesh, t, q);
    const Rgb c = palette(values[q]);
    // A quad within a 2x2-pixel box is scanned over all its rows so that "covers no
    // pixel centre" is decided for the whole quad, not per band; such a quad paints
    // the pixel under its centre (vertex average) instead.
    if (p.max_x - p.min_x < 2 && p.max_y - p.min_y < 2) {
      const int first = static_cast<int>(std::floor(p.min_y)), last = static_cast<int>(std::floor(p.max_y));
      if (fill_quad(image, p, c, clip, first, last, row_first, row_last)) continue;
      const double cx = std::floor(0.25 * (p.x[0] + p.x[1] + p.x[2] + p.x[3]));
      const double cy = std::floor(0.25 * (p.y[0] + p.y[1] + p.y[2] + p.y[3]));
      if (cx >= clip.x0 && cx <= clip.x1 && cy >= row_first && cy <= row_last)
        put(image, static_cast<int>(cx), static_cast<int>(cy), c);
    } else {
      fill_quad(image, p, c, clip, row_first, row_last, row_first, row_last);
    }
  }
  if (!(edge_size_px > 0)) return;
  const PixelRect band{clip.x0, row_first, clip.x1, row_last};
  for (const Index q : quads) {
    const QuadPixels p = quad_pixels(mesh, t, q);
    if (!(quad_pixel_area(p) >= edge_size_px * edge_size_px)) continue;
    for (int e = 0; e < 4; ++e)
      draw_segment(image, p.x[e], p.y[e], p.x[(e + 1) & 3], p.y[(e + 1) & 3], kEdgeColor, band);
  }
}

}  // namespace

Image quad_mesh_image(const QuadMesh& mesh, std::span<const double> cell_values, const QuadPictureOptions& options) {
  if (cell_values.size() != mesh.quads.size())
    throw InputError("quad picture: " + std::to_string(cell_values.size()) + " values for " +
                     std::to_string(mesh.quads.size()) + " quads (need one per quad)");
  if (!(options.value_min < options.value_max) || !std::isfinite(options.value_min) ||
      !std::isfinite(options.value_max))
    throw InputError("quad picture: colour range needs finite value_min < value_max");
  if (options.width_px < 16 || options.width_px > 65536)
    throw InputError("quad picture: width " + std::to_string(options.width_px) + " px is outside [16, 65536]");
  const BoundingBox2& view = options.view;
  if (!view.empty() && !(view.min.x() < view.max.x() && view.min.y() < view.max.y()))
    throw InputError("quad picture: the view window needs x0 < x1 and y0 < y1");
  for (const auto& quad : mesh.quads)
    for (const Index v : quad)
      if (v >= mesh.points.size())
        throw InputError("quad picture: a quad refers to point " + std::to_string(v) + " of " +
                         std::to_string(mesh.points.size()));

  const BoundingBox2 box = view.empty() ? points_box(mesh) : view;
  Image image = Image::fit(box, options.width_px, kMarginPx);
  const int map_top = options.title.empty() ? 0 : kTitleRows;
  const int map_rows = image.height;
  const int below = options.legend ? kLegendRows : 0;
  image.origin.y() -= below / image.scale;  // keeps the map at rows [map_top, map_top + map_rows)
  image.height += map_top + below;
  image.rgb.assign(static_cast<std::size_t>(image.width) * image.height * 3, 255);

  // Pixels meeting the view (the whole map area when there is nothing to show).
  PixelRect clip{0, map_top, image.width - 1, map_top + map_rows - 1};
  if (!box.empty()) {
    // 1e-6 px of slack: a view edge on a pixel boundary must not take in the next
    // pixel through rounding.
    const Vec2 low = image.to_pixel(box.min), high = image.to_pixel(box.max);
    constexpr double kSlack = 1e-6;
    clip.x0 = std::max(clip.x0, static_cast<int>(std::floor(low.x() + kSlack)));
    clip.x1 = std::min(clip.x1, static_cast<int>(std::ceil(high.x() - kSlack)) - 1);
    clip.y0 = std::max(clip.y0, static_cast<int>(std::floor(high.y() + kSlack)));
    clip.y1 = std::min(clip.y1, static_cast<int>(std::ceil(low.y() - kSlack)) - 1);
  }
  const Palette palette(options);
  if (clip.x0 <= clip.x1 && clip.y0 <= clip.y1) {
    const ToPixel t(image);
    const int band_count = (clip.y1 - clip.y0) / kBandRows + 1;
    const BandLists lists = bucket_by_band(mesh, t, clip, band_count);
    const double edge_size_px = options.edges ? edge_min_size_px(mesh, t, clip) : 0.0;
    tbb::parallel_for(tbb::blocked_range<int>(0, band_count, 1), [&](const tbb::blocked_range<int>& r) {
      for (int b = r.begin(); b != r.end(); ++b) {
        const std::span<const Index> quads(lists.quads.data() + lists.band_start[b],
                                           lists.quads.data() + lists.band_start[b + 1]);
        const int row_first = clip.y0 + b * kBandRows, row_last = std::min(clip.y1, row_first + kBandRows - 1);
        draw_band(image, mesh, cell_values, palette, t, clip, quads, row_first, row_last, edge_size_px);
      }
    });
  }
  if (!options.title.empty())
    draw_text(image, std::max(kMarginPx, (image.width - text_width(options.title)) / 2), (kTitleRows - kTextHeight) / 2,
              options.title, kTextColor);
  if (options.legend) draw_legend(image, options, palette, map_top + map_rows);
  return image;
}

std::string quad_mesh_png(const QuadMesh& mesh, std::span<const double> cell_values,
                          const QuadPictureOptions& options) {
  return encode_png(quad_mesh_image(mesh, cell_values, options));
}

BoundingBox2 parse_view(const std::string& text) {
  const auto fail = [&](const std::string& why) -> InputError {
    return InputError("--view \"" + text + "\": " + why + " (expected x0,y0,x1,y1, e.g. --view 0,0,10,5)");
  };
  std::array<double, 4> v{};
  std::size_t count = 0, start = 0;
  while (true) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    std::string_view field(text.data() + start, comma - start);
    while (!field.empty() && field.front() == ' ') field.remove_prefix(1);
    while (!field.empty() && field.back() == ' ') field.remove_suffix(1);
    if (count == 4) throw fail("more than four numbers");
    if (!field.empty() && field.front() == '+') field.remove_prefix(1);
    const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), v[count]);
    if (field.empty() || error != std::errc() || end != field.data() + field.size())
      throw fail("\"" + std::string(field) + "\" is not a number");
    if (!std::isfinite(v[count])) throw fail("numbers must be finite");
    ++count;
    if (comma == text.size()) break;
    start = comma + 1;
  }
  if (count != 4) throw fail("four numbers needed, got " + std::to_string(count));
  if (!(v[0] < v[2] && v[1] < v[3])) throw fail("needs x0 < x1 and y0 < y1");
  BoundingBox2 box;
  box.extend({v[0], v[1]});
  box.extend({v[2], v[3]});
  return box;
}

std::array<std::uint8_t, 3> viridis_color(double t) { return viridis(t); }

}  // namespace structmesh
