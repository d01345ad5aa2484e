#include "clouds_command.h"

#include <cstdio>

#include "atmo_scenario/scenario.h"
#include "core/clouds/procedural_clouds.h"
#include "vdb/vdb_io.h"

namespace atmo::clouds_cli {

namespace sc = atmo::scenario;

int run_clouds(const Options& options) {
  sc::LoadResult loaded = sc::load_scenario_file(options.scenario_path);
  if (!loaded.scenario) {
    std::fprintf(stderr, "atmo clouds: %s\n", loaded.error.c_str());
    return 2;
  }
  const sc::Scenario& s = *loaded.scenario;
  std::vector<clouds::CloudVolume> volumes;
  for (size_t i = 0; i < s.clouds.size(); ++i) {
    const sc::CloudLayer& c = s.clouds[i];
    if (c.type == sc::CloudType::Vdb) {
      std::printf("layer %zu: a vdb file (%s), not procedural: left out\n", i, c.vdb_file.c_str());
      continue;
    }
    clouds::CloudLayerSpec spec;
    spec.type = c.type == sc::CloudType::Stratus    ? clouds::CloudLayerType::Stratus
                : c.type == sc::CloudType::Overcast ? clouds::CloudLayerType::Overcast
                : c.type == sc::CloudType::Cirrus   ? clouds::CloudLayerType::Cirrus
                                                    : clouds::CloudLayerType::Cumulus;
    spec.coverage_oktas = c.type == sc::CloudType::Overcast ? 8 : c.coverage_oktas;
    spec.base_m = c.base_m;
    spec.top_m = c.top_m;
    spec.area_size_m = sc::cloud_layer_area_m(s, c);
    spec.seed = c.seed;  // the plugin mixes in its context seed (0 for atmo render)
    clouds::GeneratedLayer g = clouds::generate_cloud_layer(spec);
    std::printf("layer %zu (%s): %zu clouds from %zu volumes, coverage %.3f (asked %d/8)\n", i,
                clouds::cloud_layer_type_name(spec.type), g.field.instances.size(), g.field.prototypes.size(),
                g.coverage_fraction, spec.coverage_oktas);
    if (options.prototypes_only) {
      for (clouds::CloudVolume& v : g.field.prototypes) volumes.push_back(std::move(v));
    } else {
      for (const clouds::CloudInstance& inst : g.field.instances) {
        clouds::CloudVolume v = g.field.prototypes[static_cast<size_t>(inst.prototype)];
        v.origin_enu_m = inst.origin_enu_m;
        volumes.push_back(std::move(v));
      }
    }
  }
  if (volumes.empty()) {
    std::fprintf(stderr, "atmo clouds: %s has no procedural cloud layer with clouds\n", options.scenario_path.c_str());
    return 2;
  }
  const std::string error = vdb::write_vdb_file(options.out_path, volumes);
  if (!error.empty()) {
    std::fprintf(stderr, "atmo clouds: %s\n", error.c_str());
    return 2;
  }
  std::printf("wrote %zu grids to %s\n", volumes.size(), options.out_path.c_str());
  return 0;
}

}  // namespace atmo::clouds_cli
