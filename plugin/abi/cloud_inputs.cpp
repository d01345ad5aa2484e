#include "abi/cloud_inputs.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <optional>
#include <thread>

#include "abi/objects.h"
#include "abi/scene_inputs.h"
#include "abi/struct_io.h"
#include "abi/vdb_module_client.h"
#include "core/atmosphere/shader_twin.h"
#include "core/clouds/field_light.h"
#include "core/clouds/parallel_bands.h"
#include "core/clouds/procedural_clouds.h"
#include "core/scene/scene.h"

namespace atmo::abi {

namespace {

// The draft's hemispherical depths: half the directions (a draft is blurred anyway).
constexpr int kDraftAmbientDirections = clouds::kAmbientDirections / 2;
// The threads a build that the host waits for shares (a worker's build takes one, niced).
int waiting_threads() { return static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 4u)); }

// The streamed set-up's decks: first with this many times fewer voxels along each axis.
constexpr int kCoarseDeckFactor = 2;

std::string layer_name(uint32_t i) { return "AtmoCloudsState.layers[" + std::to_string(i) + "]"; }

bool finite_all(const double* v, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

Verdict bad(AtmoResult code, const std::string& what) { return Verdict{code, what}; }

// Range checks of one layer (its header already read).
Verdict validate_layer(const AtmoCloudLayer& l, const std::string& where) {
  if (l.type >= ATMO_CLOUD_LAYER_TYPE_COUNT)
    return bad(ATMO_ERROR_INVALID_ARGUMENT, where + ".type = " + std::to_string(l.type) + " is not an AtmoCloudLayerType");
  const double numbers[] = {l.base_m, l.top_m, l.area_centre_enu_m[0], l.area_centre_enu_m[1], l.area_size_m,
                            l.position_enu_m[0], l.position_enu_m[1], l.position_enu_m[2], l.rotation_deg[0],
                            l.rotation_deg[1], l.rotation_deg[2], l.metres_per_unit, l.density_scale,
                            l.extinction_per_m, l.droplet_diameter_um};
  if (!finite_all(numbers, 15)) return bad(ATMO_ERROR_NON_FINITE_VALUE, where + " holds a NaN or infinite number");
  if (l.extinction_per_m < 0.0 || l.extinction_per_m > 1.0)
    return bad(ATMO_ERROR_OUT_OF_RANGE, where + ".extinction_per_m = " + std::to_string(l.extinction_per_m) +
                                            " is outside (0, 1] (0: default)");
  if (l.droplet_diameter_um != 0.0 && (l.droplet_diameter_um < 5.0 || l.droplet_diameter_um > 50.0))
    return bad(ATMO_ERROR_OUT_OF_RANGE, where + ".droplet_diameter_um = " + std::to_string(l.droplet_diameter_um) +
                                            " is outside [5, 50] (0: default)");
  if (l.type == ATMO_CLOUD_VDB_FILE) {
    if (!l.vdb_path || !*l.vdb_path) return bad(ATMO_ERROR_INVALID_ARGUMENT, where + ".vdb_path is NULL or empty");
    if (l.metres_per_unit < 0.0 || l.density_scale < 0.0)
      return bad(ATMO_ERROR_OUT_OF_RANGE, where + ".metres_per_unit and density_scale must be >= 0 (0: default 1)");
    if (l.rotation_deg[1] != 0.0 || l.rotation_deg[2] != 0.0)
      return bad(ATMO_ERROR_OUT_OF_RANGE, where + ".rotation_deg: only heading is supported yet (pitch, roll 0)");
    return {};
  }
  if (l.coverage_oktas < 0 || l.coverage_oktas > 8)
    return bad(ATMO_ERROR_OUT_OF_RANGE, where + ".coverage_oktas = " + std::to_string(l.coverage_oktas) +
                                            " is outside [0, 8]");
  if (l.base_m < 0.0 || l.top_m > 20000.0 || !(l.top_m > l.base_m))
    return bad(ATMO_ERROR_OUT_OF_RANGE, where + ": base_m " + std::to_string(l.base_m) + ", top_m " +
                                            std::to_string(l.top_m) + ": need 0 <= base_m < top_m <= 20000");
  if (l.area_size_m != 0.0 && (l.area_size_m < 500.0 || l.area_size_m > 400000.0))
    return bad(ATMO_ERROR_OUT_OF_RANGE, where + ".area_size_m = " + std::to_string(l.area_size_m) +
                                            " is outside [500, 400000] (0: default 20000)");
  return {};
}

clouds::CloudLayerType procedural_type(uint32_t t) {
  switch (t) {
    case ATMO_CLOUD_STRATUS: return clouds::CloudLayerType::Stratus;
    case ATMO_CLOUD_OVERCAST: return clouds::CloudLayerType::Overcast;
    case ATMO_CLOUD_CIRRUS: return clouds::CloudLayerType::Cirrus;
    default: return clouds::CloudLayerType::Cumulus;
  }
}

void apply_optics(const AtmoCloudLayer& l, clouds::CloudVolume* v) {
  if (l.extinction_per_m > 0.0) v->optics.extinction_per_m = static_cast<float>(l.extinction_per_m);
  if (l.droplet_diameter_um > 0.0) v->optics.droplet_diameter_um = static_cast<float>(l.droplet_diameter_um);
}

// Appends a field's prototypes and instances to *out.
void append_field(clouds::CloudField&& f, clouds::CloudField* out) {
  const int base = static_cast<int>(out->prototypes.size());
  for (clouds::CloudVolume& v : f.prototypes) out->prototypes.push_back(std::move(v));
  for (clouds::CloudInstance i : f.instances) {
    i.prototype += base;
    out->instances.push_back(i);
  }
}

}  // namespace

Verdict build_clouds(const AtmoCloudsState& s, const AtmoContext_T& ctx, ContextClouds* out,
                     std::vector<std::string>* load_errors) {
  if (!finite_all(s.origin_geodetic, 3) || !std::isfinite(s.march_step_voxels) ||
      !std::isfinite(s.light_update_threshold_deg) || !std::isfinite(s.impostor_angle_threshold_deg) ||
      !std::isfinite(s.direct_march_radii) || !std::isfinite(s.impostor_max_pixels_per_texel))
    return bad(ATMO_ERROR_NON_FINITE_VALUE, "AtmoCloudsState holds a NaN or infinite number");
  if (std::abs(s.origin_geodetic[0]) > 90.0)
    return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoCloudsState.origin_geodetic latitude " +
                                            std::to_string(s.origin_geodetic[0]) + " is outside [-90, 90]");
  if (s.layer_count > 0 && !s.layers) return bad(ATMO_ERROR_INVALID_ARGUMENT, "AtmoCloudsState.layers is NULL");
  if (s.layer_count > 64) return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoCloudsState.layer_count > 64");
  if (s.march_resolution_divisor > 8 || (s.march_step_voxels != 0.0 && (s.march_step_voxels < 0.25 || s.march_step_voxels > 8.0)) ||
      s.multiple_scattering_octaves > 8 || s.light_update_threshold_deg < 0.0 || s.light_update_threshold_deg > 30.0)
    return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoCloudsState quality knobs: march_resolution_divisor [1, 8], "
                                        "march_step_voxels [0.25, 8], multiple_scattering_octaves [1, 8], "
                                        "light_update_threshold_deg [0, 30] (0: defaults)");
  if (s.draw_mode >= ATMO_CLOUD_DRAW_MODE_COUNT)
    return bad(ATMO_ERROR_INVALID_ARGUMENT, "AtmoCloudsState.draw_mode = " + std::to_string(s.draw_mode) +
                                                " is not an AtmoCloudDrawMode");
  if (s.setup >= ATMO_CLOUD_SETUP_COUNT)
    return bad(ATMO_ERROR_INVALID_ARGUMENT,
               "AtmoCloudsState.setup = " + std::to_string(s.setup) + " is not an AtmoCloudSetup");
  if ((s.impostor_texels != 0 && (s.impostor_texels < 16 || s.impostor_texels > 512)) ||
      (s.impostor_angle_threshold_deg != 0.0 &&
       (s.impostor_angle_threshold_deg < 0.05 || s.impostor_angle_threshold_deg > 10.0)) ||
      s.impostor_updates_per_frame > 4096 ||
      (s.direct_march_radii != 0.0 && (s.direct_march_radii < 1.0 || s.direct_march_radii > 100.0)) ||
      (s.impostor_max_pixels_per_texel != 0.0 &&
       (s.impostor_max_pixels_per_texel < 0.25 || s.impostor_max_pixels_per_texel > 8.0)))
    return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoCloudsState impostor knobs: impostor_texels [16, 512], "
                                        "impostor_angle_threshold_deg [0.05, 10], impostor_updates_per_frame "
                                        "[1, 4096], direct_march_radii [1, 100], impostor_max_pixels_per_texel "
                                        "[0.25, 8] (0: defaults)");
  // Read and validate every layer before building any.
  uint32_t stride = 0;
  if (s.layer_count > 0) {
    const ReadError e = array_stride<AtmoCloudLayer>(s.layer_size, "AtmoCloudsState.layer_size", &stride);
    if (e.code) return bad(e.code, e.message);
  }
  std::vector<AtmoCloudLayer> layers(s.layer_count);
  const char* bytes = reinterpret_cast<const char*>(s.layers);
  for (uint32_t i = 0; i < s.layer_count; ++i) {
    const char* element = bytes + static_cast<size_t>(stride) * i;
    AtmoStructHeader h;
    std::memcpy(&h, element, sizeof(h));
    if (h.struct_size > stride)  // the plugin reads no byte past the element
      return bad(ATMO_ERROR_OUT_OF_RANGE, layer_name(i) + ".header.struct_size = " + std::to_string(h.struct_size) +
                                              " is larger than AtmoCloudsState.layer_size (" + std::to_string(stride) +
                                              ")");
    ReadError e = read_struct(element, ATMO_TYPE_CLOUD_LAYER, layer_name(i).c_str(), &layers[i]);
    if (e.code) return bad(e.code, e.message);
    Verdict v = validate_layer(layers[i], layer_name(i));
    if (!v.ok()) return v;
  }
  ContextClouds c;
  c.origin = core::Geodetic{s.origin_geodetic[0], s.origin_geodetic[1], s.origin_geodetic[2]};
  c.origin_ecef_m = core::ecef_from_geodetic(c.origin);
  c.ecef_from_enu = core::ecef_from_enu(c.origin.latitude_deg, c.origin.longitude_deg);
  if (s.march_resolution_divisor) c.settings.march_divisor = static_cast<int>(s.march_resolution_divisor);
  if (s.march_step_voxels > 0.0) c.settings.march_step_voxels = static_cast<float>(s.march_step_voxels);
  if (s.multiple_scattering_octaves) c.settings.octaves = static_cast<int>(s.multiple_scattering_octaves);
  if (s.light_update_threshold_deg > 0.0) c.settings.light_threshold_rad = s.light_update_threshold_deg * M_PI / 180.0;
  c.settings.direct_only = s.draw_mode == ATMO_CLOUD_DRAW_DIRECT;
  // AUTO: the layer march for weather at scale. A layer wider than impostors' bound decides before the
  // layers are made (the streamed decks come coarse first); a field that turns out to hold too many
  // clouds, after (its decks are then made in full here: they are at most the bound's width).
  const bool auto_mode = s.draw_mode == ATMO_CLOUD_DRAW_AUTO;
  const auto too_wide = [](const AtmoCloudLayer& l) {
    return l.type != ATMO_CLOUD_VDB_FILE && l.area_size_m > ATMO_CLOUD_AUTO_IMPOSTOR_AREA_M;
  };
  c.settings.layer = s.draw_mode == ATMO_CLOUD_DRAW_LAYER ||
                     (auto_mode && std::any_of(layers.begin(), layers.end(), too_wide));
  c.settings.wait = s.setup == ATMO_CLOUD_SETUP_WAIT;
  clouds::ImpostorSettings& imp = c.settings.impostors;
  if (s.impostor_texels) imp.tile_texels = static_cast<int>(s.impostor_texels);
  if (s.impostor_angle_threshold_deg > 0.0) imp.angle_threshold_rad = s.impostor_angle_threshold_deg * M_PI / 180.0;
  if (s.impostor_updates_per_frame) imp.updates_per_frame = static_cast<int>(s.impostor_updates_per_frame);
  if (s.direct_march_radii > 0.0) imp.near_radius_scale = s.direct_march_radii;
  if (s.impostor_max_pixels_per_texel > 0.0) imp.max_pixels_per_texel = s.impostor_max_pixels_per_texel;

  Verdict result;
  const bool stream = c.settings.layer && !c.settings.wait;
  // The field job's recipe, layer by layer: a deck's spec, or a field as built here.
  struct FieldPiece {
    std::optional<clouds::CloudLayerSpec> generate;
    AtmoCloudLayer optics;
    clouds::CloudField ready;
  };
  std::vector<FieldPiece> pieces;
  bool any_coarse = false;
  for (const AtmoCloudLayer& l : layers)
    if (stream && l.type != ATMO_CLOUD_VDB_FILE && clouds::is_deck(procedural_type(l.type))) any_coarse = true;
  for (uint32_t i = 0; i < s.layer_count; ++i) {
    const AtmoCloudLayer& l = layers[i];
    if (l.type == ATMO_CLOUD_VDB_FILE) {
      std::vector<uint8_t> bytes;
      std::string error;
      vdb::LoadResult r;
      if (!ctx.services.read_file(l.vdb_path, ctx.asset_root, &bytes, &error)) {
        r.error = error;
      } else {
        vdb::LoadOptions o;
        if (l.vdb_grid && *l.vdb_grid) o.grid_name = l.vdb_grid;
        if (l.metres_per_unit > 0.0) o.metres_per_unit = l.metres_per_unit;
        if (l.density_scale > 0.0) o.density_scale = l.density_scale;
        r = vdb::load_vdb_through_module(bytes.data(), bytes.size(), l.vdb_path, o);
      }
      if (!r.ok) {  // every file is still tried, so the log names each that fails
        const std::string msg = layer_name(i) + ": " + r.error;
        load_errors->push_back(msg);
        if (result.ok()) result = bad(ATMO_ERROR_IO, msg);
        continue;
      }
      for (const std::string& w : r.warnings) load_errors->push_back(layer_name(i) + ": warning: " + w);
      clouds::CloudVolume v = std::move(r.volume);
      apply_optics(l, &v);
      const double heading = l.rotation_deg[0] * M_PI / 180.0;
      // Heading turns the file's axes clockwise seen from above (east towards south).
      v.rotation = glm::angleAxis(-heading, glm::dvec3(0.0, 0.0, 1.0));
      const glm::dvec3 pos(l.position_enu_m[0], l.position_enu_m[1], l.position_enu_m[2]);
      v.origin_enu_m = pos + v.rotation * v.origin_enu_m;
      clouds::CloudField f;
      f.instances.push_back({0, v.origin_enu_m});
      f.prototypes.push_back(std::move(v));
      if (any_coarse) pieces.push_back({{}, {}, f});
      append_field(std::move(f), &c.field);
    } else {
      clouds::CloudLayerSpec spec;
      spec.type = procedural_type(l.type);
      spec.coverage_oktas = l.type == ATMO_CLOUD_OVERCAST ? 8 : l.coverage_oktas;
      spec.base_m = l.base_m;
      spec.top_m = l.top_m;
      spec.area_size_m = l.area_size_m > 0.0 ? l.area_size_m : 20000.0;
      spec.area_centre_enu_m = glm::dvec2(l.area_centre_enu_m[0], l.area_centre_enu_m[1]);
      spec.seed = l.seed ^ ctx.seed;
      const bool coarse = any_coarse && clouds::is_deck(spec.type);
      clouds::GeneratedLayer g = clouds::generate_cloud_layer(
          coarse ? clouds::coarser_layer_spec(spec, kCoarseDeckFactor) : spec, nullptr, waiting_threads());
      for (clouds::CloudVolume& v : g.field.prototypes) apply_optics(l, &v);
      if (coarse) {
        AtmoCloudLayer optics = l;
        optics.vdb_path = nullptr;  // the host's string is not kept
        pieces.push_back({spec, optics, {}});
      } else if (any_coarse) {
        pieces.push_back({{}, {}, g.field});
      }
      append_field(std::move(g.field), &c.field);
    }
  }
  if (!result.ok()) return result;  // all or nothing: the clouds stay as they were
  if (auto_mode && c.field.instances.size() > ATMO_CLOUD_AUTO_IMPOSTOR_CLOUDS) c.settings.layer = true;
  index_field(&c);
  // The full lighting waits for the first pass (and, streamed, for the
  // worker); the streamed layer march's draft gets its ambient depths now.
  if (c.settings.layer && !c.settings.wait) prepare_draft(&c);
  c.version = out->version + 1;
  c.field_version = c.version;
  c.frame = ctx.frame_clock;
  c.deferred_frames = ctx.deferred_frames;
  *out = std::move(c);  // (a move stops the jobs of both sides: the field job starts after it)
  if (any_coarse)
    out->field_job.start(std::make_unique<CloudFieldJob>([pieces = std::move(pieces)](const std::atomic<bool>& cancel) {
      clouds::CloudField f;
      for (const FieldPiece& piece : pieces) {
        if (cancel.load(std::memory_order_relaxed)) return clouds::CloudField{};
        if (!piece.generate) {
          append_field(clouds::CloudField(piece.ready), &f);
          continue;
        }
        clouds::GeneratedLayer g = clouds::generate_cloud_layer(*piece.generate, &cancel);
        if (g.cancelled) return clouds::CloudField{};
        for (clouds::CloudVolume& v : g.field.prototypes) apply_optics(piece.optics, &v);
        append_field(std::move(g.field), &f);
      }
      return f;
    }), ctx.frame_clock, ctx.deferred_frames);
  return {};
}

void index_field(ContextClouds* out) {
  ContextClouds& c = *out;
  c.mean_centre_height_m = 0.0;
  for (const clouds::CloudInstance& i : c.field.instances)
    c.mean_centre_height_m += c.field.prototypes[static_cast<size_t>(i.prototype)].centre_at(i.origin_enu_m).z;
  c.mean_centre_height_m /= static_cast<double>(std::max<size_t>(1, c.field.instances.size()));
  c.lowest_base_m = c.field.instances.empty() ? 0.0 : 1e300;
  c.highest_top_m = c.field.instances.empty() ? 0.0 : -1e300;
  for (const clouds::CloudInstance& i : c.field.instances) {  // grids turn only about the vertical
    const clouds::CloudVolume& v = c.field.prototypes[static_cast<size_t>(i.prototype)];
    c.lowest_base_m = std::min(c.lowest_base_m, i.origin_enu_m.z);
    c.highest_top_m = std::max(c.highest_top_m, i.origin_enu_m.z + double(v.density.nz) * v.voxel_size_m);
  }
  c.ray_index = clouds::build_cloud_ray_index(c.field);
  const clouds::FieldNeighbours neighbours = clouds::field_neighbours(c.field, c.ray_index);
  c.sole_instance = neighbours.sole;
  c.sides.resize(c.field.prototypes.size());
  for (size_t p = 0; p < c.field.prototypes.size(); ++p)
    c.sides[p] = clouds::continuing_sides(c.field, static_cast<int>(p), &neighbours);
}


clouds::CloudLight cloud_light(AtmoContext_T* ctx, AtmoView_T* view, const core::Scene& scene) {
  const core::SkyLighting& sky = view_sky_lighting(ctx, view, scene);
  const twin::AtmosphereParameters& atm = scene.atmosphere;
  // The light at the clouds' mean height: the transmittance from there (the
  // layers are near the eye's horizon, so the eye's direction serves).
  const double altitude = std::max(1.0, ctx->clouds.origin.height_m + ctx->clouds.mean_centre_height_m);
  const core::BodyIlluminance lit = core::body_illuminance(scene, ctx->transmittance, altitude);
  const glm::dvec3 sun_lux = lit.sun_lux, moon_lux = lit.moon_lux;
  const bool moon = moon_lux.g > sun_lux.g;
  clouds::CloudLight light;
  // The direction from the clouds' origin (the same for every view); the
  // eye's, turned into the clouds' axes, should the ephemeris refuse it.
  std::string error;
  const std::optional<core::SkyBodies> at_origin =
      ctx->clouds.bodies.get(ctx->utc_posix_s, ctx->dut1_s, ctx->clouds.origin, ctx->clouds.origin_ecef_m, &error);
  const glm::dmat3 to_clouds = cloud_enu_from_eye_enu(ctx->clouds, view->eye.ecef_from_enu);
  light.direction_enu =
      at_origin ? glm::normalize(moon ? at_origin->moon_enu : at_origin->sun_enu)
                : glm::normalize(to_clouds * (moon ? scene.bodies.moon_enu : scene.sun_direction_enu));
  light.illuminance_lux = moon ? moon_lux : sun_lux;
  light.sky_radiance = sky.average_radiance;
  // The ground under the clouds: Lambertian, lit by the light and the sky.
  const double albedo = static_cast<double>(atm.ground_albedo.g);
  const glm::dvec3 ground_lux = light.illuminance_lux * std::max(0.0, light.direction_enu.z) + sky.horizontal_illuminance_lux;
  light.ground_radiance = albedo * ground_lux / M_PI;
  return light;
}

namespace {

// Takes a finished relight's grids (and its shadow map and mips); true when it did.
bool take_relight(ContextClouds* c) {
  if (!c->relight.due(c->frame)) return false;
  CloudRelightJob& job = *c->relight.job;
  job.wait();
  c->depths = job.take();
  c->lit_direction_enu = job.direction();
  c->relight_ms = job.elapsed_ms();
  c->full_lit = true;
  ++c->version;
  if (job.has_shadow()) {
    c->shadow = job.take_shadow();
    ++c->shadow_version;
  }
  if (job.has_mips()) {
    c->mips = job.take_mips();
    c->clipmap_spec = c->settings.clipmap;
    c->clipmap_geometry = clouds::clipmap_geometry(c->field, c->clipmap_spec);
    c->mips_version = c->version;
  }
  c->relight.reset();
  return true;
}

void start_relight(ContextClouds* c, const glm::dvec3& light_dir, bool first) {
  RelightRequest r;
  r.light_direction_enu = light_dir;
  // Streamed, the sky passes want the map from the first frame (the draft's meanwhile).
  r.with_shadow = c->shadow_wanted || (first && !c->draft.prototypes.empty());
  r.with_ambient = first;
  if (first) r.sides = c->sides;
  r.with_mips = c->settings.layer;
  if (c->sole_instance.size() == c->field.prototypes.size()) r.neighbours = {c->sole_instance, &c->ray_index};
  c->relight.start(std::make_unique<CloudRelightJob>(
                       &c->field, first ? std::vector<clouds::LightDepths>{} : c->depths, std::move(r)),
                   c->frame, c->deferred_frames);
  if (c->settings.wait) {
    c->relight.job->wait();
    c->relight.due_frame = c->frame;
    take_relight(c);
  }
}

// The draft's clipmap has half as many voxels across (twice the voxel: the same reach).
clouds::ClipmapSpec draft_spec(const clouds::ClipmapSpec& full) {
  clouds::ClipmapSpec s = full;
  s.size = std::max(8, full.size / 4 * 2);
  if (s.base_voxel_m > 0.0f) s.base_voxel_m *= 2.0f;
  return s;
}

}  // namespace

void prepare_draft(ContextClouds* c) {
  c->draft = {};
  c->draft_depths.clear();
  c->draft_index = {};
  if (c->empty()) return;
  c->draft.instances = c->field.instances;
  const int n = static_cast<int>(c->field.prototypes.size());
  c->draft.prototypes.resize(static_cast<size_t>(n));
  c->draft_depths.resize(static_cast<size_t>(n));
  clouds::for_bands(n, waiting_threads(), [c](int begin, int end) {  // one prototype a thread: any count
    for (size_t p = static_cast<size_t>(begin); p < static_cast<size_t>(end); ++p) {
      c->draft.prototypes[p] = clouds::half_resolution(c->field.prototypes[p]);
      clouds::compute_ambient_depths(c->draft.prototypes[p], &c->draft_depths[p],
                                     p < c->sides.size() ? c->sides[p] : clouds::ContinuingSides{},
                                     kDraftAmbientDirections);
    }
  });
  c->draft_index = clouds::build_cloud_ray_index(c->draft);
}

namespace {

// Swaps in the field job's full-resolution field (the coarse one's draft is
// still drawn) and starts its first full lighting; true when it did.
bool take_field(ContextClouds* c) {
  if (!c->field_job.due(c->frame)) return false;
  c->field_job.job->wait();
  c->relight.reset();  // (none runs: the coarse field is never lit in full)
  c->field = c->field_job.job->take();
  c->field_ms = c->field_job.job->elapsed_ms();
  c->field_job.reset();
  index_field(c);
  c->depths.clear();
  c->full_lit = false;
  // The draft is unchanged: its mips and clipmap stay current.
  const bool mips_current = c->mips_version == c->version, clipmap_current = c->clipmap_built_for == c->version;
  ++c->version;
  ++c->field_version;
  if (mips_current) c->mips_version = c->version;
  if (clipmap_current) c->clipmap_built_for = c->version;
  if (glm::length(c->lit_direction_enu) >= 0.5) start_relight(c, c->lit_direction_enu, true);
  return true;
}

}  // namespace

bool relight_clouds(ContextClouds* c, const glm::dvec3& light_dir) {
  if (c->empty()) return false;
  bool changed = take_field(c);
  changed = take_relight(c) || changed;
  if (glm::length(c->lit_direction_enu) < 0.5) {  // never lit: nothing to draw until it is
    const auto t0 = std::chrono::steady_clock::now();
    if (!c->draft.prototypes.empty()) {
      // Streamed: the draft now (its ambient depths came with set_clouds), the
      // field on the worker (once the field job, if any, has made it).
      for (size_t p = 0; p < c->draft.prototypes.size(); ++p)
        clouds::sweep_light_depths(c->draft.prototypes[p], light_dir, &c->draft_depths[p]);
      c->lit_direction_enu = light_dir;
      ++c->version;
      if (!c->field_job.job) start_relight(c, light_dir, true);
    } else {  // the other draw modes draw from the full grids: wait for them
      start_relight(c, light_dir, true);
      c->relight.due_frame = c->frame;  // now
      take_relight(c);
    }
    c->relight_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return true;
  }
  if (c->relight.job || c->field_job.job) return changed;  // one at a time: the next starts after it
  if (glm::dot(c->lit_direction_enu, light_dir) >= std::cos(c->settings.light_threshold_rad)) return changed;
  start_relight(c, light_dir, false);
  return changed || c->settings.wait;
}

bool update_cloud_shadow(ContextClouds* c) {
  c->shadow_wanted = true;
  if (c->empty() || glm::length(c->lit_direction_enu) < 0.5) return false;
  if (c->shadow.size > 0 && c->shadow.light_direction_enu == c->lit_direction_enu) return false;
  if (!c->full_lit || (c->relight.job && c->relight.job->has_shadow())) {  // the worker brings it
    if (c->shadow.size > 0 || c->full_lit) return false;
    c->shadow = make_shadow_map(c->draft, c->lit_direction_enu, 64, 3.0f, waiting_threads());  // meanwhile the draft's
    ++c->shadow_version;
    return true;
  }
  // Lit in full (a draft's job brings its map): the host waits for this one.
  c->shadow = make_shadow_map(c->field, c->lit_direction_enu, 256, 2.0f, waiting_threads());
  ++c->shadow_version;
  return true;
}

bool update_clipmap(ContextClouds* c, const glm::dvec3& eye) {
  if (c->empty() || glm::length(c->lit_direction_enu) < 0.5) return false;
  const auto t0 = std::chrono::steady_clock::now();
  const clouds::CloudField& source = c->full_lit ? c->field : c->draft;
  const clouds::CloudRayIndex& index = c->full_lit ? c->ray_index : c->draft_index;
  if (c->mips_version != c->version) {  // the light grids changed and no worker made their mips
    c->clipmap_spec = c->full_lit ? c->settings.clipmap : draft_spec(c->settings.clipmap);
    c->mips = std::make_shared<const std::vector<clouds::PrototypeMips>>(
        clouds::build_prototype_mips(source, c->full_lit ? c->depths : c->draft_depths, c->lit_direction_enu));
    c->clipmap_geometry = clouds::clipmap_geometry(source, c->clipmap_spec);
    c->mips_version = c->version;
  }
  auto install = [c](clouds::CloudClipmap clipmap, uint64_t built_for, double ms) {
    c->clipmap = std::move(clipmap);
    c->clipmap_built_for = built_for;
    c->clipmap_ms = ms;
    ++c->clipmap_version;
  };
  bool changed = false;
  if (c->clipmap_job.job && (c->clipmap_job.due(c->frame) || c->settings.wait || c->clipmap.levels.empty())) {
    CloudClipmapJob& job = *c->clipmap_job.job;
    job.wait();
    install(job.take(), job.built_for(), job.elapsed_ms());
    c->clipmap_job.reset();
    changed = true;
  }
  const glm::ivec2 cell = clouds::clipmap_cell(c->clipmap_geometry, eye);
  if (c->clipmap_built_for == c->version && !c->clipmap.levels.empty() && c->clipmap.cell == cell) return changed;
  if (c->clipmap_job.job) return changed;  // one at a time: the next starts after it
  if (c->clipmap.levels.empty() || c->settings.wait) {  // nothing to draw yet, or asked to wait: now
    clouds::CloudClipmap built = clouds::build_clipmap(source, *c->mips, index, c->clipmap_spec, c->clipmap_geometry,
                                                       cell, nullptr, waiting_threads());
    install(std::move(built), c->version,
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    return true;
  }
  ClipmapRequest r;  // the old clipmap is drawn until the worker's is ready
  r.field = &source;
  r.mips = c->mips;
  r.index = &index;
  r.spec = c->clipmap_spec;
  r.geometry = c->clipmap_geometry;
  r.cell = cell;
  r.built_for = c->version;
  c->clipmap_job.start(std::make_unique<CloudClipmapJob>(std::move(r)), c->frame, c->deferred_frames);
  return changed;
}

bool ContextClouds::settled() const {
  if (empty()) return true;
  if (relight.job || clipmap_job.job || field_job.job || !full_lit) return false;
  return !settings.layer || (clipmap_built_for == version && !clipmap.levels.empty());
}

void wait_for_cloud_jobs(ContextClouds* c) {
  // Due now, whatever the frame: the next pass takes them.
  const auto now = [](auto& slot) {
    if (!slot.job) return;
    slot.job->wait();
    slot.due_frame = 0;
  };
  now(c->field_job);
  now(c->relight);
  now(c->clipmap_job);
}

glm::dvec3 eye_in_cloud_frame(const ContextClouds& c, const glm::dvec3& eye_ecef_m) {
  return glm::transpose(c.ecef_from_enu) * (eye_ecef_m - c.origin_ecef_m);
}

glm::dmat3 cloud_enu_from_eye_enu(const ContextClouds& c, const glm::dmat3& ecef_from_eye_enu) {
  return glm::transpose(c.ecef_from_enu) * ecef_from_eye_enu;
}

double cloud_transmittance_from_eye(const ContextClouds& c, const glm::dvec3& eye_ecef_m,
                                    const glm::dmat3& ecef_from_eye_enu, const glm::dvec3& direction_eye_enu) {
  if (c.empty()) return 1.0;
  const glm::dvec3 dir = glm::normalize(cloud_enu_from_eye_enu(c, ecef_from_eye_enu) * direction_eye_enu);
  return clouds::transmittance_along_ray(c.field, c.ray_index, eye_in_cloud_frame(c, eye_ecef_m), dir);
}

clouds::CloudViewCost layer_view_cost(const CloudSettings& settings, uint32_t quality) {
  clouds::CloudViewCost cost = clouds::cloud_view_cost(
      quality == ATMO_CLOUD_QUALITY_DEFAULT ? clouds::kDefaultCloudQuality : static_cast<clouds::CloudQuality>(quality));
  if (settings.layer_divisor > 0) cost.divisor = settings.layer_divisor;
  if (settings.layer_max_steps > 0) cost.max_steps = settings.layer_max_steps;
  if (settings.layer_temporal >= 0) cost.temporal = settings.layer_temporal != 0;
  return cost;
}

}  // namespace atmo::abi
