#include "core/shadows/occlusion_tables.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>

namespace atmo::shadows {

namespace {
std::vector<double> scaled(const std::vector<double>& zh) {  // zh_l * sqrt(4 pi / (2l + 1))
  std::vector<double> k(zh.size());
  for (size_t l = 0; l < zh.size(); ++l) k[l] = zh[l] * std::sqrt(4.0 * M_PI / (2.0 * l + 1.0));
  return k;
}
}  // namespace

const TripleProduct& include_triple_product() {
  static const TripleProduct gamma(kIncludeOrder);
  return gamma;
}

const OptimalLinearTable& include_optimal_linear() {
  static const OptimalLinearTable table(include_triple_product(), OcclusionTables::kSize);
  return table;
}

std::vector<double> form_factor_zh(int order, double theta_rad) {
  // A patch at angle alpha from the axis towards p (sphere of radius s = sin theta, p at distance 1):
  // visible where cos alpha > s; it subtends cos gamma dA / |v|^2 with |v|^2 = 1 - 2 s cos alpha + s^2 and
  // cos gamma = (cos alpha - s) / |v|. Midpoint rule in cos alpha over the visible range.
  // At 90 degrees the visible patch shrinks to the point nearest p: the limit of s -> 1 (kept off 1).
  const double s = std::min(std::sin(std::clamp(theta_rad, 0.0, 0.5 * M_PI)), 0.999);
  std::vector<double> zh(order, 0.0);
  double total = 0.0;
  const int steps = 4000;
  for (int k = 0; k < steps; ++k) {
    const double mu = s + (1.0 - s) * (k + 0.5) / steps;  // cos alpha
    const double v2 = 1.0 - 2.0 * s * mu + s * s;
    const double w = (mu - s) / (v2 * std::sqrt(v2));
    const ShVector y = sh_basis(order, {std::sqrt(std::max(0.0, 1.0 - mu * mu)), 0.0, mu});
    for (int l = 0; l < order; ++l) zh[l] += w * y[l * (l + 1)];
    total += w;
  }
  // The weight's integral over the sphere of normals is 2 pi total dmu; normalise it to 1.
  const double dmu = (1.0 - s) / steps;
  for (int l = 0; l < order; ++l) zh[l] = 2.0 * M_PI * zh[l] * dmu / (2.0 * M_PI * total * dmu);
  return zh;
}

const OcclusionTables& occlusion_tables() {
  static std::once_flag once;
  static OcclusionTables tables;
  std::call_once(once, [] {
    const TripleProduct& gamma = include_triple_product();
    const OptimalLinearTable& ol = include_optimal_linear();
    const int n = OcclusionTables::kSize;
    tables.texels.resize(static_cast<size_t>(n) * OcclusionTables::kRows);
    tables.ol_max_magnitude = static_cast<float>(ol.max_magnitude());
    for (int i = 0; i < n; ++i) {
      const double theta = 0.5 * M_PI * i / (n - 1);
      const std::vector<double> g = scaled(i == 0 ? std::vector<double>(kIncludeOrder, 0.0) : log_blocker_zh(gamma, theta));
      const std::vector<double> f = scaled(form_factor_zh(kIncludeOrder, theta));
      tables.texels[OcclusionTables::kLogCap * n + i] = glm::vec4(g[0], g[1], g[2], g[3]);
      tables.texels[OcclusionTables::kFormFactor * n + i] = glm::vec4(f[0], f[1], f[2], f[3]);
      const glm::dvec2 ab = ol.table()[i];
      tables.texels[OcclusionTables::kOptimalLinear * n + i] = glm::vec4(ab.x, ab.y, 0.0, 0.0);
    }
  });
  return tables;
}

std::string sh_square_glsl(const TripleProduct& gamma) {
  static const char* kSlot[16] = {"a.x", "a.y", "a.z", "a.w", "b.x", "b.y", "b.z", "b.w",
                                  "c.x", "c.y", "c.z", "c.w", "d.x", "d.y", "d.z", "d.w"};
  std::vector<double> coef(16 * 16 * 16, 0.0);  // i, j <= k: Gamma_ijk (2x off the diagonal)
  for (const TripleProduct::Entry& e : gamma.entries())
    if (e.j <= e.k) coef[(e.i * 16 + e.j) * 16 + e.k] = e.value * (e.j == e.k ? 1.0 : 2.0);
  std::string out = "  AtmoOccSh r;\n";
  char buf[128];
  for (int i = 0; i < 16; ++i) {
    out += std::string("  r.") + kSlot[i] + " =";
    bool first = true;
    for (int j = 0; j < 16; ++j)
      for (int k = j; k < 16; ++k) {
        const double c = coef[(i * 16 + j) * 16 + k];
        if (c == 0.0) continue;
        std::snprintf(buf, sizeof buf, "%s %.9ff * g.%s * g.%s", first ? "" : (c < 0 ? " -" : " +"),
                      first ? c : std::abs(c), kSlot[j], kSlot[k]);
        out += buf;
        first = false;
      }
    if (first) out += " 0.0f";
    out += ";\n";
  }
  out += "  return r;\n";
  return out;
}

SkyTransfer make_sky_transfer(const std::vector<glm::dvec3>& radiance_sh16, const glm::dvec3& sun_direction_enu,
                              const glm::dvec3& sun_illuminance_lux) {
  const TripleProduct& gamma = include_triple_product();
  SkyTransfer out;
  const double cosine[3] = {M_PI, 2.0 * M_PI / 3.0, M_PI / 4.0};  // irradiance from radiance, bands 0..2
  for (int c = 0; c < 3; ++c) {
    ShVector l(16, 0.0);
    for (int i = 0; i < 16 && i < static_cast<int>(radiance_sh16.size()); ++i) l[i] = radiance_sh16[i][c];
    const std::vector<double> m = gamma.product_matrix(l);  // symmetric 16 x 16; E = pi (L * rho) . V
    for (int k = 0; k < 9; ++k)
      for (int i = 0; i < 16; ++i) out.transfer[(c * 9 + k) * 16 + i] = static_cast<float>(M_PI * m[i * 16 + k]);
    for (int k = 0; k < 9; ++k) out.sky_sh9[k * 3 + c] = static_cast<float>(l[k] * cosine[band_of(k)]);
  }
  // The Sun on an occluder's surface: E max(0, n . s) as SH9 (the clamped cosine's ZH times pi).
  const std::vector<double> zh = clamped_cosine_zh(3);
  const ShVector sun = rotate_zh(zh, sun_direction_enu);
  for (int k = 0; k < 9; ++k)
    for (int c = 0; c < 3; ++c)
      out.sun_sh9[k * 3 + c] = static_cast<float>(M_PI * sun[k] * sun_illuminance_lux[c]);
  return out;
}

}  // namespace atmo::shadows
