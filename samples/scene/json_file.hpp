// Reading a JSON file's text, bounded, for the scene library's parsers (camera paths,
// motion files): a hostile or mistaken path (a huge file, a device, a pipe) is refused
// rather than slurped into memory.
#pragma once

#include <cstddef>
#include <string>

namespace logrid::samples {

// The text of the file at `path`, at most `max_bytes` of it. Throws logrid::Error, its
// message `prefix` followed by what failed and what to do:
//   ErrorCode::Environment: a directory, no such file, no permission, a failed read;
//   ErrorCode::BadInput:    larger than max_bytes ("is larger than N MiB", then
//                           "; " and `too_large_hint` unless that is empty).
std::string readBoundedFile(const std::string& path, const std::string& prefix,
                            std::size_t max_bytes, const std::string& too_large_hint);

}  // namespace logrid::samples
