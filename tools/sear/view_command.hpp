// Where this build of `sear` finds the viewer's page and three.js, for `sear view` and `sear run --view`.
#pragma once

#include <string>

#include "view/view_server.hpp"

namespace sear {

// The page from the source tree this was built from, else share/sear/view beside the binary's
// folder (an installed copy); three.js from Debian's libjs-three.
ViewServerOptions view_server_options(const std::string& bind, int port);

}  // namespace sear
