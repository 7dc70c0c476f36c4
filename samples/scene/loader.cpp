// Scenes from model files through assimp (see loader.hpp): the import.
//
// The loader treats every file as hostile, because assimp 5.2 does not: small corruptions
// of ordinary files make it hang, abort or overflow its stack or heap, or import wrong
// geometry without a word (tests/fuzz/loader_fuzz_test.cpp found them). But it loads
// whatever assimp reads correctly, however loosely the file follows its format. So the
// loader
//  * checks the file before assimp sees it (exists, regular, size limit), and lets only
//    the importers that claim the file's extension look at it;
//  * refuses beforehand the PLY and glTF files that assimp is known to hang or crash on
//    or to mis-read (loader_ply.cpp, loader_gltf.cpp), and warns about the ones it reads
//    correctly although they bend their format;
//  * bounds what assimp may open besides the file (material libraries, buffers);
//  * checks assimp's raw output before its post-processing runs on it, and the result
//    after, since its own validation misses NaNs and empty faces
//    (loader_assimp_scene.cpp);
//  * converts every exception into a logrid::Error.
#include "scene/loader.hpp"

#include <cctype>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <new>
#include <set>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "logrid/error.hpp"
#include "scene/loader_detail.hpp"

#if defined(LOGRID_HAVE_ASSIMP) && LOGRID_HAVE_ASSIMP
#include <assimp/BaseImporter.h>
#include <assimp/DefaultIOSystem.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>
#define LOGRID_LOADER_ASSIMP 1
#else
#define LOGRID_LOADER_ASSIMP 0
#endif

namespace logrid::samples {

namespace load {

void fail(ErrorCode code, const std::string& path, const std::string& what) {
  throw Error(code, path + ": " + what);
}

std::string lowerCase(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace load

#if LOGRID_LOADER_ASSIMP

namespace {

namespace fs = std::filesystem;
using load::fail;
using load::lowerCase;

// Everything that can be decided without parsing: the file exists, is a readable
// regular file, is not empty and not above the size limit. Doing this ourselves gives
// the user a precise message instead of assimp's generic "Unable to open file".
void checkFile(const std::string& path, const LoadOptions& options) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::exists(status)) {
    fail(ErrorCode::Environment, path,
         "no such file" + (ec ? " (" + ec.message() + ")" : std::string()));
  }
  if (fs::is_directory(status)) {
    fail(ErrorCode::Environment, path, "is a directory, not a model file");
  }
  if (!fs::is_regular_file(status)) {
    fail(ErrorCode::Environment, path, "is not a regular file (a device, pipe or socket?)");
  }
  const std::uintmax_t bytes = fs::file_size(path, ec);
  if (ec) fail(ErrorCode::Environment, path, "cannot read its size (" + ec.message() + ")");
  if (bytes > options.max_file_bytes) {
    std::ostringstream out;
    out << "is " << bytes << " bytes, more than the limit of " << options.max_file_bytes
        << " bytes (LoadOptions::max_file_bytes)";
    fail(ErrorCode::BadInput, path, out.str());
  }
  if (!std::ifstream(path, std::ios::binary)) {
    fail(ErrorCode::Environment, path, "cannot be opened for reading (permissions?)");
  }
  if (bytes == 0) fail(ErrorCode::BadInput, path, "is empty");
}

// Assimp opens more than the file it is given (OBJ material libraries, glTF buffers,
// ...), by names taken from the file. This refuses writes, non-regular files (a buffer
// named /dev/zero or a FIFO would hang the import) and files above the size limit.
class BoundedIOSystem : public Assimp::DefaultIOSystem {
 public:
  explicit BoundedIOSystem(std::uint64_t max_bytes) : max_bytes_(max_bytes) {}

  using Assimp::DefaultIOSystem::Open;
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    if (file == nullptr || mode == nullptr) return nullptr;
    if (std::string(mode).find_first_of("wa+") != std::string::npos) return nullptr;
    std::error_code ec;
    if (!fs::is_regular_file(file, ec) || ec) return nullptr;
    const std::uintmax_t bytes = fs::file_size(file, ec);
    if (ec || bytes > max_bytes_) return nullptr;
    return Assimp::DefaultIOSystem::Open(file, mode);
  }

 private:
  std::uint64_t max_bytes_;
};

// Leaves registered only the importers that claim the file's extension, and refuses
// files that no importer claims. When several importers claim an extension (.gltf,
// .glb, .xml, ...) and none accepts the content, assimp would otherwise try every
// importer it has on it by signature: a file named .gltf could reach any of ~50
// parsers, some with known hangs (a .gltf holding a PLY header without end_header
// loops forever). The match is on the end of the name, as assimp does, so
// double extensions such as .mesh.xml keep their importer.
void restrictImporters(const std::string& path, Assimp::Importer& importer) {
  const std::string name = lowerCase(fs::path(path).filename().string());
  auto claims = [&](Assimp::BaseImporter& candidate) {
    std::set<std::string> extensions;
    candidate.GetExtensionList(extensions);
    for (const std::string& extension : extensions) {
      const std::string suffix = "." + lowerCase(extension);
      if (name.size() > suffix.size() &&
          name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
        return true;
      }
    }
    return false;
  };
  std::vector<Assimp::BaseImporter*> others;
  bool claimed = false;
  for (std::size_t i = 0; i < importer.GetImporterCount(); ++i) {
    Assimp::BaseImporter* candidate = importer.GetImporter(i);
    if (candidate == nullptr) continue;
    if (claims(*candidate)) {
      claimed = true;
    } else {
      others.push_back(candidate);
    }
  }
  if (!claimed) {
    std::string known;
    importer.GetExtensionList(known);
    const std::string extension = fs::path(path).extension().string();
    fail(ErrorCode::BadInput, path,
         (extension.empty() ? std::string("has no file extension")
                            : "has an unknown extension '" + extension + "'") +
             "; cannot tell its format (assimp reads " + known + ")");
  }
  for (Assimp::BaseImporter* other : others) {
    // UnregisterLoader hands ownership back to the caller.
    if (importer.UnregisterLoader(other) == AI_SUCCESS) delete other;
  }
}

Scene loadWithAssimp(const std::string& path, const LoadOptions& options) {
  checkFile(path, options);
  const load::Warn warn = [&](const std::string& message) {
    if (options.warn) {
      options.warn(path + ": " + message);
    } else {
      std::fprintf(stderr, "logrid: warning: %s: %s\n", path.c_str(), message.c_str());
    }
  };

  Assimp::Importer importer;
  restrictImporters(path, importer);
  load::checkPly(path, warn);
  load::checkGltf(path);
  importer.SetIOHandler(new BoundedIOSystem(options.max_file_bytes));
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  auto assimpFailed = [&]() {
    const std::string error = importer.GetErrorString();
    fail(ErrorCode::BadInput, path, error.empty() ? "assimp cannot read it" : error);
  };
  // Parse only, check what the importer made (checkRawScene), then post-process.
  const aiScene* raw = importer.ReadFile(path, 0);
  if (raw == nullptr) assimpFailed();
  load::checkRawScene(path, *raw);
  const aiScene* ai =
      importer.ApplyPostProcessing(aiProcess_ValidateDataStructure | aiProcess_Triangulate |
                                   aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
  if (ai == nullptr) assimpFailed();
  return load::sceneFromAssimp(path, *ai, options);
}

}  // namespace

Scene loadSceneFile(const std::string& path, const LoadOptions& options) {
  // Assimp reports most failures through its error string, but it can also throw (its
  // DeadlyImportError from post-processing, std::bad_alloc for a forged element count,
  // std::length_error, ...); nothing but logrid::Error may leave this function.
  try {
    return loadWithAssimp(path, options);
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    fail(ErrorCode::BadInput, path,
         "out of memory while loading (a malformed size in the file, or a model too large "
         "for this machine)");
  } catch (const std::exception& e) {
    fail(ErrorCode::BadInput, path, std::string("cannot be read: ") + e.what());
  } catch (...) {
    fail(ErrorCode::BadInput, path, "cannot be read: unknown exception from assimp");
  }
}

bool sceneFilesSupported() { return true; }

#else  // no assimp

Scene loadSceneFile(const std::string& path, const LoadOptions& /*options*/) {
  throw Error(ErrorCode::Unsupported,
              path +
                  ": this build cannot load model files; install libassimp-dev and rebuild "
                  "with -DLOGRID_WITH_ASSIMP=ON");
}

bool sceneFilesSupported() { return false; }

#endif

}  // namespace logrid::samples
