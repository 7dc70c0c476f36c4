// The run configuration of a walkthrough command: what its options (options.hpp) ask a
// frame runner to do.
#pragma once

#include <string>

#include "cli/frame_runner.hpp"
#include "cli/options.hpp"
#include "scene/prepare.hpp"

namespace logrid::samples {

// Whether a method name needs the DDO octree.
bool needsDdo(const std::string& method);

// The run configuration from the options (method, view, tile, reader, depth ...). Throws
// logrid::Error(InvalidArgument) for settings that do not go together, as the library's
// validators (validateCullerDesc() ...) judge them, naming the setting.
RunConfig runConfig(const WalkOptions& o, const PreparedScene& scene);

}  // namespace logrid::samples
