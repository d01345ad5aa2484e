#include "abi/state_hash.h"

#include "abi/objects.h"
#include "core/scene/state_hash.h"

namespace atmo::abi {

namespace {

using core::StateHasher;

void hash_frame(const AtmoContext_T& c, StateHasher* h) {
  h->add(c.frame_number);
  h->add(c.frame_clock);
  h->add(c.deferred_frames);
  h->add(c.utc_posix_s);
  h->add(c.dut1_s);
}

void hash_key(const TableKey& k, StateHasher* h) {
  h->add(k.visibility_m), h->add(k.aerosol_scale_height_m), h->add(k.ground_albedo), h->add(k.radius_m);
}

void hash_air(const AtmoContext_T& c, StateHasher* h) {
  h->add(c.atmosphere.visibility_m), h->add(c.atmosphere.aerosol_scale_height_m), h->add(c.atmosphere.ground_albedo);
  hash_key(c.tables_key, h);  // the tables in use
  // A switch under way, and the frame it takes effect.
  h->add(c.tables_requested.valid());
  if (c.tables_requested.valid()) {
    hash_key(c.tables_requested, h);
    h->add(c.tables_due_frame);
  }
}

uint64_t field_hash(const clouds::CloudField& f) {
  StateHasher h;
  h.add(static_cast<uint64_t>(f.prototypes.size()));
  for (const clouds::CloudVolume& v : f.prototypes) {
    h.add(v.density.nx), h.add(v.density.ny), h.add(v.density.nz);
    h.add(v.density.values);
    h.add(v.voxel_size_m);
    h.add(v.origin_enu_m);
    h.add(v.rotation);
    h.add(v.optics.extinction_per_m), h.add(v.optics.albedo), h.add(v.optics.droplet_diameter_um);
  }
  h.add(static_cast<uint64_t>(f.instances.size()));
  for (const clouds::CloudInstance& i : f.instances) h.add(i.prototype), h.add(i.origin_enu_m);
  return h.value();
}

template <class Slot>
void hash_job(const Slot& slot, StateHasher* h) {
  h->add(slot.job != nullptr);
  if (slot.job) h->add(slot.due_frame);
}

void hash_clouds(AtmoContext_T& c, StateHasher* h) {
  const ContextClouds& k = c.clouds;
  h->add(k.empty());
  if (k.empty()) return;
  if (c.state_hash_cache.field_version != k.field_version) {
    c.state_hash_cache.field_hash = field_hash(k.field);
    c.state_hash_cache.field_version = k.field_version;
  }
  h->add(c.state_hash_cache.field_hash);
  h->add(k.origin.latitude_deg), h->add(k.origin.longitude_deg), h->add(k.origin.height_m);
  const CloudSettings& s = k.settings;
  h->add(s.march_divisor), h->add(s.march_step_voxels), h->add(s.octaves), h->add(s.light_threshold_rad);
  h->add(s.direct_only), h->add(s.layer), h->add(s.wait);
  h->add(s.impostors.tile_texels), h->add(s.impostors.angle_threshold_rad), h->add(s.impostors.updates_per_frame);
  h->add(s.impostors.near_radius_scale), h->add(s.impostors.max_pixels_per_texel);
  // The light they are lit with, from which grids, and the work under way (with the frames it lands).
  h->add(k.lit_direction_enu);
  h->add(k.full_lit);
  h->add(!k.draft.prototypes.empty());
  hash_job(k.relight, h);
  hash_job(k.field_job, h);
  hash_job(k.clipmap_job, h);
  h->add(!k.clipmap.levels.empty());
  if (!k.clipmap.levels.empty()) h->add(k.clipmap.cell);
  c.cloud_renderer.hash_state(c.frame_clock, h);  // the impostors, as this frame found them
}

void hash_fog(const AtmoContext_T& c, StateHasher* h) {
  const fog::FogOptics& o = c.fog.optics;
  h->add(o.extinction_per_m), h->add(o.albedo), h->add(o.phase_g), h->add(o.top_height_m), h->add(o.multiple_scattering);
  h->add(c.fog.airlight_table_size);
}

uint64_t lights_hash(const lights::LightSet& set) {
  StateHasher h;
  h.add(set.glow_threshold_cd_m2), h.add(set.visual_threshold_lux);
  h.add(static_cast<uint64_t>(set.groups.size()));
  for (const auto& [id, g] : set.groups) {
    h.add(id);
    h.add(g.ecef_from_world), h.add(g.world_from_group);
    h.add(static_cast<uint64_t>(g.lights.size()));
    for (const lights::Light& l : g.lights) {
      h.add(l.position_m), h.add(l.axis), h.add(l.intensity_cd), h.add(l.cos_inner), h.add(l.cos_outer);
      h.add(l.lobes), h.add(l.mean_profile);
    }
  }
  return h.value();
}

uint64_t occluders_hash(const ContextOccluders& o) {
  StateHasher h;
  h.add(o.flags);
  h.add(o.ecef_from_world);
  h.add(static_cast<uint64_t>(o.objects.size()));
  for (size_t i = 0; i < o.objects.size(); ++i) {
    const shadows::OccluderObject& b = o.objects[i];
    h.add(static_cast<uint64_t>(b.spheres.size()));
    for (const glm::dvec4& s : b.spheres) h.add(s);
    h.add(b.albedo);
    if (i < o.world_from_object.size()) h.add(o.world_from_object[i]);
  }
  return h.value();
}

void hash_view(const AtmoView_T& v, StateHasher* h) {
  const AtmoViewState& s = v.state;
  h->add(s.eye_kind), h->add(s.world_frame);
  for (double x : s.eye_ecef_m) h->add(x);
  for (double x : s.eye_geodetic) h->add(x);
  for (double x : s.world_origin_geodetic) h->add(x);
  for (double x : s.view_from_world) h->add(x);
  for (double x : s.clip_from_view) h->add(x);
  for (int32_t x : s.viewport) h->add(static_cast<int64_t>(x));
  h->add(s.depth_texture != 0);  // the name is the process's own
  h->add(s.depth_convention), h->add(s.far_plane_m), h->add(s.log_depth_coefficient);
  h->add(s.output_encoding), h->add(s.exposure_scale), h->add(s.sky_method);
  for (uint32_t x : s.sky_view_table_size) h->add(x);
  for (uint32_t x : s.aerial_volume_size) h->add(x);
  h->add(s.depth_origin), h->add(s.aerial_range_m), h->add(s.cloud_quality);
}

}  // namespace

void state_hash_parts(AtmoContext_T* c, const AtmoView_T& view, uint64_t parts[ATMO_STATE_HASH_PART_COUNT]) {
  StateHasher frame(ATMO_STATE_HASH_FRAME), air(ATMO_STATE_HASH_AIR), clouds(ATMO_STATE_HASH_CLOUDS),
      fog(ATMO_STATE_HASH_FOG), lights(ATMO_STATE_HASH_LIGHTS), occluders(ATMO_STATE_HASH_OCCLUDERS),
      view_part(ATMO_STATE_HASH_VIEW);
  hash_frame(*c, &frame);
  hash_air(*c, &air);
  hash_clouds(*c, &clouds);
  hash_fog(*c, &fog);
  if (c->state_hash_cache.lights_version != c->lights.version) {
    c->state_hash_cache.lights_hash = lights_hash(c->lights);
    c->state_hash_cache.lights_version = c->lights.version;
  }
  lights.add(c->state_hash_cache.lights_hash);
  if (c->state_hash_cache.occluders_version != c->occluders.version) {
    c->state_hash_cache.occluders_hash = occluders_hash(c->occluders);
    c->state_hash_cache.occluders_version = c->occluders.version;
  }
  occluders.add(c->state_hash_cache.occluders_hash);
  hash_view(view, &view_part);
  parts[ATMO_STATE_HASH_FRAME] = frame.value();
  parts[ATMO_STATE_HASH_AIR] = air.value();
  parts[ATMO_STATE_HASH_CLOUDS] = clouds.value();
  parts[ATMO_STATE_HASH_FOG] = fog.value();
  parts[ATMO_STATE_HASH_LIGHTS] = lights.value();
  parts[ATMO_STATE_HASH_OCCLUDERS] = occluders.value();
  parts[ATMO_STATE_HASH_VIEW] = view_part.value();
}

uint64_t combined_state_hash(const uint64_t parts[ATMO_STATE_HASH_PART_COUNT]) {
  StateHasher h;
  for (int k = ATMO_STATE_HASH_FRAME; k <= ATMO_STATE_HASH_OCCLUDERS; ++k) h.add(parts[k]);
  return h.value();
}

}  // namespace atmo::abi
