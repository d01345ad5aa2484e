// Automatic exposure for scenarios that give none. The knots follow the
// usual photographic tables (sunny 16 = EV 15, sunset ~12, the end of civil
// twilight ~5) and are clamped at 2 at night, which keeps a moonlit landscape
// dark but not black.
#include "atmo_scenario/scenario.h"

#include <cmath>

namespace atmo::scenario {

double auto_exposure_ev100(double elevation_deg) {
  static constexpr int kN = 6;
  static constexpr double kX[kN] = {-10.0, -6.0, -4.0, 0.0, 10.0, 25.0};
  static constexpr double kY[kN] = {2.0, 5.0, 8.0, 12.0, 14.3, 15.0};
  if (std::isnan(elevation_deg)) return kY[kN - 1];
  if (elevation_deg <= kX[0]) return kY[0];
  if (elevation_deg >= kX[kN - 1]) return kY[kN - 1];

  // PCHIP tangents (Fritsch-Carlson / Butland weighted harmonic mean): the
  // curve stays monotone between knots. End tangents are 0 so it joins the
  // flat night and day plateaus with a continuous slope.
  double h[kN - 1], d[kN - 1], m[kN];
  for (int k = 0; k < kN - 1; ++k) {
    h[k] = kX[k + 1] - kX[k];
    d[k] = (kY[k + 1] - kY[k]) / h[k];
  }
  m[0] = m[kN - 1] = 0.0;
  for (int k = 1; k < kN - 1; ++k) {
    if (d[k - 1] * d[k] <= 0.0) {
      m[k] = 0.0;
    } else {
      const double w1 = 2.0 * h[k] + h[k - 1], w2 = h[k] + 2.0 * h[k - 1];
      m[k] = (w1 + w2) / (w1 / d[k - 1] + w2 / d[k]);
    }
  }

  int k = 0;
  while (elevation_deg > kX[k + 1]) ++k;
  const double t = (elevation_deg - kX[k]) / h[k];
  const double t2 = t * t, t3 = t2 * t;
  return (2 * t3 - 3 * t2 + 1) * kY[k] + (t3 - 2 * t2 + t) * h[k] * m[k] +
         (-2 * t3 + 3 * t2) * kY[k + 1] + (t3 - t2) * h[k] * m[k + 1];
}

}  // namespace atmo::scenario
