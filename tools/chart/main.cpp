// atmo-chart — draws an error-versus-cost chart (or any y-versus-x scatter
// with one series per group) from a CSV file into a PNG, offscreen, with
// VTK's chart module. See docs/CHART_TOOL.md.
//
// Exit status: 0 written; 1 no OpenGL context or VTK failed to draw;
// 2 bad arguments or input (missing file or column, a value that is not a
// number or cannot go on a log axis, no data rows) or the PNG cannot be written.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "chart_render.h"
#include "series_csv.h"

namespace {

constexpr int kBadInput = 2;

int report(int status, const std::string& message) {
  std::fprintf(stderr, "atmo-chart: %s\n", message.c_str());
  return status;
}

std::string format_g(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

// A value a log axis cannot show, as "file:line: ..." (empty when all are > 0).
std::string check_log_axis(const std::string& path, const std::vector<atmo::chart::Series>& series, bool x_axis,
                           const std::string& column, const char* flag) {
  for (const auto& s : series)
    for (const auto& p : s.points) {
      const double v = x_axis ? p.x : p.y;
      if (!(v > 0.0))
        return path + ":" + std::to_string(p.line) + ": column '" + column + "': " + format_g(v) +
               " cannot go on a logarithmic axis (" + flag + " needs values > 0)";
    }
  return "";
}

int run(int argc, char** argv) {
  CLI::App app{"atmo-chart: draw y versus x from a CSV file as a PNG chart, one line+marker series per group "
               "(offscreen, VTK charts)"};
  std::string csv_path, png_path;
  atmo::chart::ColumnNames columns;
  atmo::chart::ChartOptions chart;
  double hline = 0.0;
  std::string legend = "bottom-right";
  app.add_option("--csv", csv_path, "Input CSV: a header line of column names, then rows; '#' lines are comments")
      ->required();
  app.add_option("--out", png_path, "Output PNG (parent folders are created)")->required();
  app.add_option("--x", columns.x, "Numeric column for the x axis (e.g. cost_ms)")->required();
  app.add_option("--y", columns.y, "Numeric column for the y axis (e.g. psnr_db)")->required();
  app.add_option("--group", columns.group, "Text column: one series (colour, marker, legend entry) per value");
  app.add_option("--label", columns.label, "Text column drawn next to each point");
  app.add_flag("--logx", chart.log_x, "Logarithmic x axis (values must be > 0)");
  app.add_flag("--logy", chart.log_y, "Logarithmic y axis (values must be > 0)");
  app.add_option("--title", chart.title, "Chart title (default: \"Y versus X\")");
  app.add_option("--xlabel", chart.x_title, "x axis title (default: the x column's name)");
  app.add_option("--ylabel", chart.y_title, "y axis title (default: the y column's name)");
  app.add_option("--width", chart.width, "Image width in pixels")->capture_default_str()->check(CLI::Range(200, 8192));
  app.add_option("--height", chart.height, "Image height in pixels")
      ->capture_default_str()
      ->check(CLI::Range(150, 8192));
  CLI::Option* hline_opt = app.add_option("--hline", hline, "Draw a dashed horizontal reference line at this y");
  app.add_option("--hline-label", chart.hline_label, "Legend entry of the reference line (default: \"y = VALUE\")")
      ->needs(hline_opt);
  app.add_option("--legend", legend, "Legend corner inside the plot")
      ->capture_default_str()
      ->check(CLI::IsMember({"top-left", "top-right", "bottom-left", "bottom-right"}));

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int status = app.exit(e);  // prints help or the error
    return status == 0 ? 0 : kBadInput;
  }

  if (*hline_opt) {
    if (!std::isfinite(hline)) return report(kBadInput, "--hline: not a finite number");
    chart.hline = hline;
  }
  static const std::map<std::string, atmo::chart::LegendCorner> corners = {
      {"top-left", atmo::chart::LegendCorner::TopLeft},
      {"top-right", atmo::chart::LegendCorner::TopRight},
      {"bottom-left", atmo::chart::LegendCorner::BottomLeft},
      {"bottom-right", atmo::chart::LegendCorner::BottomRight}};
  chart.legend = corners.at(legend);
  if (chart.x_title.empty()) chart.x_title = columns.x;
  if (chart.y_title.empty()) chart.y_title = columns.y;
  if (chart.title.empty()) chart.title = chart.y_title + " versus " + chart.x_title;

  std::error_code ec;
  if (std::filesystem::is_directory(csv_path, ec)) return report(kBadInput, csv_path + ": cannot open: is a folder");
  if (std::filesystem::path(png_path).filename().empty() || std::filesystem::is_directory(png_path, ec))
    return report(kBadInput, png_path + ": is a folder; --out needs a file name");

  std::vector<atmo::chart::Series> series;
  std::string error;
  if (!atmo::chart::read_series_csv(csv_path, columns, &series, &error)) return report(kBadInput, error);
  if (chart.log_x) {
    error = check_log_axis(csv_path, series, true, columns.x, "--logx");
    if (!error.empty()) return report(kBadInput, error);
  }
  if (chart.log_y) {
    error = check_log_axis(csv_path, series, false, columns.y, "--logy");
    if (!error.empty()) return report(kBadInput, error);
    if (chart.hline && !(*chart.hline > 0.0))
      return report(kBadInput, "--hline " + format_g(*chart.hline) + " cannot go on a logarithmic y axis");
  }

  const std::filesystem::path parent = std::filesystem::path(png_path).parent_path();
  if (!parent.empty()) {
    std::filesystem::create_directories(parent, ec);
    if (ec) return report(kBadInput, png_path + ": cannot create the folder " + parent.string() + ": " + ec.message());
  }

  const int status = atmo::chart::render_chart_png(series, chart, png_path, &error);
  if (status != 0) return report(status, error);
  size_t points = 0;
  for (const auto& s : series) points += s.points.size();
  std::printf("atmo-chart: wrote %s (%dx%d, %zu series, %zu points)\n", png_path.c_str(), chart.width, chart.height,
              series.size(), points);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    return report(1, std::string("unexpected error: ") + e.what());
  }
}
