// Error against wall time, drawn into a vtkImageData (y up, pixel (0,0) at the lower left) and
// written with vtkPNGWriter. Text is rasterised by vtkFreeTypeTools with VTK's embedded fonts,
// which needs no OpenGL context and no font files on the machine.
#include "bench_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <vector>

#include <vtkFreeTypeTools.h>
#include <vtkImageCanvasSource2D.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkSmartPointer.h>
#include <vtkStdString.h>
#include <vtkTextProperty.h>

namespace sphforge::cli {

namespace {

/// Colour-blind-friendly qualitative palette (Okabe-Ito, black last).
constexpr std::array<std::array<int, 3>, 8> kPalette = {{{0, 114, 178},
                                                         {213, 94, 0},
                                                         {0, 158, 115},
                                                         {204, 121, 167},
                                                         {230, 159, 0},
                                                         {86, 180, 233},
                                                         {120, 120, 120},
                                                         {0, 0, 0}}};

enum class HAlign { Left, Centre, Right };
enum class VAlign { Bottom, Centre, Top };

/// A logarithmic axis from 10^lo to 10^hi mapped onto pixels [p0, p1].
struct LogAxis {
  int lo = 0, hi = 1;
  int p0 = 0, p1 = 1;
  double pixel(double value) const {
    const double t = (std::log10(value) - lo) / static_cast<double>(hi - lo);
    return p0 + t * (p1 - p0);
  }
};

/// Whole decades enclosing [min, max] (at least one decade).
LogAxis decades(double min, double max) {
  LogAxis axis;
  if (!(min > 0.0) || !(max > 0.0) || !std::isfinite(min) || !std::isfinite(max)) {
    axis.lo = -1;
    axis.hi = 0;
    return axis;
  }
  // A twentieth of a decade of room, so that no point sits on the frame.
  axis.lo = static_cast<int>(std::floor(std::log10(min) - 0.05));
  axis.hi = static_cast<int>(std::ceil(std::log10(max) + 0.05));
  if (axis.hi <= axis.lo) axis.hi = axis.lo + 1;
  return axis;
}

/// "0.05" for m = 5, k = -2; "5e-7" outside 1e-3 .. 1e3.
std::string tick_label(int m, int k) {
  char buf[32];
  if (k >= -3 && k <= 3) std::snprintf(buf, sizeof buf, "%.*f", k < 0 ? -k : 0, m * std::pow(10.0, k));
  else std::snprintf(buf, sizeof buf, "%de%d", m, k);
  return buf;
}

/// The multiples of each decade that get a label: 1 always; 2 and 5 too on short axes.
std::vector<int> labelled_multiples(const LogAxis& axis) {
  if (axis.hi - axis.lo <= 2) return {1, 2, 5};
  return {1};
}

class Canvas {
 public:
  Canvas(int width, int height) : width_(width), height_(height) {
    canvas_->SetScalarTypeToUnsignedChar();
    canvas_->SetNumberOfScalarComponents(3);
    canvas_->SetExtent(0, width - 1, 0, height - 1, 0, 0);
    colour(255, 255, 255);
    canvas_->FillBox(0, width - 1, 0, height - 1);
  }

  void colour(int r, int g, int b) { canvas_->SetDrawColor(r, g, b); }
  void line(int x0, int y0, int x1, int y1) { canvas_->DrawSegment(x0, y0, x1, y1); }
  void thick_line(int x0, int y0, int x1, int y1, double radius) {
    if (x0 == x1 && y0 == y1) return;
    canvas_->FillTube(x0, y0, x1, y1, radius);
  }
  void box(int x0, int x1, int y0, int y1) { canvas_->FillBox(x0, x1, y0, y1); }
  void triangle(int x0, int y0, int x1, int y1, int x2, int y2) { canvas_->FillTriangle(x0, y0, x1, y1, x2, y2); }

  /// Marker of shape `shape` (square, triangle, diamond, down triangle) centred at (x, y).
  void marker(int shape, int x, int y, int r) {
    switch (shape % 4) {
      case 0: box(x - r, x + r, y - r, y + r); break;
      case 1: triangle(x - r - 1, y - r, x + r + 1, y - r, x, y + r + 1); break;
      case 2:
        triangle(x - r - 1, y, x + r + 1, y, x, y + r + 1);
        triangle(x - r - 1, y, x + r + 1, y, x, y - r - 1);
        break;
      default: triangle(x - r - 1, y + r, x + r + 1, y + r, x, y - r - 1); break;
    }
  }

  /// The image with every drawing so far; text is blended into it afterwards.
  vtkImageData* image() {
    if (!image_) {
      canvas_->Update();
      image_ = canvas_->GetOutput();
    }
    return image_;
  }

  /// Renders `text` with FreeType and alpha-blends it in, anchored at (x, y).
  /// Returns the text's width and height in pixels (0 when nothing could be rendered).
  std::array<int, 2> text(const std::string& text, int x, int y, HAlign h, VAlign v, int size = 14,
                          double orientation = 0.0, bool bold = false, std::array<int, 3> rgb = {0, 0, 0}) {
    if (text.empty()) return {0, 0};
    vtkFreeTypeTools* ft = vtkFreeTypeTools::GetInstance();
    ft->ScaleToPowerTwoOff();
    vtkNew<vtkTextProperty> prop;
    prop->SetFontFamilyToArial();
    prop->SetFontSize(size);
    prop->SetBold(bold);
    prop->SetColor(rgb[0] / 255.0, rgb[1] / 255.0, rgb[2] / 255.0);
    prop->SetOrientation(orientation);
    prop->SetJustificationToLeft();
    prop->SetVerticalJustificationToBottom();
    vtkNew<vtkImageData> glyphs;
    int dims[2] = {0, 0};
    if (!ft->RenderString(prop, vtkStdString(text), 72, glyphs, dims) || dims[0] <= 0 || dims[1] <= 0) return {0, 0};
    const int x0 = h == HAlign::Left ? x : h == HAlign::Centre ? x - dims[0] / 2 : x - dims[0];
    const int y0 = v == VAlign::Bottom ? y : v == VAlign::Centre ? y - dims[1] / 2 : y - dims[1];
    int gext[6];
    glyphs->GetExtent(gext);
    vtkImageData* dst = image();
    auto* out = static_cast<unsigned char*>(dst->GetScalarPointer());
    for (int j = 0; j < dims[1] && gext[2] + j <= gext[3]; ++j)
      for (int i = 0; i < dims[0] && gext[0] + i <= gext[1]; ++i) {
        const int px = x0 + i, py = y0 + j;
        if (px < 0 || py < 0 || px >= width_ || py >= height_) continue;
        const auto* src = static_cast<unsigned char*>(glyphs->GetScalarPointer(gext[0] + i, gext[2] + j, gext[4]));
        const double a = src[3] / 255.0;
        if (a <= 0.0) continue;
        unsigned char* d = out + 3 * (static_cast<std::size_t>(py) * width_ + px);
        for (int c = 0; c < 3; ++c) d[c] = static_cast<unsigned char>(std::lround(d[c] * (1.0 - a) + src[c] * a));
      }
    return {dims[0], dims[1]};
  }

  void write(const std::filesystem::path& file) {
    vtkNew<vtkPNGWriter> writer;
    writer->SetInputData(image());
    writer->SetFileName(file.string().c_str());
    writer->Write();
    if (writer->GetErrorCode() != 0 || !std::filesystem::exists(file))
      throw std::runtime_error("cannot write '" + file.string() + "'");
  }

 private:
  int width_, height_;
  vtkNew<vtkImageCanvasSource2D> canvas_;
  vtkImageData* image_ = nullptr;
};

/// A point the log-log plot can draw: both coordinates positive and finite.
bool drawable(double x, double y) { return x > 0.0 && y > 0.0 && std::isfinite(x) && std::isfinite(y); }

}  // namespace

std::vector<std::optional<std::array<int, 3>>> plot_colours(const std::vector<PlotSeries>& series) {
  std::vector<std::optional<std::array<int, 3>>> colours(series.size());
  std::size_t rank = 0;
  for (std::size_t i = 0; i < series.size(); ++i)
    for (const auto& [x, y] : series[i].points)
      if (drawable(x, y)) {
        const auto& c = kPalette[rank % kPalette.size()];
        colours[i] = std::array<int, 3>{c[0], c[1], c[2]};
        ++rank;
        break;
      }
  return colours;
}

void write_error_plot(const std::filesystem::path& file, const std::vector<PlotSeries>& series,
                      const std::string& title, const std::string& note, int width, int height) {
  // (note may hold several lines separated by '\n')
  // Layout (pixels, y up): axes box, legend to its right, title and note above.
  std::vector<std::string> notes;
  for (std::size_t start = 0; start <= note.size();) {
    const std::size_t nl = note.find('\n', start);
    notes.push_back(note.substr(start, nl == std::string::npos ? std::string::npos : nl - start));
    if (nl == std::string::npos) break;
    start = nl + 1;
  }
  const int left = 90, bottom = 70, right = width - 340, top = height - 50 - 18 * static_cast<int>(notes.size());
  const int legend_x = right + 25;

  double xmin = std::numeric_limits<double>::infinity(), xmax = 0.0;
  double ymin = std::numeric_limits<double>::infinity(), ymax = 0.0;
  bool any = false;
  for (const auto& s : series)
    for (const auto& [x, y] : s.points) {
      if (!drawable(x, y)) continue;
      any = true;
      xmin = std::min(xmin, x);
      xmax = std::max(xmax, x);
      ymin = std::min(ymin, y);
      ymax = std::max(ymax, y);
    }
  LogAxis ax = decades(xmin, xmax), ay = decades(ymin, ymax);
  ax.p0 = left;
  ax.p1 = right;
  ay.p0 = bottom;
  ay.p1 = top;

  Canvas c(width, height);

  // Grid: decades as light lines, 2..9 as fainter ones; ticks on the box.
  for (int k = ax.lo; k <= ax.hi; ++k)
    for (int m = 1; m <= 9; ++m) {
      const double v = m * std::pow(10.0, k);
      if (k == ax.hi && m > 1) break;
      const int px = static_cast<int>(std::lround(ax.pixel(v)));
      c.colour(m == 1 ? 205 : 235, m == 1 ? 205 : 235, m == 1 ? 205 : 235);
      c.line(px, bottom, px, top);
      c.colour(0, 0, 0);
      c.line(px, bottom, px, bottom + (m == 1 ? 8 : 4));
      c.line(px, top, px, top - (m == 1 ? 8 : 4));
    }
  for (int k = ay.lo; k <= ay.hi; ++k)
    for (int m = 1; m <= 9; ++m) {
      const double v = m * std::pow(10.0, k);
      if (k == ay.hi && m > 1) break;
      const int py = static_cast<int>(std::lround(ay.pixel(v)));
      c.colour(m == 1 ? 205 : 235, m == 1 ? 205 : 235, m == 1 ? 205 : 235);
      c.line(left, py, right, py);
      c.colour(0, 0, 0);
      c.line(left, py, left + (m == 1 ? 8 : 4), py);
      c.line(right, py, right - (m == 1 ? 8 : 4), py);
    }
  c.colour(0, 0, 0);
  c.line(left, bottom, right, bottom);
  c.line(left, top, right, top);
  c.line(left, bottom, left, top);
  c.line(right, bottom, right, top);

  // Data: polyline then markers, series by series.
  // Colour and marker go by the rank among the drawn series (plot_colours), not by the index among
  // all: with many metrics not drawn, two drawn ones 8 apart in the list shared a colour and a marker.
  const std::vector<std::optional<std::array<int, 3>>> colours = plot_colours(series);  // none: not drawn
  int rank = 0;
  for (std::size_t i = 0; i < series.size(); ++i) {
    if (!colours[i]) continue;
    std::vector<std::pair<int, int>> px;
    for (const auto& [x, y] : series[i].points)
      if (drawable(x, y))
        px.emplace_back(static_cast<int>(std::lround(ax.pixel(x))), static_cast<int>(std::lround(ay.pixel(y))));
    const std::array<int, 3>& rgb = *colours[i];
    c.colour(rgb[0], rgb[1], rgb[2]);
    for (std::size_t k = 1; k < px.size(); ++k)
      c.thick_line(px[k - 1].first, px[k - 1].second, px[k].first, px[k].second, 1.2);
    for (const auto& [x, y] : px) c.marker(rank, x, y, 4);
    // Legend entry: a line sample with the marker.
    const int ly = top - 12 - 24 * static_cast<int>(i);
    c.thick_line(legend_x, ly, legend_x + 30, ly, 1.2);
    c.marker(rank, legend_x + 15, ly, 4);
    ++rank;
  }

  // Text last: it is blended into the finished drawing.
  for (int k = ax.lo; k <= ax.hi; ++k)
    for (const int m : labelled_multiples(ax)) {
      if (k == ax.hi && m > 1) break;
      c.text(tick_label(m, k), static_cast<int>(std::lround(ax.pixel(m * std::pow(10.0, k)))), bottom - 8,
             HAlign::Centre, VAlign::Top, m == 1 ? 14 : 12);
    }
  for (int k = ay.lo; k <= ay.hi; ++k)
    for (const int m : labelled_multiples(ay)) {
      if (k == ay.hi && m > 1) break;
      c.text(tick_label(m, k), left - 8, static_cast<int>(std::lround(ay.pixel(m * std::pow(10.0, k)))),
             HAlign::Right, VAlign::Centre, m == 1 ? 14 : 12);
    }
  c.text("wall time [s]", (left + right) / 2, 14, HAlign::Centre, VAlign::Bottom, 16);
  c.text("relative error [1]", 22, (bottom + top) / 2, HAlign::Left, VAlign::Centre, 16, 90.0);
  c.text(title, left, height - 12, HAlign::Left, VAlign::Top, 17, 0.0, true);
  for (std::size_t k = 0; k < notes.size(); ++k)
    c.text(notes[k], left, height - 36 - 18 * static_cast<int>(k), HAlign::Left, VAlign::Top, 13, 0.0, false,
           {70, 70, 70});
  for (std::size_t i = 0; i < series.size(); ++i) {
    const int ly = top - 12 - 24 * static_cast<int>(i);
    if (colours[i]) c.text(series[i].name, legend_x + 40, ly, HAlign::Left, VAlign::Centre, 13);
    else c.text(series[i].name, legend_x + 40, ly, HAlign::Left, VAlign::Centre, 13, 0.0, false, {160, 160, 160});
  }
  if (std::find(colours.begin(), colours.end(), std::nullopt) != colours.end())
    c.text("grey: not drawn (no error > 0)", legend_x, top - 12 - 24 * static_cast<int>(series.size()), HAlign::Left,
           VAlign::Centre, 12, 0.0, false, {160, 160, 160});
  if (!any)
    c.text("no positive finite error to plot (see bench.csv)", (left + right) / 2, (bottom + top) / 2, HAlign::Centre,
           VAlign::Centre, 15, 0.0, false, {150, 0, 0});
  c.write(file);
}

}  // namespace sphforge::cli
