// make_abi_seeds.cpp — writes the ABI fuzz target's seed corpus
// (fuzz/corpus/abi/) in the format of abi_input.h: valid calls with typical
// values (so mutations start inside the valid ranges), a few undersized or
// mistyped structs, chains and arrays. Run once by hand:
//   build-fuzz/fuzz/fuzz_make_abi_seeds fuzz/corpus/abi
#include <cstdio>
#include <fstream>
#include <string>

#include "abi_input.h"
#include "seed_writer.h"

namespace {

using atmo_fuzz::CallHead;

struct Seed {
  std::string bytes;
  void head(atmo_fuzz::Op op, uint8_t flags = 0, uint8_t chain = 0, uint32_t struct_size = 0, uint32_t count = 0,
            uint32_t stride = 0, uint8_t reserved = 0) {
    CallHead h{static_cast<uint8_t>(op), flags, chain, reserved, struct_size, count, stride};
    bytes.append(reinterpret_cast<const char*>(&h), sizeof(h));
  }
  template <typename T>
  void add(const T& value) {
    bytes.append(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  void write(const std::string& path) const { atmo_fuzz::write_seed(path, bytes); }
};

AtmoLighting lighting() {
  AtmoLighting l{};
  l.header = ATMO_HEADER(ATMO_TYPE_LIGHTING, AtmoLighting);
  return l;
}

AtmoCloudLayer layer(uint32_t type) {
  AtmoCloudLayer l{};
  l.header = ATMO_HEADER(ATMO_TYPE_CLOUD_LAYER, AtmoCloudLayer);
  l.type = type;
  l.coverage_oktas = 3;
  l.base_m = 1000.0;
  l.top_m = 1400.0;
  l.area_size_m = 500.0;
  l.seed = 5;
  // The harness reads the pointers' low bytes as choices (abi_input.h): "cloud.vdb", "density".
  std::memset(&l.vdb_path, 0, sizeof(l.vdb_path));
  reinterpret_cast<unsigned char*>(&l.vdb_path)[0] = 2;
  reinterpret_cast<unsigned char*>(&l.vdb_grid)[0] = 2;
  return l;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string dir = atmo_fuzz::seed_dir(argc, argv);
  using namespace atmo_fuzz;
  {  // the air, a frame, a view and the lighting
    Seed s;
    AtmoAtmosphereState a{};
    a.header = ATMO_HEADER(ATMO_TYPE_ATMOSPHERE_STATE, AtmoAtmosphereState);
    a.visibility_m = 20000.0;
    a.aerosol_scale_height_m = 1500.0;
    a.ground_albedo = 0.2;
    s.head(kSetAtmosphere);
    s.add(a);
    s.head(kSetFrame);
    s.add(typical_frame());
    s.head(kSetView);
    s.add(typical_view(500.0));
    s.head(kGetLighting);
    s.add(lighting());
    s.write(dir + "/air_frame_view_lighting");
  }
  {  // a view from orbit, ECEF, and the 104-byte lighting of the first layout
    Seed s;
    AtmoViewState v = typical_view(400000.0);
    v.eye_kind = ATMO_POSITION_ECEF;
    v.world_frame = ATMO_WORLD_ECEF;
    v.eye_ecef_m[0] = 6.778e6;
    v.depth_convention = ATMO_DEPTH_LOGARITHMIC;
    v.far_plane_m = 1e7;
    s.head(kSetFrame);
    s.add(typical_frame());
    s.head(kSetView, 0, 0x0b);  // a chain of 3 that cycles
    s.add(v);
    s.head(kGetLighting, kSizeFromInput, 0, 104);
    s.add(lighting());
    s.write(dir + "/orbit_ecef_old_lighting");
  }
  {  // fog and two lights (one a cone), with a longer light stride
    Seed s;
    AtmoFogState f{};
  f.header = ATMO_HEADER(ATMO_TYPE_FOG_STATE, AtmoFogState);
    f.visibility_m = 300.0;
    f.top_height_m = 80.0;
    s.head(kSetFog);
    s.add(f);
    AtmoLightsState l{};
  l.header = ATMO_HEADER(ATMO_TYPE_LIGHTS_STATE, AtmoLightsState);
    l.world_frame = ATMO_WORLD_ENU;
    l.world_origin_geodetic[0] = 47.0;
    l.world_origin_geodetic[1] = 8.0;
    const uint32_t stride = sizeof(AtmoLightPoint) + 8;
    s.head(kSetLights, 0, 0, 0, 2, stride);
    s.add(l);
    for (int i = 0; i < 2; ++i) {
      AtmoLightPoint p{};
      p.position_m[0] = 10.0 * i;
      p.position_m[2] = 2.0;
      p.intensity_cd = 5000.0;
      p.color[0] = p.color[1] = p.color[2] = 1.0;
      if (i == 1) {
        p.direction[1] = 1.0;
        p.cone_inner_rad = 0.1;
        p.cone_outer_rad = 0.3;
      }
      s.add(p);
      s.bytes.append(stride - sizeof(AtmoLightPoint), '\0');
    }
    // The group's second light moved, then the group posed.
    AtmoLightsUpdate u{};
    u.header = ATMO_HEADER(ATMO_TYPE_LIGHTS_UPDATE, AtmoLightsUpdate);
    u.first = 1;
    s.head(kUpdateLights, 0, 0, 0, 1, sizeof(AtmoLightPoint));
    s.add(u);
    AtmoLightPoint moved{};
    moved.position_m[0] = 30.0;
    moved.intensity_cd = 2000.0;
    moved.color[0] = moved.color[1] = moved.color[2] = 1.0;
    s.add(moved);
    AtmoLightGroupPose pose{};
    pose.header = ATMO_HEADER(ATMO_TYPE_LIGHT_GROUP_POSE, AtmoLightGroupPose);
    for (int k = 0; k < 4; ++k) pose.world_from_group[5 * k] = 1.0;
    pose.world_from_group[12] = 50.0;
    s.head(kSetLightGroupPose);
    s.add(pose);
    s.head(kSetFrame);
    s.add(typical_frame());
    s.head(kSetView);
    s.add(typical_view(2.0));
    s.write(dir + "/fog_two_lights");
  }
  {  // occluders: two objects of 3 spheres each, then both moved
    Seed s;
    s.head(kSetFrame);
    s.add(typical_frame());
    s.head(kSetView);
    s.add(typical_view(2.0));
    AtmoOccludersState o{};
    o.header = ATMO_HEADER(ATMO_TYPE_OCCLUDERS_STATE, AtmoOccludersState);
    o.world_frame = ATMO_WORLD_ENU;
    o.world_origin_geodetic[0] = 47.0;
    o.world_origin_geodetic[1] = 8.0;
    s.head(kSetOccluders, 0, 0, 0, 2, sizeof(AtmoOccluderObject), 3);
    s.add(o);
    AtmoOccluderObject object{};
    object.albedo[0] = object.albedo[1] = object.albedo[2] = 0.4;
    for (int k = 0; k < 4; ++k) object.world_from_object[5 * k] = 1.0;
    s.add(object);
    object.world_from_object[12] = 30.0;
    s.add(object);
    for (int i = 0; i < 6; ++i) {  // each object's 3 spheres, after the objects
      AtmoOccluderSphere sphere{{2.0 * (i % 3), 0.0, 3.0}, 1.5};
      s.add(sphere);
    }
    AtmoOccluderPoses p{};
    p.header = ATMO_HEADER(ATMO_TYPE_OCCLUDER_POSES, AtmoOccluderPoses);
    s.head(kSetOccluderPoses, 0, 0, 0, 2);
    s.add(p);
    double m[2][16] = {};
    for (auto& row : m)
      for (int k = 0; k < 4; ++k) row[5 * k] = 1.0;
    m[1][13] = 10.0;
    s.add(m);
    s.write(dir + "/occluders_two_moved");
  }
  {  // clouds: a small cumulus layer and a VDB file layer
    Seed s;
    AtmoCloudsState c{};
  c.header = ATMO_HEADER(ATMO_TYPE_CLOUDS_STATE, AtmoCloudsState);
    c.origin_geodetic[0] = 47.0;
    c.origin_geodetic[1] = 8.0;
    s.head(kSetClouds, 0, 0, 0, 2, sizeof(AtmoCloudLayer));
    s.add(c);
    s.add(layer(ATMO_CLOUD_CUMULUS));
    s.add(layer(ATMO_CLOUD_VDB_FILE));
    s.write(dir + "/clouds_cumulus_and_vdb");
  }
  {  // undersized and mistyped structs, NULL
    Seed s;
    s.head(kSetFrame, kSizeFromInput, 0, 16);
    s.add(typical_frame());
    s.head(kSetView, kWrongType);
    s.add(typical_view(500.0));
    s.head(kSetFog, kNullStruct);
    s.add(AtmoFogState{});
    s.head(kSetAtmosphere, kSizeFromInput, 0, 24);
    s.add(AtmoAtmosphereState{});
    s.write(dir + "/bad_sizes_types_null");
  }
  return 0;
}
