#include "scene/json_file.hpp"

#include <filesystem>
#include <fstream>
#include <system_error>

#include "logrid/error.hpp"

namespace logrid::samples {

std::string readBoundedFile(const std::string& path, const std::string& prefix,
                            std::size_t max_bytes, const std::string& too_large_hint) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw Error(ErrorCode::Environment, prefix + "is a directory; pass a .json file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const bool exists = std::filesystem::exists(path, ec);
    throw Error(ErrorCode::Environment,
                prefix + (exists ? "cannot open the file for reading; check its permissions"
                                 : "no such file; check the path"));
  }
  // Read at most one chunk past the limit, so that neither a huge file nor an endless
  // one (a device, a pipe) is slurped into memory.
  std::string text;
  char chunk[1 << 16];
  while (text.size() <= max_bytes) {
    in.read(chunk, sizeof chunk);
    text.append(chunk, static_cast<std::size_t>(in.gcount()));
    if (!in) break;
  }
  if (in.bad()) {
    throw Error(ErrorCode::Environment, prefix + "reading the file failed; check the file");
  }
  if (text.size() > max_bytes) {
    throw Error(ErrorCode::BadInput, prefix + "is larger than " + std::to_string(max_bytes >> 20) +
                                         " MiB" +
                                         (too_large_hint.empty() ? "" : "; " + too_large_hint));
  }
  return text;
}

}  // namespace logrid::samples
