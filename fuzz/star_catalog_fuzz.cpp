// star_catalog_fuzz.cpp — the star catalogue parser (core/astro/star_catalog)
// on any bytes. Contract (star_catalog.h): no crash, no exception; either
// stars and no error, or an error and no stars; every star's fields finite.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/astro/star_catalog.h"
#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const atmo::core::astro::StarCatalogLoad load = atmo::core::astro::parse_star_catalog(text, "fuzz.tsv");
  FUZZ_CHECK(load.error.empty() || load.stars.empty(), "on error, no stars");
  for (const atmo::core::astro::CatalogStar& s : load.stars) {
    FUZZ_CHECK(std::isfinite(s.ra_rad) && std::isfinite(s.dec_rad) && std::isfinite(s.pm_ra_rad_per_year) &&
                   std::isfinite(s.pm_dec_rad_per_year) && std::isfinite(s.parallax_arcsec) &&
                   std::isfinite(s.v_mag) && std::isfinite(s.b_minus_v),
               "a star's numbers are finite");
    (void)atmo::core::astro::find_star(load.stars, s.hd);
  }
  return 0;
}
