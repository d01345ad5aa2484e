// flight.h — a scenario's flight as frames: where the eye is, what time it is
// and which events fire at frame k (docs/MULTI_CHANNEL.md). Pure (no GL, no
// MPI); rank 0 of atmo-channels computes each frame's FrameState from it and
// broadcasts that, never the scenario.
#pragma once

#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include <glm/glm.hpp>

#include "atmo_scenario/scenario.h"

namespace atmo::channels {

// A keyframe with its position in the ENU frame at the scenario's location.
struct Keyframe {
  double t_s = 0.0;
  glm::dvec3 enu_m{0.0};
  double heading_deg = 0.0;
  double pitch_deg = 0.0;
};

// The run's flight: the file's "flight", or, without one, a still at the first camera's pose.
struct FlightPlan {
  double frame_rate_hz = 60.0;
  std::int64_t frames = 1;
  std::vector<Keyframe> keyframes;  // at least one, t_s increasing
};

FlightPlan flight_plan_of(const scenario::Scenario& s);

struct EyePose {
  glm::dvec3 enu_m{0.0};
  double heading_deg = 0.0;
  double pitch_deg = 0.0;
};

// The keyframes' linear interpolation at t_s (position, heading and pitch as written), held before the first
// keyframe and after the last.
EyePose eye_at(const std::vector<Keyframe>& keyframes, double t_s);

// The most events that may fire at one frame (FrameState's fixed array).
inline constexpr int kMaxEventsPerFrame = 32;

// The indices (into scenario.flight->events, in file order) of the events at frame k.
std::vector<int> events_at(const scenario::Scenario& s, std::int64_t frame);

// "" or why the flight cannot be run (more than kMaxEventsPerFrame events at one frame).
std::string flight_error(const scenario::Scenario& s);

// One frame as rank 0 broadcasts it (MPI_Bcast of its bytes: a fixed-size POD, the same layout on every rank
// of one build). Every rank read the same scenario; events are indices into its flight's events.
struct FrameState {
  std::uint64_t frame = 0;       // AtmoFrameState.host_frame_number
  double t_s = 0.0;              // frame / frame_rate_hz
  double utc_posix_s = 0.0;      // the scenario's utc + t_s
  double dut1_s = 0.0;
  double eye_enu_m[3] = {0, 0, 0};
  double heading_deg = 0.0;
  double pitch_deg = 0.0;
  double exposure_scale = 1.0;   // the 8-bit encoding's (host side only): fixed for the flight
  std::int32_t save = 0;         // 1: write this frame's images
  std::int32_t event_count = 0;
  std::int32_t events[kMaxEventsPerFrame] = {};
};
static_assert(std::is_trivially_copyable_v<FrameState>, "FrameState is broadcast as bytes");

// Frame k of the flight (save and exposure_scale left to the caller).
FrameState frame_state(const scenario::Scenario& s, const FlightPlan& plan, std::int64_t frame);

}  // namespace atmo::channels
