// glTF files checked before assimp reads them (loader_detail.hpp).
//
// Assimp 5.2 parses glTF JSON with rapidjson's recursive parser and imports the node
// graph recursively, copying every node as often as it is used: a .gltf of 200000 nested
// '[' or a chain of 50000 nodes overflows the stack (a crash), and nodes that each use
// the next one twice expand to 2^depth copies (memory until the machine gives out). So
// the JSON of a glTF file is checked first: its nesting depth, then the depth of its
// node graph and the number of nodes it expands to; and the chunk lengths of a .glb,
// which assimp allocates before it reads them.
//
// Everything else in a glTF file goes to assimp, which reports what it cannot read.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <system_error>
#include <unordered_map>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/loader_detail.hpp"

namespace logrid::samples::load {
namespace {

namespace fs = std::filesystem;

constexpr int kMaxJsonDepth = 128;

// The JSON of a .gltf file, or the JSON chunk of a .glb after checking the .glb's
// framing: assimp allocates whatever a chunk header declares before it reads the chunk,
// so a JSON chunk declared 2 GiB long in a 1 KiB file costs 2 GiB and seconds.
std::string gltfJson(const std::string& path, const std::string& extension) {
  std::ifstream in(path, std::ios::binary);
  if (extension == ".gltf") {
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }
  std::error_code ec;
  const std::uintmax_t bytes = fs::file_size(path, ec);
  if (ec) fail(ErrorCode::Environment, path, "cannot read its size (" + ec.message() + ")");
  auto bad = [&](const std::string& what) {
    fail(ErrorCode::BadInput, path, "is not a well-formed binary glTF file: " + what);
  };
  // Magic "glTF", version, total length, then (glTF 2) the JSON chunk's length and type
  // "JSON", or (glTF 1) the JSON content's length and format 0.
  unsigned char header[28] = {};
  in.read(reinterpret_cast<char*>(header), sizeof header);
  auto word = [&](std::size_t at) {
    return std::uint32_t{header[at]} | std::uint32_t{header[at + 1]} << 8 |
           std::uint32_t{header[at + 2]} << 16 | std::uint32_t{header[at + 3]} << 24;
  };
  if (bytes < 20 || std::string(reinterpret_cast<const char*>(header), 4) != "glTF") {
    bad("no glTF header");
  }
  const std::uint32_t version = word(4), length = word(8), json_length = word(12);
  if (version != 1 && version != 2) bad("version " + std::to_string(version));
  if (length > bytes || length < 20) {
    std::ostringstream out;
    out << "its header declares " << length << " bytes, the file has " << bytes << " (truncated?)";
    bad(out.str());
  }
  if (json_length > length - 20) {
    std::ostringstream out;
    out << "a JSON chunk of " << json_length << " bytes in a file of " << length;
    bad(out.str());
  }
  if (version == 2) {
    if (std::string(reinterpret_cast<const char*>(header) + 16, 4) != "JSON") {
      bad("the first chunk is not JSON");
    }
    // The binary chunk, if any, must fit too.
    const std::uint64_t bin_at = 20 + std::uint64_t{json_length};
    if (bin_at + 8 <= length) {
      unsigned char chunk[4] = {};
      in.seekg(static_cast<std::streamoff>(bin_at));
      in.read(reinterpret_cast<char*>(chunk), 4);
      const std::uint32_t bin_length = std::uint32_t{chunk[0]} | std::uint32_t{chunk[1]} << 8 |
                                       std::uint32_t{chunk[2]} << 16 |
                                       std::uint32_t{chunk[3]} << 24;
      if (bin_length > length - bin_at - 8) {
        std::ostringstream out;
        out << "a binary chunk of " << bin_length << " bytes with " << length - bin_at - 8
            << " left in the file";
        bad(out.str());
      }
    }
  }
  std::string json(json_length, '\0');
  in.clear();
  in.seekg(20);
  in.read(&json[0], static_cast<std::streamsize>(json_length));
  return json;
}

// The JSON's nesting depth, outside strings, at most kMaxJsonDepth.
void checkJsonDepth(const std::string& path, const std::string& json) {
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < json.size(); ++i) {
    const char c = json[i];
    if (in_string) {
      if (c == '\\') {
        ++i;
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth) {
        std::ostringstream out;
        out << "its JSON nests deeper than " << kMaxJsonDepth << " levels";
        fail(ErrorCode::BadInput, path, out.str());
      }
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

// The node graph as each node's children: glTF 2 lists nodes in an array and children by
// index, glTF 1 in an object and children by name. Anything malformed is left out (for
// assimp to report).
std::vector<std::vector<std::size_t>> nodeChildren(const nlohmann::json& nodes) {
  std::vector<const nlohmann::json*> node_list;
  std::unordered_map<std::string, std::size_t> names;
  if (nodes.is_array()) {
    for (const nlohmann::json& node : nodes) node_list.push_back(&node);
  } else if (nodes.is_object()) {
    for (auto it = nodes.begin(); it != nodes.end(); ++it) {
      names.emplace(it.key(), node_list.size());
      node_list.push_back(&it.value());
    }
  }
  const std::size_t count = node_list.size();
  std::vector<std::vector<std::size_t>> children(count);
  for (std::size_t n = 0; n < count; ++n) {
    if (!node_list[n]->is_object() || !node_list[n]->contains("children")) continue;
    const nlohmann::json& list = (*node_list[n])["children"];
    if (!list.is_array()) continue;
    for (const nlohmann::json& child : list) {
      if (child.is_number_unsigned() && child.get<std::uint64_t>() < count) {
        children[n].push_back(static_cast<std::size_t>(child.get<std::uint64_t>()));
      } else if (child.is_string()) {
        const auto it = names.find(child.get<std::string>());
        if (it != names.end()) children[n].push_back(it->second);
      }
    }
  }
  return children;
}

// No cycle, no subtree deeper than kMaxNodeDepth or expanding to more than kMaxInstances
// nodes: per node, the depth of its subtree and the number of nodes it expands to
// (saturating), by an iterative depth-first walk.
void checkNodeGraph(const std::string& path,
                    const std::vector<std::vector<std::size_t>>& children) {
  const std::size_t count = children.size();
  std::vector<std::uint64_t> expanded(count, 0), height(count, 0);
  std::vector<char> state(count, 0);  // 0 new, 1 on the stack, 2 done
  for (std::size_t root = 0; root < count; ++root) {
    if (state[root] != 0) continue;
    std::vector<std::pair<std::size_t, std::size_t>> stack{{root, 0}};  // node, next child
    state[root] = 1;
    while (!stack.empty()) {
      auto& [node, next] = stack.back();
      if (next < children[node].size()) {
        const std::size_t child = children[node][next++];
        if (state[child] == 1) fail(ErrorCode::BadInput, path, "the node graph has a cycle");
        if (state[child] == 0) {
          state[child] = 1;
          stack.push_back({child, 0});
        }
        continue;
      }
      std::uint64_t total = 1, deepest = 0;
      for (const std::size_t child : children[node]) {
        total = std::min<std::uint64_t>(total + expanded[child], std::uint64_t{1} << 62);
        deepest = std::max(deepest, height[child]);
      }
      expanded[node] = total;
      height[node] = deepest + 1;
      state[node] = 2;
      if (height[node] > kMaxNodeDepth) {
        std::ostringstream out;
        out << "the node graph is deeper than " << kMaxNodeDepth << " levels";
        fail(ErrorCode::BadInput, path, out.str());
      }
      if (total > kMaxInstances) {
        std::ostringstream out;
        out << "the node graph expands to more than " << kMaxInstances
            << " nodes (nodes used by several parents are copied for each)";
        fail(ErrorCode::BadInput, path, out.str());
      }
      stack.pop_back();
    }
  }
}

}  // namespace

void checkGltf(const std::string& path) {
  const std::string extension = lowerCase(fs::path(path).extension().string());
  if (extension != ".gltf" && extension != ".glb") return;
  const std::string json = gltfJson(path, extension);
  checkJsonDepth(path, json);
  const nlohmann::json document = nlohmann::json::parse(json, nullptr, false);
  if (!document.is_object() || !document.contains("nodes")) return;
  checkNodeGraph(path, nodeChildren(document["nodes"]));
}

}  // namespace logrid::samples::load
