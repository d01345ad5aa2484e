// Scenario files: JSON descriptions of a test scene (place, time, cameras,
// atmosphere, ...), loaded and validated into plain structs.
//
// The format is config/scenario.schema.json. Units are SI and field names
// carry them (_m, _deg, _s, _cd, _lux); angles stay in degrees here as they
// are in the file — convert to radians where they enter the renderer.
//
// Validation is hand-written but enforces every rule of the schema, plus the
// cross-field rules a schema cannot say (far_m > near_m, top_m > base_m,
// calendar dates, unique camera names). Unknown fields are errors. Each error
// line reads "<file>: <JSON pointer>: expected ..., found ...".
#ifndef ATMO_SCENARIO_SCENARIO_H
#define ATMO_SCENARIO_SCENARIO_H

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace atmo::scenario {

inline constexpr int kSchemaVersion = 1;

// Something in the file that was parsed and validated but that this build
// cannot draw yet; the runner prints these as "not yet supported".
struct Notice {
  std::string path;     // JSON pointer, e.g. "/clouds"
  std::string message;
};

// WGS84 geodetic point.
struct GeodeticPoint {
  double latitude_deg = 0.0;   // [-90, 90]
  double longitude_deg = 0.0;  // [-180, 180]
  double height_m = 0.0;       // above the ellipsoid, [-1000, 1e7]
};

// A point given either in east-north-up metres from Scenario::location
// (the ENU origin) or as a geodetic point.
struct Position {
  enum class Kind { Enu, Geodetic };
  Kind kind = Kind::Enu;
  std::array<double, 3> enu_m{};  // Kind::Enu: east, north, up
  GeodeticPoint geodetic;         // Kind::Geodetic
};

struct Camera {
  std::string name;           // [A-Za-z0-9][A-Za-z0-9_-]{0,63}, unique; names output files
  Position position;
  double heading_deg = 0.0;   // [-360, 360]; 0 = north, clockwise
  double pitch_deg = 0.0;     // [-90, 90]; + looks up
  double roll_deg = 0.0;      // [-180, 180]; + rolls right side down; default 0
  double vertical_fov_deg = 60.0;  // (0, 180)
  int width = 0;              // pixels, [1, 8192]
  int height = 0;             // pixels, [1, 8192]
  double near_m = 1.0;        // > 0
  double far_m = 100000.0;    // > near_m
  // [-20, 30]; replaces render.exposure_ev100 for this camera (e.g. a
  // telephoto on the Moon next to a wide night view).
  std::optional<double> exposure_ev100;
};

struct Atmosphere {
  double visibility_m = 40000.0;          // MOR at the ground, [50, 500000]
  double aerosol_scale_height_m = 1200.0; // [100, 20000]
  double ground_albedo = 0.1;             // [0, 1]
};

enum class TerrainKind { Hills, Flat, None };

// Host-drawn ground (the plugin draws none). Absent: no host geometry.
struct Terrain {
  TerrainKind kind = TerrainKind::Hills;
  std::uint64_t seed = 0;            // [0, 2^53 - 1]
  double size_m = 20000.0;           // side of the square patch, [100, 200000]
  double relief_m = 150.0;           // hill height, [0, 5000]
  bool runway = false;               // a runway centred on the ENU origin
  double runway_heading_deg = 90.0;  // its true direction, [0, 360]
};

enum class CloudType { Cumulus, Stratus, Overcast, Cirrus, Vdb };

// Procedural layers use coverage_oktas/base_m/top_m; a Vdb layer uses
// vdb_file/position/scale instead. Heights are above the ENU origin.
struct CloudLayer {
  CloudType type = CloudType::Cumulus;
  int coverage_oktas = 0;     // [0, 8]
  double base_m = 0.0;        // [0, 20000]
  double top_m = 0.0;         // (base_m, 20000]
  std::uint64_t seed = 0;
  std::string vdb_file;       // Vdb: as written, relative to the scenario file
  Position position;          // Vdb: where the grid's origin goes
  double scale = 1.0;         // Vdb: metres per grid unit, > 0
  double heading_deg = 0.0;   // Vdb: the grid's x axis turned from east, clockwise seen from above, [0, 360]
  double density_scale = 1.0; // Vdb: multiplies the grid's values, > 0
  double area_m = 0.0;        // procedural: side of the square the layer fills; 0: the terrain's size (or 20 km)
};

struct Fog {
  double visibility_m = 0.0;  // MOR inside the fog, [10, 5000]
  double top_m = 0.0;         // above the ENU origin, (0, 3000]
};

struct LightPoint {
  std::array<double, 3> enu_m{};
  double intensity_cd = 0.0;                // > 0
  std::array<double, 3> color{1.0, 1.0, 1.0};  // linear RGB, each [0, 1]
};

// One runway of an airport layout (tools/host_scene light_layouts.h
// RunwaySpec): edge, centreline, touchdown-zone, threshold and end lights and
// an approach lighting system before its threshold.
struct AirportRunway {
  std::array<double, 2> centre_enu_m{};  // east, north of its centre on the ground
  double heading_deg = 90.0;             // landing direction, [0, 360]
  double length_m = 3000.0;              // [300, 6000]
  double width_m = 45.0;                 // [10, 100]
};

// An airport's lights (light_layouts.h airport_lights): its runways, then
// taxiways parallel to the first and stubs to it. Absent runways: one on the
// terrain's runway (centred on the ENU origin along terrain.runway_heading_deg,
// 3000 x 45 m; heading 90 without terrain).
struct AirportLights {
  std::vector<AirportRunway> runways;  // 1 to 8
  double taxiway_length_m = 8000.0;    // [0, 50000]
};

// A town's lights (light_layouts.h town_lights): streets, cars, windows and
// signs in a square of side sqrt(lights / lights_per_km2) km.
struct TownLights {
  std::array<double, 2> centre_enu_m{0.0, 5000.0};  // east, north
  std::uint32_t lights = 10000;                      // exactly this many, [1, 65536]
  double lights_per_km2 = 1300.0;                    // [10, 100000]
  std::uint64_t seed = 1;                            // [0, 2^53 - 1]
};

struct Lights {
  bool runway_approach = false;  // approach lighting of Terrain::runway
  std::optional<AirportLights> airport;
  std::optional<TownLights> town;
  std::vector<LightPoint> points;
};

// One of the host's objects (an aircraft, a vehicle, a hangar): drawn by the
// host from its mesh and handed to the plugin as an occluder of the sky
// (set_occluders, its sphere set; docs/SKY_OCCLUSION.md). The object's frame
// (tools/spheres: m, x forward, y left, z up, standing on z = 0) is turned by
// heading_deg about up and its origin put at position_m.
struct SceneObject {
  std::string spheres;                       // an "atmo-spheres-1" file, as written (relative to the scenario file)
  std::string mesh;                          // an OBJ or PLY mesh, as written (relative to the scenario file)
  std::array<double, 3> position_m{};        // east, north, up from Scenario::location (the ENU frame's origin)
  double heading_deg = 0.0;                  // [-360, 360]: the object's x axis from true north, clockwise
  std::array<double, 3> albedo{0.5, 0.5, 0.5};  // diffuse reflectance, linear RGB, each [0, 1]
};

// At most ATMO_OCCLUDER_OBJECTS_MAX (atmo.h) objects.
inline constexpr std::size_t kMaxObjects = 4096;

// The night sky is drawn whenever it can be seen (the plugin decides by
// physics and exposure); stars: false leaves out the night-sky pass (stars and
// planets). The Moon belongs to the sky pass: moon: false is reported as not
// supported.
struct NightSky {
  bool stars = true;
  bool moon = true;
};

enum class DepthConvention { Standard, Reversed, Logarithmic };
enum class OutputEncoding { LinearHdr, DisplaySrgb };
// AtmoCloudDrawMode's order. A still in Layer (or Auto) mode waits for the
// full lighting (ATMO_CLOUD_SETUP_WAIT) and traces every pixel
// (ATMO_CLOUD_QUALITY_HIGH), so it does not depend on earlier frames.
enum class CloudDrawMode { Auto, Direct, Layer, Impostors };

struct Render {
  DepthConvention depth_convention = DepthConvention::Reversed;
  std::optional<double> exposure_ev100;  // [-20, 30]; absent: auto_exposure_ev100(sun)
  OutputEncoding output = OutputEncoding::LinearHdr;
  CloudDrawMode cloud_draw_mode = CloudDrawMode::Auto;
};

struct Outputs {
  bool exr = true;
  bool png = true;
};

struct Reference {
  std::string image;              // PNG, as written, relative to the scenario file
  std::string metric = "psnr_db"; // the only metric so far
  double min_psnr_db = 0.0;       // > 0
};

struct LuminanceCheck {
  std::string name;
  double u = 0.0;          // [0, 1], left to right
  double v = 0.0;          // [0, 1], v = 0 is the top row
  double min_cd_m2 = 0.0;  // >= 0
  double max_cd_m2 = 0.0;  // >= min_cd_m2
  std::string camera;      // the one camera checked; empty: every camera
};

struct Expectations {
  bool finite = true;  // every output pixel finite
  std::optional<Reference> reference;
  std::vector<LuminanceCheck> luminance_checks;
  std::optional<double> max_frame_ms;  // > 0
};

// Display channels side by side (a multi-channel image generator; samples/channels,
// docs/MULTI_CHANNEL.md). Wrap: count channels around the vertical axis, each
// horizontal_fov_deg wide, adjacent ones sharing an edge-blend band of
// overlap_deg; channel i (0 = leftmost) is centred at
// (i - (count - 1) / 2) * (horizontal_fov_deg - overlap_deg) right of the eye's heading.
enum class ChannelLayout { Wrap };
struct Channels {
  ChannelLayout layout = ChannelLayout::Wrap;
  int count = 3;                     // [1, 64]
  double horizontal_fov_deg = 60.0;  // (0, 180)
  double vertical_fov_deg = 40.0;    // (0, 180)
  double overlap_deg = 0.0;          // [0, horizontal_fov_deg)
  int width = 0;                     // pixels of each channel, [1, 8192]
  int height = 0;                    // [1, 8192]
  double near_m = 1.0;               // > 0
  double far_m = 100000.0;           // > near_m
};

// One pose of the eye on the flight path, at t_s seconds after the scenario's utc.
struct FlightKeyframe {
  double t_s = 0.0;          // >= 0, increasing from keyframe to keyframe
  Position position;         // the cameras' position (all channels share it)
  double heading_deg = 0.0;  // [-360, 360]; interpolated as written (350 to 10 turns the long way)
  double pitch_deg = 0.0;    // [-90, 90]
};

// What changes at the start of a frame: a whole atmosphere section (absent
// fields take the format's defaults, as at the top level) and/or the clouds
// (replaced; an empty list clears them).
struct FlightEvent {
  std::int64_t at_frame = 0;  // [0, 10^9]
  std::optional<Atmosphere> atmosphere;
  std::optional<std::vector<CloudLayer>> clouds;
};

// Frame k shows t = k / frame_rate_hz seconds after utc, the eye at the
// keyframes' linear interpolation (held before the first and after the last).
struct Flight {
  double frame_rate_hz = 60.0;  // (0, 1000]
  std::int64_t frames = 0;      // [1, 10^6]; absent: floor(last t_s * frame_rate_hz) + 1
  std::vector<FlightKeyframe> keyframes;  // at least 1
  std::vector<FlightEvent> events;        // in file order; several may share a frame
};

// Sections with defaults for every field are plain members, filled in when
// absent; sections whose absence means "feature off" are optional.
struct Scenario {
  int schema_version = kSchemaVersion;
  std::string name;
  std::string description;
  std::string source_file;  // the path or label it was loaded from
  std::string source_dir;   // base of relative paths in the file ("" = cwd)

  GeodeticPoint location;   // ENU origin of every enu_m in the file
  std::string utc;          // as written
  double utc_posix_s = 0.0; // utc as POSIX seconds
  double dut1_s = 0.0;      // UT1 - UTC, [-0.9, 0.9] s

  std::vector<Camera> cameras;  // at least one
  Atmosphere atmosphere;
  std::optional<Terrain> terrain;
  std::vector<CloudLayer> clouds;
  std::optional<Fog> fog;
  std::optional<Lights> lights;
  std::vector<SceneObject> objects;  // none: no occluders (and no set_occluders call)
  std::optional<NightSky> night_sky;
  Render render;
  Outputs outputs;
  Expectations expectations;
  std::optional<Channels> channels;  // absent: the sample host's defaults (samples/channels)
  std::optional<Flight> flight;      // absent: one frame at the first camera's pose

  std::vector<Notice> not_yet_supported;  // one per such section present
  // How an imported file (OpenSCENARIO, openscenario.h) was mapped: defaults
  // taken, values clamped, what won where two sources disagree. Empty for JSON.
  std::vector<Notice> import_notes;
};

struct LoadResult {
  std::optional<Scenario> scenario;
  std::string error;  // empty on success; else one line per problem
};

// What an OpenSCENARIO file does not say and the command line may
// (openscenario.h; `atmo render --lat --lon --size`). Unset: the import's defaults.
struct ImportOptions {
  std::optional<double> latitude_deg;   // wins over the road network's geo-reference
  std::optional<double> longitude_deg;
  std::optional<int> width, height;     // the default camera's pixels
  bool empty() const { return !latitude_deg && !longitude_deg && !width && !height; }
};

// Reads and validates a scenario file; errors are labelled with `path`.
// An OpenSCENARIO file (".xosc", any case: is_openscenario_path) is imported
// (openscenario.h) with `options`; a JSON file ignores them.
LoadResult load_scenario_file(const std::string& path, const ImportOptions& options = {});
bool is_openscenario_path(const std::string& path);

// Validates JSON text; errors are labelled with `file_label`, whose directory
// (if any) becomes Scenario::source_dir.
LoadResult parse_scenario(const std::string& json_text, const std::string& file_label);

// A path written in the scenario (reference image, VDB file, object files) resolved against
// the scenario file's directory; absolute paths are returned unchanged.
std::string resolve_path(const Scenario& scenario, const std::string& relative);

// The side of the square a procedural cloud layer fills: its area_m, else the
// terrain's size, else 20 km.
double cloud_layer_area_m(const Scenario& scenario, const CloudLayer& layer);

// Field names the loader accepts in each kind of object, keyed as in the
// schema: "scenario" for the top level, else the schema's "$defs" name.
// Exposed so a test can check that the schema and the loader agree.
struct ObjectShape {
  std::string name;
  std::vector<std::string> fields;
};
const std::vector<ObjectShape>& object_shapes();
const std::vector<std::string>& top_level_fields();

// "YYYY-MM-DDThh:mm:ss[.f...]Z" or with a "+hh:mm"/"-hh:mm" offset, to POSIX
// seconds (days of 86 400 s, proleptic Gregorian): the plugin's parser
// (core/astro/iso8601.h, also its calendar). Years 0000-9999; seconds 00-59
// (a leap second has no POSIX time). On failure returns nullopt and,
// if error is not null, says why.
std::optional<double> parse_iso8601_utc(const std::string& text, std::string* error);


// POSIX seconds as "YYYY-MM-DDThh:mm:ss[.fff]Z" (milliseconds only when non-zero).
std::string format_iso8601_utc(double posix_s);

// A sane EV100 when a scenario gives none, from the sun's elevation (deg):
// a monotone, C1-smooth cubic Hermite (Fritsch-Carlson) curve through
//   elevation  <= -10   -6   -4    0    10   >= 25
//   EV100          2    5    8   12    14.3    15
// flat outside [-10, 25]: 15 in full sun, 12 at sunset, ~8 in civil
// twilight, 2 at night (stars and moonlight).
double auto_exposure_ev100(double sun_elevation_deg);

const char* to_string(TerrainKind kind);
const char* to_string(CloudType type);
const char* to_string(DepthConvention convention);
const char* to_string(OutputEncoding encoding);
const char* to_string(ChannelLayout layout);

}  // namespace atmo::scenario

#endif  // ATMO_SCENARIO_SCENARIO_H
