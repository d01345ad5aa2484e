#include "core/spectral/colorimetry.h"

#include <algorithm>
#include <stdexcept>

namespace atmo::spectral {

namespace detail {
extern const double kCie1931Table[][4];
extern const int kCie1931TableRows;
extern const double kCieD65Table[][2];
extern const int kCieD65TableRows;
}  // namespace detail

const std::vector<CmfSample>& cie1931_2deg_5nm() {
  static const std::vector<CmfSample> table = [] {
    std::vector<CmfSample> t;
    for (int i = 0; i < detail::kCie1931TableRows; ++i) {
      const double* r = detail::kCie1931Table[i];
      t.push_back({r[0], r[1], r[2], r[3]});
    }
    return t;
  }();
  return table;
}

const std::vector<SpdSample>& cie_d65_5nm() {
  static const std::vector<SpdSample> table = [] {
    std::vector<SpdSample> t;
    for (int i = 0; i < detail::kCieD65TableRows; ++i) t.push_back({detail::kCieD65Table[i][0], detail::kCieD65Table[i][1]});
    return t;
  }();
  return table;
}

namespace {
// Both tables are on a uniform 5 nm grid; find the bracketing rows.
template <typename Row, typename F>
auto interpolate(const std::vector<Row>& t, double w, F value) -> decltype(value(t[0])) {
  using V = decltype(value(t[0]));
  if (t.empty() || w < t.front().wavelength_nm || w > t.back().wavelength_nm) return V(0.0);
  const double step = t[1].wavelength_nm - t[0].wavelength_nm;
  const double f = (w - t.front().wavelength_nm) / step;
  const size_t i = std::min(static_cast<size_t>(f), t.size() - 2);
  const double a = f - static_cast<double>(i);
  return value(t[i]) * (1.0 - a) + value(t[i + 1]) * a;
}
}  // namespace

glm::dvec3 cie1931_2deg(double w) {
  return interpolate(cie1931_2deg_5nm(), w, [](const CmfSample& s) { return glm::dvec3(s.x, s.y, s.z); });
}

double cie_d65(double w) {
  return interpolate(cie_d65_5nm(), w, [](const SpdSample& s) { return s.value; });
}

glm::dmat3 linear_srgb_from_xyz() {
  auto xyz_of = [](double x, double y) { return glm::dvec3(x / y, 1.0, (1.0 - x - y) / y); };
  // Columns: the primaries' XYZ up to a scale each, fixed so that RGB (1,1,1) is the white with Y = 1.
  glm::dmat3 primaries(xyz_of(0.64, 0.33), xyz_of(0.30, 0.60), xyz_of(0.15, 0.06));
  glm::dvec3 scale = glm::inverse(primaries) * xyz_of(0.3127, 0.3290);
  glm::dmat3 xyz_from_rgb(primaries[0] * scale.x, primaries[1] * scale.y, primaries[2] * scale.z);
  return glm::inverse(xyz_from_rgb);
}

SpectrumToColor::SpectrumToColor(const std::vector<double>& wavelengths_nm)
    : wavelengths_(wavelengths_nm), weights_(wavelengths_nm.size(), glm::dvec3(0.0)) {
  const size_t n = wavelengths_.size();
  if (n == 0) return;
  for (size_t i = 1; i < n; ++i)
    if (!(wavelengths_[i] > wavelengths_[i - 1])) throw std::invalid_argument("SpectrumToColor: wavelengths must increase");
  // Hat function of sample i evaluated at w (flat beyond the ends of the grid).
  auto hat = [&](size_t i, double w) {
    if (n == 1) return 1.0;
    if (w <= wavelengths_.front()) return i == 0 ? 1.0 : 0.0;
    if (w >= wavelengths_.back()) return i == n - 1 ? 1.0 : 0.0;
    if (i > 0 && w >= wavelengths_[i - 1] && w <= wavelengths_[i])
      return (w - wavelengths_[i - 1]) / (wavelengths_[i] - wavelengths_[i - 1]);
    if (i + 1 < n && w >= wavelengths_[i] && w <= wavelengths_[i + 1])
      return (wavelengths_[i + 1] - w) / (wavelengths_[i + 1] - wavelengths_[i]);
    return 0.0;
  };
  // Midpoint rule in 1 nm sub-steps over the CMF range: the CMF table is
  // itself piecewise linear at 5 nm, so 1 nm is converged to ~1e-4.
  const double lo = cie1931_2deg_5nm().front().wavelength_nm, hi = cie1931_2deg_5nm().back().wavelength_nm;
  const int sub = static_cast<int>(hi - lo);
  for (int s = 0; s < sub; ++s) {
    const double w = lo + s + 0.5;
    const glm::dvec3 cmf = cie1931_2deg(w);
    for (size_t i = 0; i < n; ++i) {
      const double h = hat(i, w);
      if (h != 0.0) weights_[i] += cmf * h;
    }
  }
}

glm::dvec3 SpectrumToColor::xyz(const std::vector<double>& values) const {
  if (values.size() != weights_.size()) throw std::invalid_argument("SpectrumToColor: wrong number of samples");
  glm::dvec3 sum(0.0);
  for (size_t i = 0; i < values.size(); ++i) sum += weights_[i] * values[i];
  return sum;
}

double SpectrumToColor::luminance(const std::vector<double>& values) const {
  return kMaxLuminousEfficacy * xyz(values).y;
}

glm::dvec3 SpectrumToColor::linear_srgb(const std::vector<double>& values) const {
  return kMaxLuminousEfficacy * (linear_srgb_from_xyz() * xyz(values));
}

}  // namespace atmo::spectral
