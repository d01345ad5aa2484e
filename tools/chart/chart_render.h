// Draws series as an XY chart with VTK's chart module, offscreen, into a PNG.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "series_csv.h"

namespace atmo::chart {

enum class LegendCorner { TopLeft, TopRight, BottomLeft, BottomRight };

struct ChartOptions {
  std::string title, x_title, y_title;
  bool log_x = false, log_y = false;
  int width = 1200, height = 800;
  std::optional<double> hline;  // horizontal reference line at this y
  std::string hline_label;      // its legend entry ("y = <value>" when empty)
  LegendCorner legend = LegendCorner::BottomRight;
};

// Values must already be valid for the axes (positive on a log axis) and no
// series may be empty. Returns the exit status for main: 0 written; 1 no
// OpenGL context (neither headless EGL nor an X display) or VTK reported an
// error while drawing; 2 the PNG could not be written. On failure *error
// holds a message.
int render_chart_png(const std::vector<Series>& series, const ChartOptions& options, const std::string& png_path,
                     std::string* error);

}  // namespace atmo::chart
