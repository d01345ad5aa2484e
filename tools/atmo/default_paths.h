// default_paths.h — the plugin and the star catalogue an `atmo` run takes when
// none is named: an installed atmo's own (<prefix>/bin/atmo ->
// <prefix>/lib/atmo/libatmo.so, <prefix>/share/atmo/stars/...), else the
// build tree's it was built with.
#pragma once

#include <string>

namespace atmo::cli {

std::string default_plugin_path();
std::string default_star_catalog_path();

}  // namespace atmo::cli
