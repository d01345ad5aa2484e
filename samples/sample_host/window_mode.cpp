// Window mode: GLFW window (GL 4.5 core, else 3.3 core), free-fly camera,
// Dear ImGui panel for time, place, air, fog (RVR), the lights, depth
// convention, exposure, the weather's cloud layers and the per-pass GPU
// timings with the light count.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <glad/gl.h>
// After glad: GLFW must not include a GL header of its own.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include "atmo_host_scene/depth_setup.h"
#include "atmo_support/image.h"
#include "core/astro/iso8601.h"
#include "modes.h"
#include "sample_renderer.h"

namespace atmo::sample {

namespace hs = atmo::host_scene;

namespace {

void* glfw_proc_address(void* /*user*/, const char* name) {
  return reinterpret_cast<void*>(glfwGetProcAddress(name));
}

void glfw_error(int code, const char* message) { std::fprintf(stderr, "GLFW error 0x%x: %s\n", code, message); }

struct Window {
  GLFWwindow* handle = nullptr;
  ~Window() {
    if (handle) glfwDestroyWindow(handle);
    glfwTerminate();
  }
};

GLFWwindow* create_window(int width, int height) {
  // Newest first; the plugin needs 3.3 at least.
  const int versions[2][2] = {{4, 5}, {3, 3}};
  for (const auto& v : versions) {
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, v[0]);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, v[1]);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    if (GLFWwindow* w = glfwCreateWindow(width, height, "Atmo sample host", nullptr, nullptr)) return w;
  }
  return nullptr;
}

struct FlyCamera {
  double speed_m_s = 60.0;
  double last_x = 0.0, last_y = 0.0;
  bool dragging = false;
};

// WASD moves along the view, Q/E down/up, mouse drag turns; shift is 10x.
void update_camera(GLFWwindow* window, const hs::Terrain& terrain, double dt, FlyCamera* fly, hs::CameraPose* pose) {
  const ImGuiIO& io = ImGui::GetIO();
  double x = 0.0, y = 0.0;
  glfwGetCursorPos(window, &x, &y);
  const bool pressed = glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
  if (pressed && (fly->dragging || !io.WantCaptureMouse)) {
    if (fly->dragging) {
      pose->heading_deg = std::fmod(pose->heading_deg + 0.15 * (x - fly->last_x) + 360.0, 360.0);
      pose->pitch_deg = std::clamp(pose->pitch_deg - 0.15 * (y - fly->last_y), -89.0, 89.0);
    }
    fly->dragging = true;
  } else {
    fly->dragging = false;
  }
  fly->last_x = x;
  fly->last_y = y;

  if (io.WantCaptureKeyboard) return;
  auto down = [&](int key) { return glfwGetKey(window, key) == GLFW_PRESS; };
  const glm::dmat3 axes = hs::enu_from_camera_rotation(*pose);
  glm::dvec3 move(0.0);
  if (down(GLFW_KEY_W)) move -= axes[2];
  if (down(GLFW_KEY_S)) move += axes[2];
  if (down(GLFW_KEY_D)) move += axes[0];
  if (down(GLFW_KEY_A)) move -= axes[0];
  if (down(GLFW_KEY_E)) move.z += 1.0;
  if (down(GLFW_KEY_Q)) move.z -= 1.0;
  if (glm::length(move) == 0.0) return;
  const bool fast = down(GLFW_KEY_LEFT_SHIFT) || down(GLFW_KEY_RIGHT_SHIFT);
  pose->position_enu_m += glm::normalize(move) * fly->speed_m_s * (fast ? 10.0 : 1.0) * dt;
  // Stay above the ground (curvature included).
  const glm::dvec3& p = pose->position_enu_m;
  const double ground = terrain.height_at(p.x, p.y) - hs::curvature_drop_m(p.x, p.y);
  pose->position_enu_m.z = std::max(p.z, ground + 1.5);
}

// The window's back buffer (display-referred) as a PNG; row 0 of Image is the top.
bool write_screenshot(const std::string& path, int width, int height) {
  atmo::support::Image image = atmo::support::make_image(width, height);
  std::vector<float> rows(image.rgba.size());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, rows.data());
  const size_t row = static_cast<size_t>(width) * 4;
  for (int y = 0; y < height; ++y) {
    std::copy_n(rows.begin() + static_cast<std::ptrdiff_t>(row * static_cast<size_t>(height - 1 - y)), row,
                image.rgba.begin() + static_cast<std::ptrdiff_t>(row * static_cast<size_t>(y)));
  }
  std::string error;
  if (!atmo::support::write_png(path, image, &error)) {
    std::fprintf(stderr, "atmo-sample-host: screenshot: %s\n", error.c_str());
    return false;
  }
  return true;
}

struct PanelState {
  std::array<double, kSectionCount> smoothed_ms{};
  std::array<double, kSectionCount> smoothed_wall_ms{};  // with finish_sections
  double smoothed_cpu_ms = 0.0;
  double smoothed_fog_lighting_ms = 0.0;
  bool finish_sections = false;     // glFinish after each section: exact times on llvmpipe, slower frames
  double rvr_m = 550.0;             // the RVR the Fog checkbox turns back on
  int town_slider = 0;              // the Town lights slider's value while it is dragged
  bool animate_time = false;
  float time_rate = 60.0f;
  std::vector<std::string> errors;  // of the last frame that had any
  bool apply_clouds = false;        // the Weather section's Apply was pressed
  bool clouds_edited = false;       // the layers changed since the last Apply
  bool clouds_ok = true;
  std::string clouds_message;       // set_clouds' result
  std::string objects_error;        // why the objects could not be read (their checkbox is then off)
};

// A std::string edited through a fixed buffer (the Debian imgui has no imgui_stdlib).
bool input_text(const char* label, std::string* text) {
  char buffer[1024];
  std::snprintf(buffer, sizeof buffer, "%s", text->c_str());
  if (!ImGui::InputText(label, buffer, sizeof buffer)) return false;
  *text = buffer;
  return true;
}

// The Weather window: add and remove cloud layers; Apply calls set_clouds with them.
void draw_weather(PanelState* panel, CloudSettings* clouds) {
  ImGui::SetNextWindowPos(ImVec2(std::max(480.0f, ImGui::GetIO().DisplaySize.x - 390.0f), 10), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(380, 0), ImGuiCond_FirstUseEver);
  ImGui::Begin("Weather");
  ImGui::PushItemWidth(-170.0f);  // room for the labels
  bool edited = false;
  for (size_t i = 0; i < clouds->layers.size();) {
    CloudLayerSettings& l = clouds->layers[i];
    ImGui::PushID(static_cast<int>(i));
    char title[64];
    std::snprintf(title, sizeof title, "Layer %zu: %s", i + 1, cloud_type_name(l.type));
    const bool open = ImGui::TreeNodeEx("layer", ImGuiTreeNodeFlags_DefaultOpen, "%s", title);
    ImGui::SameLine();
    const bool remove = ImGui::SmallButton("Remove");
    if (open) {
      int type = static_cast<int>(l.type);
      if (ImGui::BeginCombo("Type", cloud_type_name(l.type))) {
        for (int t = 0; t < ATMO_CLOUD_LAYER_TYPE_COUNT; ++t) {
          if (ImGui::Selectable(cloud_type_name(static_cast<AtmoCloudLayerType>(t)), t == type)) type = t;
        }
        ImGui::EndCombo();
      }
      if (type != static_cast<int>(l.type)) {
        // A VDB file keeps its own heights: its origin starts on the datum (as --vdb puts it).
        if (type == ATMO_CLOUD_VDB_FILE) l.base_m = 0.0;
        l.type = static_cast<AtmoCloudLayerType>(type);
        edited = true;
      }
      if (l.type == ATMO_CLOUD_VDB_FILE) {
        edited |= input_text("File", &l.vdb_path);
        edited |= input_text("Grid (empty: density)", &l.vdb_grid);
        edited |= ImGui::InputDouble("Origin east (km)", &l.area_east_km, 0.1, 1.0, "%.2f");
        edited |= ImGui::InputDouble("Origin north (km)", &l.area_north_km, 0.1, 1.0, "%.2f");
        edited |= ImGui::InputDouble("Origin up (m)", &l.base_m, 10.0, 100.0, "%.0f");
      } else {
        edited |= ImGui::SliderInt("Coverage (oktas)", &l.coverage_oktas, 0, 8);
        edited |= ImGui::InputDouble("Base (m)", &l.base_m, 50.0, 500.0, "%.0f");
        edited |= ImGui::InputDouble("Top (m)", &l.top_m, 50.0, 500.0, "%.0f");
        edited |= ImGui::InputDouble("Area side (km)", &l.area_size_km, 1.0, 10.0, "%.1f");
        edited |= ImGui::InputDouble("Area centre east (km)", &l.area_east_km, 1.0, 10.0, "%.1f");
        edited |= ImGui::InputDouble("Area centre north (km)", &l.area_north_km, 1.0, 10.0, "%.1f");
        edited |= ImGui::InputScalar("Seed", ImGuiDataType_U64, &l.seed);
      }
      ImGui::TreePop();
    }
    ImGui::PopID();
    if (remove) {
      clouds->layers.erase(clouds->layers.begin() + static_cast<std::ptrdiff_t>(i));
      edited = true;
    } else {
      ++i;
    }
  }
  if (ImGui::Button("Add layer")) {
    clouds->layers.push_back(clouds->layers.empty() ? CloudLayerSettings{} : clouds->layers.back());
    edited = true;
  }
  ImGui::TextUnformatted("Draw");
  for (uint32_t mode = 0; mode < ATMO_CLOUD_DRAW_MODE_COUNT; ++mode) {
    char name[32];
    std::snprintf(name, sizeof name, "%s", cloud_draw_mode_name(mode) ? cloud_draw_mode_name(mode) : "");
    if (!*name) std::snprintf(name, sizeof name, "mode %u", mode);
    ImGui::SameLine();
    if (ImGui::RadioButton(name, clouds->draw_mode == mode)) {
      clouds->draw_mode = static_cast<AtmoCloudDrawMode>(mode);
      edited = true;
    }
  }
  ImGui::TextUnformatted("Layer quality");
  for (uint32_t q = 0; q < ATMO_CLOUD_QUALITY_COUNT; ++q) {
    ImGui::SameLine();
    // The view's knob: takes effect on the next frame, no Apply needed.
    if (ImGui::RadioButton(cloud_quality_name(q), clouds->quality == q))
      clouds->quality = static_cast<AtmoCloudQuality>(q);
  }
  int divisor = static_cast<int>(clouds->march_resolution_divisor);
  if (ImGui::SliderInt("March divisor", &divisor, 1, 8)) {
    clouds->march_resolution_divisor = static_cast<uint32_t>(divisor);
    edited = true;
  }
  panel->clouds_edited |= edited;
  panel->apply_clouds = ImGui::Button("Apply");
  if (panel->clouds_edited) {
    ImGui::SameLine();
    ImGui::TextDisabled("edited, not applied");
  }
  if (!panel->clouds_message.empty()) {
    const ImVec4 colour = panel->clouds_ok ? ImVec4(0.6f, 0.9f, 0.6f, 1.0f) : ImVec4(1.0f, 0.35f, 0.3f, 1.0f);
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextColored(colour, "%s", panel->clouds_message.c_str());
    ImGui::PopTextWrapPos();
  }
  ImGui::PopItemWidth();
  ImGui::End();
}

void draw_panel(const SampleRenderer& renderer, const FrameReport& report, FlyCamera* fly, PanelState* panel,
                SceneSettings* s) {
  ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(460, 0), ImGuiCond_FirstUseEver);
  ImGui::Begin("Atmo");
  ImGui::PushItemWidth(-160.0f);  // room for the labels
  const AtmoPluginApi& api = renderer.api();
  ImGui::Text("%s %u.%u.%u, interface %u", api.plugin_name, api.plugin_version >> 16,
              (api.plugin_version >> 8) & 0xff, api.plugin_version & 0xff, api.interface_version);

  if (ImGui::CollapsingHeader("Time (UTC)", ImGuiTreeNodeFlags_DefaultOpen)) {
    const double days = std::floor(s->utc_posix_s / 86400.0);
    float hours = static_cast<float>((s->utc_posix_s - days * 86400.0) / 3600.0);
    std::int64_t year = 0;
    unsigned month = 0, day = 0;
    core::astro::civil_from_days(static_cast<std::int64_t>(days), &year, &month, &day);
    int ymd[3] = {static_cast<int>(year), static_cast<int>(month), static_cast<int>(day)};
    bool changed = ImGui::InputInt3("Date Y-M-D", ymd);
    changed |= ImGui::SliderFloat("Time of day (h)", &hours, 0.0f, 24.0f, "%.2f");
    if (changed) {
      ymd[1] = std::clamp(ymd[1], 1, 12);
      ymd[2] = std::clamp(ymd[2], 1, static_cast<int>(core::astro::days_in_month(ymd[0], static_cast<unsigned>(ymd[1]))));
      s->utc_posix_s = static_cast<double>(core::astro::days_from_civil(ymd[0], static_cast<unsigned>(ymd[1]),
                                                                        static_cast<unsigned>(ymd[2]))) *
                           86400.0 +
                       hours * 3600.0;
    }
    ImGui::Checkbox("Animate", &panel->animate_time);
    ImGui::SameLine();
    ImGui::SliderFloat("Rate", &panel->time_rate, 1.0f, 7200.0f, "%.0fx", ImGuiSliderFlags_Logarithmic);
    ImGui::Text("%s", format_utc(s->utc_posix_s).c_str());
  }

  if (ImGui::CollapsingHeader("Place", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::InputDouble("Latitude (deg)", &s->origin.latitude_deg, 0.1, 1.0, "%.4f");
    ImGui::InputDouble("Longitude (deg)", &s->origin.longitude_deg, 0.1, 1.0, "%.4f");
    s->origin.latitude_deg = std::clamp(s->origin.latitude_deg, -90.0, 90.0);
    s->origin.longitude_deg = std::remainder(s->origin.longitude_deg, 360.0);
    ImGui::InputDouble("Airfield height (m)", &s->origin.height_m, 10.0, 100.0, "%.1f");
    hs::ViewSetup view;
    view.world_origin = s->origin;
    view.pose = s->pose;
    const hs::Geodetic eye = hs::eye_geodetic(view);
    double eye_height = eye.height_m;
    if (ImGui::InputDouble("Eye height (m)", &eye_height, 10.0, 1000.0, "%.1f")) {
      s->pose.position_enu_m.z += eye_height - eye.height_m;
    }
    ImGui::Text("Eye %.5f, %.5f deg", eye.latitude_deg, eye.longitude_deg);
    ImGui::Text("Sun elevation %.2f deg, azimuth %.2f deg", glm::degrees(report.lighting.sun_elevation_rad),
                glm::degrees(report.lighting.sun_azimuth_rad));
  }

  if (ImGui::CollapsingHeader("Air and camera", ImGuiTreeNodeFlags_DefaultOpen)) {
    float visibility = static_cast<float>(s->visibility_m);
    if (ImGui::SliderFloat("Visibility (m)", &visibility, 50.0f, 500000.0f, "%.0f", ImGuiSliderFlags_Logarithmic)) {
      s->visibility_m = visibility;
    }
    // Ground fog by its RVR (set_fog on each change: cheap once its phase function's tables exist).
    bool fog = s->fog_visibility_m > 0.0;
    if (ImGui::Checkbox("Fog", &fog)) s->fog_visibility_m = fog ? panel->rvr_m : 0.0;
    ImGui::SameLine();
    ImGui::BeginDisabled(!fog);
    float rvr = static_cast<float>(fog ? s->fog_visibility_m : panel->rvr_m);
    if (ImGui::SliderFloat("RVR (m)", &rvr, static_cast<float>(kRvrMinM), static_cast<float>(kRvrMaxM), "%.0f",
                           ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp)) {
      panel->rvr_m = rvr;
      s->fog_visibility_m = rvr;
    }
    float top = static_cast<float>(s->fog_top_m);
    if (ImGui::SliderFloat("Fog top (m)", &top, 1.0f, 3000.0f, "%.0f", ImGuiSliderFlags_Logarithmic))
      s->fog_top_m = top;
    ImGui::EndDisabled();
    float ev = static_cast<float>(s->ev100);
    if (ImGui::SliderFloat("Exposure EV100", &ev, -6.0f, 18.0f, "%.1f")) s->ev100 = ev;
    ImGui::TextUnformatted("Depth");
    for (hs::DepthConvention c :
         {hs::DepthConvention::Standard, hs::DepthConvention::Reversed, hs::DepthConvention::Logarithmic}) {
      ImGui::SameLine();
      ImGui::BeginDisabled(!hs::depth_convention_supported(c));
      if (ImGui::RadioButton(hs::to_string(c), s->depth_convention == c)) s->depth_convention = c;
      ImGui::EndDisabled();
    }
    float speed = static_cast<float>(fly->speed_m_s);
    if (ImGui::SliderFloat("Speed (m/s)", &speed, 1.0f, 3000.0f, "%.0f", ImGuiSliderFlags_Logarithmic)) {
      fly->speed_m_s = speed;
    }
    const glm::dvec3& p = s->pose.position_enu_m;
    ImGui::Text("ENU %.0f %.0f %.0f m, heading %.1f, pitch %.1f", p.x, p.y, p.z, s->pose.heading_deg,
                s->pose.pitch_deg);
    if (ImGui::Button("Back to the approach")) s->pose = approach_path(0.0);
    ImGui::TextDisabled("WASD move, Q/E down/up, drag to look, shift 10x");
  }

  if (ImGui::CollapsingHeader("Objects", ImGuiTreeNodeFlags_DefaultOpen)) {
    // The apron's objects (as --objects apron): drawn by the host; their sky occlusion through set_occluders,
    // ATMO_PASS_SKY_OCCLUSION over the terrain and atmo_sky_occlusion.glsl on the objects.
    ImGui::BeginDisabled(!renderer.objects_loaded());
    bool apron = s->objects == ObjectsChoice::Apron;
    if (ImGui::Checkbox("Objects on the apron", &apron)) s->objects = apron ? ObjectsChoice::Apron : ObjectsChoice::None;
    ImGui::SameLine();
    if (ImGui::Button("To the apron")) s->pose = apron_view();
    ImGui::BeginDisabled(!apron);
    ImGui::Checkbox("Object shadows (sky occlusion)", &s->object_shadows);
    ImGui::SameLine();
    ImGui::BeginDisabled(!s->object_shadows);
    ImGui::Checkbox("Bounce", &s->object_bounce);
    ImGui::EndDisabled();
    ImGui::EndDisabled();
    ImGui::EndDisabled();
    if (!panel->objects_error.empty()) {
      ImGui::PushTextWrapPos(0.0f);
      ImGui::TextColored(ImVec4(1.0f, 0.35f, 0.3f, 1.0f), "%s", panel->objects_error.c_str());
      ImGui::PopTextWrapPos();
    }
    if (apron) {
      const auto shown_ms = [&](int section) {
        return panel->finish_sections ? panel->smoothed_wall_ms[static_cast<size_t>(section)]
                                      : panel->smoothed_ms[static_cast<size_t>(section)];
      };
      ImGui::Text("%zu objects, %u occluders, one driving (set_occluder_poses each frame)", apron_objects().size(),
                  report.occluders);
      ImGui::Text("%s: sky occlusion pass %.2f ms, objects %.2f ms", panel->finish_sections ? "to glFinish" : "GPU",
                  shown_ms(kSectionSkyOcclusion), shown_ms(kSectionObjects));
      if (!std::isnan(report.sky_occlusion_cpu_ms))
        ImGui::Text("get_sky_occlusion %.2f ms CPU, longest tile list %u", report.sky_occlusion_cpu_ms,
                    report.longest_tile_list);
    }
  }

  if (ImGui::CollapsingHeader("Lights", ImGuiTreeNodeFlags_DefaultOpen)) {
    // set_lights when the choice changes: group 0 the runway or the airport, group 1 the town.
    for (LightsChoice c : kLightsChoices) {
      if (c != kLightsChoices[0]) ImGui::SameLine();
      if (ImGui::RadioButton(lights_choice_name(c), s->lights == c)) s->lights = c;
    }
    ImGui::BeginDisabled(s->lights != LightsChoice::AirportTown);
    // The slider follows the drag; the town is laid and sent on release (set_lights of group 1).
    if (!ImGui::IsAnyItemActive()) panel->town_slider = static_cast<int>(s->town_lights);
    ImGui::SliderInt("Town lights", &panel->town_slider, 100, static_cast<int>(max_town_lights()), "%d",
                     ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp);
    if (ImGui::IsItemDeactivatedAfterEdit()) s->town_lights = static_cast<uint32_t>(panel->town_slider);
    ImGui::EndDisabled();
    ImGui::Text("%u lights sent (group 0: %u, group 1: %u)", report.lights_sent, report.group_lights[0],
                report.group_lights[1]);
    ImGui::Text("terrain lit by %u (get_fog_lighting %.2f ms CPU)", report.fog_lighting.light_count,
                panel->smoothed_fog_lighting_ms);
    const auto shown_ms = [&](int section) {
      return panel->finish_sections ? panel->smoothed_wall_ms[static_cast<size_t>(section)]
                                    : panel->smoothed_ms[static_cast<size_t>(section)];
    };
    ImGui::Text("%s: light glows %.2f ms, light points %.2f ms, terrain %.2f ms",
                panel->finish_sections ? "to glFinish" : "GPU", shown_ms(kSectionLightGlows),
                shown_ms(kSectionLightPoints), shown_ms(kSectionTerrain));
    // The plugin's own counts (its debug log lines): what each light pass culled, merged and drew.
    ImGui::PushTextWrapPos(0.0f);
    for (const std::string& line : report.light_debug)
      if (!line.empty()) ImGui::TextDisabled("%s", line.c_str());
    ImGui::PopTextWrapPos();
  }

  // With each section finished, a column of their wall times to glFinish.
  const bool wall_column = panel->finish_sections;
  if (ImGui::CollapsingHeader("GPU time per pass", ImGuiTreeNodeFlags_DefaultOpen) &&
      ImGui::BeginTable("timings", wall_column ? 4 : 3)) {
    ImGui::TableSetupColumn("section", ImGuiTableColumnFlags_WidthFixed, 140.0f);
    ImGui::TableSetupColumn("ms", ImGuiTableColumnFlags_WidthFixed, 90.0f);
    if (wall_column) ImGui::TableSetupColumn("to glFinish", ImGuiTableColumnFlags_WidthFixed, 90.0f);
    ImGui::TableSetupColumn("result", ImGuiTableColumnFlags_WidthStretch);
    if (wall_column) ImGui::TableHeadersRow();
    double total = 0.0, wall_total = 0.0;
    for (int i = 0; i < kSectionCount; ++i) {
      const double ms = panel->smoothed_ms[static_cast<size_t>(i)];
      const double wall = panel->smoothed_wall_ms[static_cast<size_t>(i)];
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(section_name(i));
      ImGui::TableNextColumn();
      if (std::isnan(ms)) {
        ImGui::TextUnformatted("-");
      } else {
        ImGui::Text("%.3f ms", ms);
        total += ms;
      }
      if (wall_column) {
        ImGui::TableNextColumn();
        if (!std::isnan(wall)) {
          ImGui::Text("%.3f ms", wall);
          wall_total += wall;
        }
      }
      ImGui::TableNextColumn();
      if (section_pass(i) >= 0) {
        const AtmoResult r = report.pass_results[static_cast<size_t>(section_pass(i))];
        const char* name = r == INT32_MIN ? "not run" : renderer.api().result_string(r);
        ImGui::TextDisabled("%s", std::strncmp(name, "ATMO_", 5) == 0 ? name + 5 : name);
      }
    }
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::TextUnformatted("GPU total");
    ImGui::TableNextColumn();
    ImGui::Text("%.3f ms", total);
    if (wall_column) {
      ImGui::TableNextColumn();
      ImGui::Text("%.3f ms", wall_total);
    }
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::TextUnformatted("CPU frame");
    ImGui::TableNextColumn();
    ImGui::Text("%.3f ms", panel->smoothed_cpu_ms);
    if (wall_column) ImGui::TableNextColumn();
    ImGui::TableNextColumn();
    ImGui::TextDisabled("%.1f fps", ImGui::GetIO().Framerate);
    ImGui::EndTable();
    ImGui::Checkbox("Finish each section (glFinish: its wall time; stalls)", &panel->finish_sections);
    // A software rasteriser defers drawing, so timer queries credit one pass with another's work.
    const char* gl_renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    if (gl_renderer && std::strstr(gl_renderer, "llvmpipe"))
      ImGui::TextDisabled("llvmpipe defers rasterisation: per-pass GPU times shift\nbetween passes (the total is "
                          "right); finish each section\nfor each one's own");
  }
  ImGui::PopItemWidth();

  if (!panel->errors.empty()) {
    ImGui::Separator();
    for (const std::string& e : panel->errors) ImGui::TextColored(ImVec4(1.0f, 0.35f, 0.3f, 1.0f), "%s", e.c_str());
  }
  ImGui::End();
  draw_weather(panel, &s->clouds);
}

}  // namespace

int run_window(const Options& options, SceneSettings settings) {
  glfwSetErrorCallback(glfw_error);
  if (!glfwInit()) {
    std::fprintf(stderr, "atmo-sample-host: glfwInit failed (no display? use --frames N --out DIR)\n");
    return 2;
  }
  Window window;
  window.handle = create_window(options.width, options.height);
  if (!window.handle) {
    std::fprintf(stderr, "atmo-sample-host: no GL 4.5 or 3.3 core context\n");
    return 2;
  }
  glfwMakeContextCurrent(window.handle);
  glfwSwapInterval(1);
  if (!gladLoadGL(glfwGetProcAddress)) {
    std::fprintf(stderr, "atmo-sample-host: glad could not load GL\n");
    return 2;
  }
  std::printf("GL %s, %s\n", reinterpret_cast<const char*>(glGetString(GL_VERSION)),
              reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
  fall_back_depth_convention(&settings);

  std::unique_ptr<SampleRenderer> renderer;
  try {
    renderer = std::make_unique<SampleRenderer>(options.plugin_path, &glfw_proc_address, options.verbose);
  } catch (const atmo::Error& e) {
    std::fprintf(stderr, "atmo-sample-host: %s\n", e.what());
    return 1;
  }
  std::string error;
  if (!renderer->gl_init(settings.seed, &error)) {
    std::fprintf(stderr, "atmo-sample-host: gl_init: %s\n", error.c_str());
    renderer->gl_shutdown();
    return 1;
  }
  // The apron's objects, read once (the panel turns them on and off); asked for and missing: a setup failure.
  std::string objects_error;
  if (!renderer->load_objects(options.objects_dir, &objects_error)) {
    if (settings.objects != ObjectsChoice::None) {
      std::fprintf(stderr, "atmo-sample-host: --objects %s: %s\n", objects_choice_name(settings.objects),
                   objects_error.c_str());
      renderer->gl_shutdown();
      return 2;
    }
    objects_error = "objects: " + objects_error;
  }

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the working directory
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window.handle, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");

  FlyCamera fly;
  PanelState panel;
  panel.smoothed_ms.fill(std::nan(""));
  panel.smoothed_wall_ms.fill(std::nan(""));
  if (settings.fog_visibility_m > 0.0) panel.rvr_m = settings.fog_visibility_m;
  panel.objects_error = objects_error;
  panel.apply_clouds = !settings.clouds.layers.empty();  // the command line's layers
  FrameReport report;
  std::string last_printed;
  double last_time = glfwGetTime();
  uint64_t frame = 0;
  int status = 0;
  while (!glfwWindowShouldClose(window.handle)) {
    glfwPollEvents();
    const double now = glfwGetTime();
    const double dt = std::min(now - last_time, 0.25);
    last_time = now;

    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    update_camera(window.handle, renderer->terrain(), dt, &fly, &settings.pose);
    if (panel.animate_time) settings.utc_posix_s += dt * panel.time_rate;
    if (panel.apply_clouds) {
      // Blocks the window while the plugin generates the layers (seconds for large ones).
      panel.clouds_ok = renderer->set_clouds(settings, &panel.clouds_message);
      panel.clouds_edited = false;
      std::fprintf(panel.clouds_ok ? stdout : stderr, "%s%s\n", panel.clouds_ok ? "" : "atmo-sample-host: ",
                   panel.clouds_message.c_str());
      if (!panel.clouds_ok) status = 1;
    }
    draw_panel(*renderer, report, &fly, &panel, &settings);
    ImGui::Render();

    int width = 0, height = 0;
    glfwGetFramebufferSize(window.handle, &width, &height);
    report = renderer->render_frame(settings, frame++, 0, width, height, false, panel.finish_sections);
    // Smoothed for reading; a section that stops running shows "-" at once.
    const auto smooth = [](double ms, double* shown) {
      *shown = std::isnan(ms) ? ms : (std::isnan(*shown) ? ms : 0.9 * *shown + 0.1 * ms);
    };
    for (size_t i = 0; i < report.gpu_ms.size(); ++i) {
      smooth(report.gpu_ms[i], &panel.smoothed_ms[i]);
      smooth(report.wall_ms[i], &panel.smoothed_wall_ms[i]);
    }
    panel.smoothed_cpu_ms = 0.9 * panel.smoothed_cpu_ms + 0.1 * report.cpu_ms;
    smooth(report.fog_lighting_ms, &panel.smoothed_fog_lighting_ms);
    if (!report.errors.empty()) {
      panel.errors = report.errors;
      status = 1;
      if (report.errors.front() != last_printed) {  // once per distinct message, not every frame
        last_printed = report.errors.front();
        for (const std::string& e : report.errors) std::fprintf(stderr, "atmo-sample-host: %s\n", e.c_str());
      }
    }

    if (width > 0 && height > 0) {
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      glViewport(0, 0, width, height);
      ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    }
    const bool last = options.exit_after > 0 && frame >= static_cast<uint64_t>(options.exit_after);
    const bool closing = last || glfwWindowShouldClose(window.handle);
    if (closing && !options.screenshot.empty() && width > 0 && height > 0 &&
        !write_screenshot(options.screenshot, width, height)) {
      status = 2;
    }
    glfwSwapBuffers(window.handle);
    if (last) break;
  }

  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  renderer->gl_shutdown();
  renderer.reset();
  return status;
}

}  // namespace atmo::sample
