// The first message a page gets, live or from a replay file (tools/view/PROTOCOL.md, "hello").
#pragma once

#include <string>

namespace sear {

struct ProjectDesc;

// mode: "live" or "replay".
std::string view_hello_json(const ProjectDesc& project, const std::string& mode);

}  // namespace sear
