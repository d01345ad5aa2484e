#include "flight.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "atmo_host_scene/camera.h"

namespace atmo::channels {

namespace sc = atmo::scenario;
namespace hs = atmo::host_scene;

namespace {

glm::dvec3 enu_of(const sc::Scenario& s, const sc::Position& p) {
  if (p.kind == sc::Position::Kind::Enu) return {p.enu_m[0], p.enu_m[1], p.enu_m[2]};
  const hs::Geodetic origin{s.location.latitude_deg, s.location.longitude_deg, s.location.height_m};
  return hs::enu_from_geodetic(origin, {p.geodetic.latitude_deg, p.geodetic.longitude_deg, p.geodetic.height_m});
}

}  // namespace

FlightPlan flight_plan_of(const sc::Scenario& s) {
  FlightPlan plan;
  if (s.flight) {
    plan.frame_rate_hz = s.flight->frame_rate_hz;
    plan.frames = s.flight->frames;
    for (const sc::FlightKeyframe& k : s.flight->keyframes)
      plan.keyframes.push_back({k.t_s, enu_of(s, k.position), k.heading_deg, k.pitch_deg});
  } else {
    const sc::Camera& c = s.cameras.front();
    plan.keyframes.push_back({0.0, enu_of(s, c.position), c.heading_deg, c.pitch_deg});
  }
  return plan;
}

EyePose eye_at(const std::vector<Keyframe>& keys, double t_s) {
  auto pose_of = [](const Keyframe& k) { return EyePose{k.enu_m, k.heading_deg, k.pitch_deg}; };
  if (keys.empty()) return {};
  if (t_s <= keys.front().t_s) return pose_of(keys.front());
  if (t_s >= keys.back().t_s) return pose_of(keys.back());
  // The segment [a, b] holding t_s.
  const auto b = std::upper_bound(keys.begin(), keys.end(), t_s, [](double t, const Keyframe& k) { return t < k.t_s; });
  const Keyframe& k1 = *b;
  const Keyframe& k0 = *(b - 1);
  const double u = (t_s - k0.t_s) / (k1.t_s - k0.t_s);
  EyePose p;
  p.enu_m = k0.enu_m + u * (k1.enu_m - k0.enu_m);
  p.heading_deg = k0.heading_deg + u * (k1.heading_deg - k0.heading_deg);
  p.pitch_deg = k0.pitch_deg + u * (k1.pitch_deg - k0.pitch_deg);
  return p;
}

std::vector<int> events_at(const sc::Scenario& s, std::int64_t frame) {
  std::vector<int> out;
  if (!s.flight) return out;
  for (size_t i = 0; i < s.flight->events.size(); ++i)
    if (s.flight->events[i].at_frame == frame) out.push_back(static_cast<int>(i));
  return out;
}

std::string flight_error(const sc::Scenario& s) {
  if (!s.flight) return "";
  std::map<std::int64_t, int> per_frame;
  for (const sc::FlightEvent& e : s.flight->events) {
    if (++per_frame[e.at_frame] > kMaxEventsPerFrame)
      return "more than " + std::to_string(kMaxEventsPerFrame) + " events at frame " + std::to_string(e.at_frame);
  }
  return "";
}

FrameState frame_state(const sc::Scenario& s, const FlightPlan& plan, std::int64_t frame) {
  FrameState f;
  f.frame = static_cast<std::uint64_t>(frame);
  f.t_s = static_cast<double>(frame) / plan.frame_rate_hz;
  f.utc_posix_s = s.utc_posix_s + f.t_s;
  f.dut1_s = s.dut1_s;
  const EyePose eye = eye_at(plan.keyframes, f.t_s);
  for (int k = 0; k < 3; ++k) f.eye_enu_m[k] = eye.enu_m[k];
  f.heading_deg = eye.heading_deg;
  f.pitch_deg = eye.pitch_deg;
  const std::vector<int> events = events_at(s, frame);
  f.event_count = static_cast<std::int32_t>(std::min<size_t>(events.size(), kMaxEventsPerFrame));
  for (int i = 0; i < f.event_count; ++i) f.events[i] = events[i];
  return f;
}

}  // namespace atmo::channels
