// Atmo::cigi from an installed prefix: encode an IG Control and an Atmosphere Control, decode them back.
#include <atmo/cigi.h>

#include <cstdio>

int main() {
  using namespace atmo::cigi;
  AtmosphereControl air;
  air.visibility_m = 4000.0f;
  const auto bytes = encode(Version{3, 3}, ByteOrder::Big, {IgControl{}, air});
  const DecodeResult d = decode(bytes);
  if (!d.ok() || d.events.size() != 2 || std::get<AtmosphereControl>(d.events[1]).visibility_m != 4000.0f) {
    std::fprintf(stderr, "CIGI round trip failed: %s\n", d.ok() ? "wrong events" : d.error->message.c_str());
    return 1;
  }
  std::printf("CIGI 3.3 round trip: %zu bytes, visibility %.0f m\n", bytes.size(),
              static_cast<double>(std::get<AtmosphereControl>(d.events[1]).visibility_m));
  return 0;
}
