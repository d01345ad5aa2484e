#include "core/shadows/sphere_occlusion.h"

#include <algorithm>
#include <cmath>

#include "core/shadows/occlusion_twin.h"

namespace atmo::shadows {

const char* exp_method_name(ExpMethod method) {
  switch (method) {
    case ExpMethod::direct_product: return "direct product";
    case ExpMethod::exact: return "exact exp";
    case ExpMethod::optimal_linear: return "optimal linear";
    case ExpMethod::hybrid: return "hybrid";
  }
  return "?";
}

namespace {
constexpr int kLogSamples = 1024;
}

ShOrder::ShOrder(int order) : gamma_(order), ol_(gamma_) {
  log_table_.resize(kLogSamples);
  for (int i = 0; i < kLogSamples; ++i)
    log_table_[i] = i == 0 ? std::vector<double>(order, 0.0)
                           : log_blocker_zh(gamma_, 0.5 * M_PI * i / (kLogSamples - 1));
}

std::vector<double> ShOrder::log_blocker(double theta_rad) const {
  const double x = std::clamp(theta_rad / (0.5 * M_PI), 0.0, 1.0) * (kLogSamples - 1);
  const int i = std::min(static_cast<int>(x), kLogSamples - 2);
  const double t = x - i;
  std::vector<double> r(order());
  for (int l = 0; l < order(); ++l) r[l] = log_table_[i][l] * (1.0 - t) + log_table_[i + 1][l] * t;
  return r;
}

OccludedSky occluded_sky(const ShOrder& order, const std::vector<glm::dvec4>& spheres, const glm::dvec3& n,
                         const std::vector<glm::dvec3>& radiance_sh, ExpMethod method) {
  const int o = order.order(), count = coefficients(o);
  ShVector sum(count, 0.0), product = sh_one(o);
  for (const glm::dvec4& raw : spheres) {
    const glm::vec4 s = twin::atmo_occ_adjust(glm::vec4(raw), glm::vec3(n));
    if (!(s.w > 0.0f)) continue;
    const glm::dvec3 c(s.x, s.y, s.z);
    const double d = glm::length(c);
    const double theta = d > s.w ? std::asin(s.w / d) : 0.5 * M_PI;
    if (method == ExpMethod::direct_product) {
      product = order.gamma().product(product, rotate_zh(blocker_zh(o, theta), c));
    } else {
      const ShVector g = rotate_zh(order.log_blocker(theta), c);
      for (int i = 0; i < count; ++i) sum[i] += g[i];
    }
  }
  ShVector v;
  switch (method) {
    case ExpMethod::direct_product: v = product; break;
    case ExpMethod::exact: v = sh_exp_exact(order.gamma(), sum); break;
    case ExpMethod::optimal_linear: v = sh_exp_optimal_linear(order.optimal_linear(), sum); break;
    case ExpMethod::hybrid: v = sh_exp_hybrid(order.gamma(), order.optimal_linear(), sum); break;
  }
  const ShVector rho = rotate_zh(clamped_cosine_zh(o), n);
  OccludedSky out;
  out.sky_visibility = std::clamp(sh_dot(rho, v), 0.0, 1.0);
  for (int c = 0; c < 3; ++c) {
    ShVector l(count, 0.0);
    for (int i = 0; i < count && i < static_cast<int>(radiance_sh.size()); ++i) l[i] = radiance_sh[i][c];
    const ShVector lr = order.gamma().product(l, rho);  // L * rho: the sky's light on the receiver by direction
    out.open_lux[c] = std::max(0.0, M_PI * sh_dot(l, rho));
    out.sky_lux[c] = std::clamp(M_PI * sh_dot(lr, v), 0.0, out.open_lux[c]);
  }
  return out;
}

}  // namespace atmo::shadows
