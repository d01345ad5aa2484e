#include "ephemeris_command.h"

#include <cmath>
#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "core/astro/ephemeris.h"
#include "core/astro/star_catalog.h"

namespace atmo::ephemeris {

namespace astro = atmo::core::astro;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kAuM = 149597870700.0;

int fail(const std::string& message) {
  std::fprintf(stderr, "atmo ephemeris: %s\n", message.c_str());
  return 2;
}

std::string hms(double rad) {
  double h = std::fmod(rad / kDeg / 15.0, 24.0);
  if (h < 0) h += 24.0;
  int hh = static_cast<int>(h);
  int mm = static_cast<int>((h - hh) * 60.0);
  double ss = ((h - hh) * 60.0 - mm) * 60.0;
  if (ss >= 59.995) {  // keep the printed seconds below 60
    ss = 0.0;
    if (++mm == 60) {
      mm = 0;
      hh = (hh + 1) % 24;
    }
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%02dh%02dm%05.2fs", hh, mm, ss);
  return buf;
}

std::string dms(double rad) {
  const double d = std::fabs(rad / kDeg);
  int dd = static_cast<int>(d);
  int mm = static_cast<int>((d - dd) * 60.0);
  double ss = ((d - dd) * 60.0 - mm) * 60.0;
  if (ss >= 59.95) {
    ss = 0.0;
    if (++mm == 60) {
      mm = 0;
      ++dd;
    }
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%c%02d°%02d'%04.1f\"", rad < 0 ? '-' : '+', dd, mm, ss);
  return buf;
}

double deg(double rad) { return rad / kDeg; }

nlohmann::ordered_json vec(const glm::dvec3& v) { return nlohmann::ordered_json::array({v.x, v.y, v.z}); }

nlohmann::ordered_json direction_json(const astro::SkyDirection& d) {
  return {{"azimuth_deg", deg(d.azimuth_rad)},
          {"elevation_deg", deg(d.elevation_rad)},
          {"elevation_refracted_deg", deg(d.elevation_refracted_rad)},
          {"ra_equinox_deg", deg(d.ra_equinox_rad)},
          {"ra_cirs_deg", deg(d.ra_cirs_rad)},
          {"dec_deg", deg(d.dec_rad)},
          {"hour_angle_deg", deg(d.hour_angle_rad)},
          {"direction_enu", vec(d.enu)},
          {"direction_enu_unrefracted", vec(d.enu_unrefracted)}};
}

nlohmann::ordered_json body_json(const astro::BodyEphemeris& b) {
  nlohmann::ordered_json j = {{"name", astro::to_string(b.body)}};
  j.update(direction_json(b.direction));
  j["distance_m"] = b.distance_m;
  j["distance_au"] = b.distance_m / kAuM;
  j["light_time_s"] = b.light_time_s;
  j["magnitude"] = b.apparent_magnitude;
  j["angular_radius_deg"] = deg(b.angular_radius_rad);
  if (b.body != astro::Body::kSun) {
    j["sun_distance_au"] = b.sun_distance_m / kAuM;
    j["illuminated_fraction"] = b.illuminated_fraction;
    j["phase_angle_deg"] = deg(b.phase_angle_rad);
    j["bright_limb_position_angle_deg"] = deg(b.bright_limb_position_angle_rad);
    j["parallactic_angle_deg"] = deg(b.parallactic_angle_rad);
    j["bright_limb_zenith_angle_deg"] = deg(b.bright_limb_zenith_angle_rad);
    j["bright_limb_enu"] = vec(b.bright_limb_enu);
  }
  if (b.body == astro::Body::kSaturn) j["saturn_ring_tilt_deg"] = deg(b.saturn_ring_tilt_rad);
  return j;
}

std::string distance_text(const astro::BodyEphemeris& b) {
  char buf[48];
  if (b.body == astro::Body::kMoon) {
    std::snprintf(buf, sizeof buf, "%.1f km", b.distance_m / 1000.0);
  } else {
    std::snprintf(buf, sizeof buf, "%.6f au", b.distance_m / kAuM);
  }
  return buf;
}

}  // namespace

int run_ephemeris(const Options& o) {
  std::string error;
  // Observer, time, options: every check with a message, exit code 2.
  const auto observer = astro::observer_from_geodetic(o.latitude_deg, o.longitude_deg, o.height_m, &error);
  if (!observer) return fail("--lat/--lon/--height: " + error);
  const auto calendar = astro::parse_iso8601(o.utc, &error);
  if (!calendar) return fail("--utc: " + error);
  astro::TimeScaleOptions time_options;
  time_options.dut1_s = o.dut1_s;
  time_options.delta_t_s = o.delta_t_s;
  const auto time = astro::time_scales_from_utc(*calendar, time_options, &error);
  if (!time) return fail("--utc/--dut1/--delta-t: " + error);

  astro::EphemerisOptions options;
  options.refraction = !o.no_refraction;
  const bool given_conditions = o.pressure_hpa || o.temperature_c;
  if (given_conditions) {
    astro::RefractionConditions c = astro::standard_refraction_conditions(o.height_m);
    if (o.pressure_hpa) c.pressure_hpa = *o.pressure_hpa;
    if (o.temperature_c) c.temperature_c = *o.temperature_c;
    options.conditions = c;
  }
  const auto frame = astro::AstrometryFrame::create(*time, *observer, options, &error);
  if (!frame) return fail("--pressure/--temperature: " + error);

  // The star, if asked for.
  std::optional<astro::CatalogStar> star;
  if (o.star_hd || !o.star_name.empty()) {
    const astro::StarCatalogLoad catalog = astro::load_star_catalog(o.catalog_path);
    if (!catalog.error.empty()) return fail("--catalog: " + catalog.error);
    const astro::CatalogStar* s = o.star_hd ? astro::find_star(catalog.stars, *o.star_hd)
                                            : astro::find_star_by_name(catalog.stars, o.star_name);
    if (!s) {
      return fail(o.star_hd ? "--star: no star HD " + std::to_string(*o.star_hd) + " in " + o.catalog_path
                            : "--star-name: no star named '" + o.star_name + "' in " + o.catalog_path);
    }
    star = *s;
  }

  const auto bodies = frame->bodies();
  const astro::TimeScales& t = frame->time();
  const astro::RefractionConditions& c = frame->conditions();

  if (o.json) {
    nlohmann::ordered_json j;
    j["observer"] = {{"latitude_deg", o.latitude_deg},
                     {"longitude_deg", deg(observer->longitude_rad)},
                     {"height_m", o.height_m},
                     {"ellipsoid", "WGS84"}};
    j["time"] = {{"utc", astro::format_julian_date(t.utc, t.utc_defined) + (t.utc_defined ? "Z" : " UT")},
                 {"tai", astro::format_julian_date(t.tai, false)},
                 {"tt", astro::format_julian_date(t.tt, false)},
                 {"ut1", astro::format_julian_date(t.ut1, false)},
                 {"jd_utc", t.utc.value()},
                 {"jd_tai", t.tai.value()},
                 {"jd_tt", t.tt.value()},
                 {"jd_ut1", t.ut1.value()},
                 {"tai_minus_utc_s", t.tai_minus_utc_s},
                 {"dut1_s", t.dut1_s},
                 {"delta_t_s", t.delta_t_s},
                 {"delta_t_source", astro::to_string(t.delta_t_source)},
                 {"utc_defined", t.utc_defined},
                 {"in_validated_range", t.in_validated_range},
                 {"notes", frame->notes()}};
    j["refraction"] = {{"enabled", frame->refraction_enabled()},
                       {"conditions", given_conditions ? "given" : "standard atmosphere at the observer's height"},
                       {"pressure_hpa", c.pressure_hpa},
                       {"temperature_c", c.temperature_c},
                       {"relative_humidity", c.relative_humidity},
                       {"wavelength_um", c.wavelength_um}};
    j["equation_of_origins_deg"] = deg(frame->equation_of_origins_rad());
    j["bodies"] = nlohmann::ordered_json::array();
    for (const auto& b : bodies) j["bodies"].push_back(body_json(b));
    if (star) {
      nlohmann::ordered_json s = {{"hd", star->hd},        {"name", star->name},         {"bayer", star->bayer},
                          {"v_mag", star->v_mag},  {"b_minus_v", star->b_minus_v},
                          {"parallax_arcsec", star->parallax_arcsec}};
      s.update(direction_json(frame->star(astro::star_astrometry(*star))));
      j["star"] = s;
    }
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }

  // The human table.
  std::printf("Observer  %.6f° %s, %.6f° %s, %.1f m above the WGS84 ellipsoid\n", std::fabs(o.latitude_deg),
              o.latitude_deg < 0 ? "S" : "N", std::fabs(deg(observer->longitude_rad)),
              observer->longitude_rad < 0 ? "W" : "E", o.height_m);
  std::printf("Time      UTC %s%s   TAI %s   TT %s   UT1 %s\n",
              astro::format_julian_date(t.utc, t.utc_defined).c_str(), t.utc_defined ? "" : " (UT)",
              astro::format_julian_date(t.tai, false).c_str(), astro::format_julian_date(t.tt, false).c_str(),
              astro::format_julian_date(t.ut1, false).c_str());
  std::printf("          JD(TT) %.6f   TAI-UTC %.3f s   DUT1 %+.4f s   Delta T = TT-UT1 %.3f s (%s)\n", t.tt.value(),
              t.tai_minus_utc_s, t.dut1_s, t.delta_t_s, astro::to_string(t.delta_t_source));
  if (!frame->notes().empty()) std::printf("Note      %s\n", frame->notes().c_str());
  if (frame->refraction_enabled()) {
    std::printf("Refraction %.1f hPa, %.1f °C, RH %.2f, %.2f µm (%s)\n", c.pressure_hpa, c.temperature_c,
                c.relative_humidity, c.wavelength_um, given_conditions ? "given" : "standard atmosphere");
  } else {
    std::printf("Refraction off (--no-refraction): refracted = geometric elevation\n");
  }
  std::printf("Azimuth from north through east; RA/Dec topocentric apparent, true equator and equinox of date.\n\n");
  std::printf("%-8s %9s %9s %9s %15s %13s %14s %7s %6s %7s %7s %7s\n", "body", "azimuth", "elev", "elev geo",
              "distance", "RA", "Dec", "mag", "illum", "phase", "limb PA", "limb/up");
  for (const auto& b : bodies) {
    const auto& d = b.direction;
    if (b.body == astro::Body::kSun) {
      std::printf("%-8s %8.4f° %8.4f° %8.4f° %15s %13s %14s %7.2f %6s %7s %7s %7s\n", astro::to_string(b.body),
                  deg(d.azimuth_rad), deg(d.elevation_refracted_rad), deg(d.elevation_rad), distance_text(b).c_str(),
                  hms(d.ra_equinox_rad).c_str(), dms(d.dec_rad).c_str(), b.apparent_magnitude, "-", "-", "-", "-");
    } else {
      std::printf("%-8s %8.4f° %8.4f° %8.4f° %15s %13s %14s %7.2f %6.3f %6.2f° %6.1f° %6.1f°\n",
                  astro::to_string(b.body), deg(d.azimuth_rad), deg(d.elevation_refracted_rad), deg(d.elevation_rad),
                  distance_text(b).c_str(), hms(d.ra_equinox_rad).c_str(), dms(d.dec_rad).c_str(),
                  b.apparent_magnitude, b.illuminated_fraction, deg(b.phase_angle_rad),
                  deg(b.bright_limb_position_angle_rad), deg(b.bright_limb_zenith_angle_rad));
    }
  }
  if (star) {
    const astro::SkyDirection d = frame->star(astro::star_astrometry(*star));
    std::string label = star->name.empty() ? (star->bayer.empty() ? "star" : star->bayer) : star->name;
    std::printf("%-8s %8.4f° %8.4f° %8.4f° %15s %13s %14s %7.2f   (HD %u, B-V %.2f)\n", label.c_str(),
                deg(d.azimuth_rad), deg(d.elevation_refracted_rad), deg(d.elevation_rad), "-",
                hms(d.ra_equinox_rad).c_str(), dms(d.dec_rad).c_str(), star->v_mag, star->hd, star->b_minus_v);
  }
  std::printf("\nelev: refracted (as seen), elev geo: unrefracted; limb PA: bright limb from north through east;\n"
              "limb/up: the same from the zenith direction (counterclockwise as seen).\n");
  return 0;
}

}  // namespace atmo::ephemeris
