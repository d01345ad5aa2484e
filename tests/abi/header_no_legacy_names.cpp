// A host whose own render-pass class is called AtmoPass: with ATMO_NO_LEGACY_NAMES the headers leave the
// name to it (AtmoPassKind is the plugin's). Without the define this file does not compile.
#define ATMO_NO_LEGACY_NAMES
#include "atmo/atmo.h"
#include "atmo/atmo.hpp"

class AtmoPass {
 public:
  explicit AtmoPass(AtmoPassKind kind) : kind_(kind) {}
  AtmoPassKind kind() const { return kind_; }

 private:
  AtmoPassKind kind_;
};

int atmo_host_pass_compiles() { return static_cast<int>(AtmoPass(ATMO_PASS_SKY).kind()); }
