#include "chart_render.h"

#include <vtkAxis.h>
#include <vtkBrush.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContext2D.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkLogger.h>
#include <vtkMatrix3x3.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>
#include <vtkPNGWriter.h>
#include <vtkPen.h>
#include <vtkPlotLine.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>
#include <vtkTransform2D.h>
#include <vtkWindowToImageFilter.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <sstream>

#include "atmo_support/headless_gl.h"

namespace atmo::chart {

namespace {

// Prints VTK's messages plainly on stderr and counts the errors, so that a
// failed draw or write turns into an exit status instead of a blank PNG.
class CountingOutputWindow : public vtkOutputWindow {
 public:
  static CountingOutputWindow* New();
  vtkTypeMacro(CountingOutputWindow, vtkOutputWindow);

  void DisplayText(const char* text) override { std::fprintf(stderr, "atmo-chart: VTK: %s\n", tidy(text).c_str()); }
  void DisplayErrorText(const char* text) override {
    ++errors;
    std::fprintf(stderr, "atmo-chart: VTK error: %s\n", tidy(text).c_str());
  }
  void DisplayWarningText(const char* text) override {
    std::fprintf(stderr, "atmo-chart: VTK warning: %s\n", tidy(text).c_str());
  }
  void DisplayGenericWarningText(const char* text) override { DisplayWarningText(text); }
  void DisplayDebugText(const char*) override {}

  // "ERROR: In FILE, line N\nCLASS (PTR): MESSAGE\n\n" -> "CLASS (PTR): MESSAGE [FILE, line N]".
  static std::string tidy(const char* text) {
    std::string t = text ? text : "";
    while (!t.empty() && (t.back() == '\n' || t.back() == ' ')) t.pop_back();
    const size_t nl = t.find('\n');
    if (nl == std::string::npos) return t;
    std::string where = t.substr(0, nl), what = t.substr(nl + 1);
    const size_t in = where.find("In ");
    if (in != std::string::npos) where = where.substr(in + 3);
    for (char& c : what)
      if (c == '\n') c = ' ';
    return what + " [" + where + "]";
  }

  int errors = 0;
};
vtkStandardNewMacro(CountingOutputWindow);

// A line through the points with a marker at each, plus each point's label
// drawn to the upper right of its marker (vtkPlotPoints' IndexedLabels only
// feed tooltips, which a PNG never shows).
class LabeledPlotLine : public vtkPlotLine {
 public:
  static LabeledPlotLine* New();
  vtkTypeMacro(LabeledPlotLine, vtkPlotLine);

  void SetPointLabels(std::vector<Point> points, vtkTextProperty* text) {
    points_ = std::move(points);
    text_ = text;
  }

  bool Paint(vtkContext2D* painter) override {
    // A single point has no line: markers only (vtkPlotLine would refuse it).
    const bool drawn = points_.size() < 2 ? vtkPlotPoints::Paint(painter) : Superclass::Paint(painter);
    if (!drawn) return false;
    if (!this->Visible || !text_) return true;
    // The painter maps plot coordinates to pixels; the offset is in pixels.
    const double* m = painter->GetTransform()->GetMatrix()->GetData();
    const double sx = m[0], sy = m[4];
    if (!(std::abs(sx) > 0.0) || !(std::abs(sy) > 0.0)) return true;
    const double dx = 0.6 * text_->GetFontSize() / sx, dy = 0.35 * text_->GetFontSize() / sy;
    painter->ApplyTextProp(text_);
    for (const Point& p : points_) {
      if (p.label.empty()) continue;
      double px = 0.0, py = 0.0;
      this->TransformDataToScreen(p.x, p.y, px, py);  // log10 and shift/scale, as the plot does
      painter->DrawString(static_cast<float>(px + dx), static_cast<float>(py + dy), p.label.c_str());
    }
    return true;
  }

 private:
  std::vector<Point> points_;
  vtkSmartPointer<vtkTextProperty> text_;
};
vtkStandardNewMacro(LabeledPlotLine);

struct Rgb {
  unsigned char r, g, b;
};
// Tableau 10 without its grey: distinct hues that stay readable on white.
constexpr Rgb kPalette[] = {{31, 119, 180}, {214, 39, 40},  {44, 160, 44},  {255, 127, 14}, {148, 103, 189},
                            {140, 86, 75},  {227, 119, 194}, {23, 190, 207}, {188, 189, 34}};
constexpr int kMarkers[] = {vtkPlotPoints::CIRCLE, vtkPlotPoints::SQUARE, vtkPlotPoints::DIAMOND,
                            vtkPlotPoints::CROSS, vtkPlotPoints::PLUS};
constexpr int kTickFont = 14, kAxisTitleFont = 16, kTitleFont = 20, kLegendFont = 15, kPointLabelFont = 14;

// [lo, hi] of the values, padded, in data units; on a log axis the padding is
// a fraction of the span in decades.
void padded_range(std::vector<double> values, bool log, double pad_lo, double pad_hi, double* lo, double* hi) {
  for (double& v : values) v = log ? std::log10(v) : v;
  double a = *std::min_element(values.begin(), values.end());
  double b = *std::max_element(values.begin(), values.end());
  if (b - a <= 0.0) {
    const double half = log ? 0.5 : std::max(std::abs(a) * 0.1, 1.0);
    a -= half;
    b += half;
  }
  const double span = b - a;
  a -= pad_lo * span;
  b += pad_hi * span;
  *lo = log ? std::pow(10.0, a) : a;
  *hi = log ? std::pow(10.0, b) : b;
}

void style_axis(vtkAxis* axis, const std::string& title, bool log, double lo, double hi) {
  axis->SetTitle(title);
  axis->GetTitleProperties()->SetFontSize(kAxisTitleFont);
  axis->GetTitleProperties()->SetBold(true);
  axis->GetTitleProperties()->SetColor(0.0, 0.0, 0.0);
  axis->GetLabelProperties()->SetFontSize(kTickFont);
  axis->GetLabelProperties()->SetColor(0.1, 0.1, 0.1);
  axis->SetLogScale(log);
  axis->SetBehavior(vtkAxis::FIXED);
  axis->SetUnscaledRange(lo, hi);
}

vtkSmartPointer<vtkTable> xy_table(const std::vector<double>& xs, const std::vector<double>& ys) {
  vtkNew<vtkDoubleArray> x, y;
  x->SetName("x");
  y->SetName("y");
  for (size_t i = 0; i < xs.size(); ++i) {
    x->InsertNextValue(xs[i]);
    y->InsertNextValue(ys[i]);
  }
  auto table = vtkSmartPointer<vtkTable>::New();
  table->AddColumn(x);
  table->AddColumn(y);
  return table;
}

std::string format_value(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

int render_chart_png(const std::vector<Series>& series, const ChartOptions& options, const std::string& png_path,
                     std::string* error) {
  auto fail = [&](int status, const std::string& msg) {
    if (error) *error = msg;
    return status;
  };
  // VTK's messages go through CountingOutputWindow only (not also vtkLogger).
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
  vtkNew<CountingOutputWindow> messages;
  vtkOutputWindow::SetInstance(messages);

  // The GL context outlives every VTK object below (declared first, destroyed
  // last): VTK frees its GL resources when they are destroyed.
  std::string egl_error;
  std::unique_ptr<support::HeadlessGl> gl =
      support::HeadlessGl::create(support::HeadlessGl::Profile::Core, &egl_error);
  vtkSmartPointer<vtkRenderWindow> window;
  if (gl) {
    // Debian's VTK 9.1 has neither EGL nor OSMesa render windows, only X; so
    // VTK draws into our headless EGL context as into a host's context (see
    // glew_egl_shim.cpp for the one GLEW detail that needs).
    auto generic = vtkSmartPointer<vtkGenericOpenGLRenderWindow>::New();
    generic->SetOwnContext(0);
    generic->SetIsCurrent(true);
    generic->SetReadyForRendering(true);
    generic->SetFrameBlitModeToNoBlit();  // no default framebuffer: the image is read from VTK's own
    window = generic;
  } else {
    const char* display = std::getenv("DISPLAY");
    if (!display || !*display)
      return fail(1, "no OpenGL context: " + egl_error +
                         "\nand no X display to fall back on (DISPLAY is unset; xvfb-run would provide one)");
    std::fprintf(stderr, "atmo-chart: headless EGL failed (%s); using the X display %s\n", egl_error.c_str(),
                 display);
    window = vtkSmartPointer<vtkRenderWindow>::New();  // vtkXOpenGLRenderWindow
  }
  window->SetOffScreenRendering(1);
  window->SetSize(options.width, options.height);
  window->SetMultiSamples(8);

  vtkNew<vtkContextView> view;
  view->SetRenderWindow(window);
  view->GetRenderer()->SetBackground(1.0, 1.0, 1.0);

  vtkNew<vtkChartXY> chart;
  view->GetScene()->AddItem(chart);
  chart->SetTitle(options.title);
  chart->GetTitleProperties()->SetFontSize(kTitleFont);
  chart->GetTitleProperties()->SetBold(true);
  chart->GetTitleProperties()->SetColor(0.0, 0.0, 0.0);

  // Fixed ranges with room around the points (and to their right for labels).
  bool any_label = false;
  std::vector<double> all_x, all_y;
  for (const Series& s : series)
    for (const Point& p : s.points) {
      all_x.push_back(p.x);
      all_y.push_back(p.y);
      any_label = any_label || !p.label.empty();
    }
  if (options.hline) all_y.push_back(*options.hline);
  double x_lo, x_hi, y_lo, y_hi;
  padded_range(all_x, options.log_x, 0.05, any_label ? 0.12 : 0.05, &x_lo, &x_hi);
  padded_range(all_y, options.log_y, 0.08, 0.10, &y_lo, &y_hi);
  style_axis(chart->GetAxis(vtkAxis::BOTTOM), options.x_title, options.log_x, x_lo, x_hi);
  style_axis(chart->GetAxis(vtkAxis::LEFT), options.y_title, options.log_y, y_lo, y_hi);

  // The reference line first, so that the series are drawn over it.
  if (options.hline) {
    vtkPlot* line = chart->AddPlot(vtkChart::LINE);
    line->SetInputData(xy_table({x_lo, x_hi}, {*options.hline, *options.hline}), "x", "y");
    line->SetColor(90, 90, 90, 255);
    line->SetWidth(2.0f);
    line->GetPen()->SetLineType(vtkPen::DASH_LINE);
    line->SetLabel(options.hline_label.empty() ? "y = " + format_value(*options.hline) : options.hline_label);
  }

  for (size_t i = 0; i < series.size(); ++i) {
    const Series& s = series[i];
    const Rgb c = kPalette[i % (sizeof kPalette / sizeof kPalette[0])];
    std::vector<double> xs, ys;
    for (const Point& p : s.points) {
      xs.push_back(p.x);
      ys.push_back(p.y);
    }
    vtkNew<LabeledPlotLine> plot;
    plot->SetInputData(xy_table(xs, ys), "x", "y");
    plot->SetColor(c.r, c.g, c.b, 255);
    plot->SetWidth(2.5f);
    plot->SetMarkerStyle(kMarkers[i % (sizeof kMarkers / sizeof kMarkers[0])]);
    plot->SetMarkerSize(11.0f);
    plot->SetLabel(s.name.empty() ? (series.size() == 1 ? options.y_title : std::string("(none)")) : s.name);
    vtkNew<vtkTextProperty> text;
    text->SetFontSize(kPointLabelFont);
    text->SetColor(c.r / 255.0 * 0.8, c.g / 255.0 * 0.8, c.b / 255.0 * 0.8);
    text->SetJustificationToLeft();
    text->SetVerticalJustificationToBottom();
    plot->SetPointLabels(s.points, text);
    chart->AddPlot(plot);
  }

  chart->SetShowLegend(true);
  vtkChartLegend* legend = chart->GetLegend();
  legend->GetLabelProperties()->SetFontSize(kLegendFont);
  legend->GetLabelProperties()->SetColor(0.0, 0.0, 0.0);
  legend->GetBrush()->SetColor(255, 255, 255, 235);
  legend->GetPen()->SetColor(160, 160, 160, 255);
  const bool left = options.legend == LegendCorner::TopLeft || options.legend == LegendCorner::BottomLeft;
  const bool top = options.legend == LegendCorner::TopLeft || options.legend == LegendCorner::TopRight;
  legend->SetHorizontalAlignment(left ? vtkChartLegend::LEFT : vtkChartLegend::RIGHT);
  legend->SetVerticalAlignment(top ? vtkChartLegend::TOP : vtkChartLegend::BOTTOM);

  window->Render();
  if (messages->errors > 0)
    return fail(1, "VTK reported " + std::to_string(messages->errors) + " error(s) while drawing (above)");

  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(png_path.c_str());
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
  if (writer->GetErrorCode() != 0 || messages->errors > 0)
    return fail(2, png_path + ": cannot write the PNG (see VTK's message above)");
  return 0;
}

}  // namespace atmo::chart
