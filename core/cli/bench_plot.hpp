// The plot of `sphforge bench`: relative error (log y) against wall time (log x), one polyline
// with markers per metric, drawn with VTK into an image (vtkImageCanvasSource2D, text through
// FreeType, no OpenGL context) and written as PNG.
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sphforge::cli {

struct PlotSeries {
  std::string name;                              ///< legend text (the metric)
  std::vector<std::pair<double, double>> points; ///< (wall time [s], relative error [1]); non-positive values are skipped
};

/// The colour (RGB 0..255) of every series as the plot draws it, also reported in bench.json: the
/// series with a point to draw (both coordinates positive and finite) take the palette in turn, the
/// others none (their legend entry is grey).
std::vector<std::optional<std::array<int, 3>>> plot_colours(const std::vector<PlotSeries>& series);

/// Draws the series and writes `file` (PNG, width x height pixels). `title` goes above the axes;
/// `note` (e.g. what the error is measured against; lines separated by '\n') below the title. Throws std::runtime_error
/// when the file cannot be written.
void write_error_plot(const std::filesystem::path& file, const std::vector<PlotSeries>& series,
                      const std::string& title, const std::string& note, int width = 1100, int height = 680);

}  // namespace sphforge::cli
