#include "logrid/method.hpp"

#include <cassert>

namespace logrid {

const std::vector<MethodInfo>& methodTable() {
  // clang-format off
  static const std::vector<MethodInfo> table = {
    // method, name, description,
    //   two_list_order, state_semantics, tests_occlusion, needs_depth_values, lookahead,
    //   visible_pixels, full_fraction, row_stride
    {Method::LogState, "log-state",
     "lazy occlusion grid, occlusion-state variant (two-list traversal)",
     true, true, true, false, true, true, true, true},
    {Method::LogZfar, "log-zfar",
     "lazy occlusion grid, zfar variant (depth tests, any front-to-back order)",
     false, false, true, false, true, true, false, true},
    {Method::Bog, "bog",
     "busy occlusion grid: tiles refreshed right after each draw",
     true, true, true, false, false, true, true, true},
    {Method::Hzb, "hzb",
     "hierarchical z-buffer, refreshed from the drawn box's area after each draw",
     true, false, true, true, false, false, false, false},
    {Method::Pq, "pq",
     "one pixel-level query over each tested box's whole rectangle",
     true, true, true, false, true, true, false, false},
    {Method::Vfc, "vfc",
     "view-frustum culling only",
     false, false, false, false, false, false, false, false},
  };
  // clang-format on
  return table;
}

const MethodInfo& methodInfo(Method method) {
  const auto& table = methodTable();
  assert(std::size_t(method) < table.size() && "methodInfo: unknown method");
  return table[std::size_t(method)];
}

const char* toString(Method method) {
  const auto& table = methodTable();
  return std::size_t(method) < table.size() ? table[std::size_t(method)].name : "?";
}

std::optional<Method> parseMethod(const std::string& name) {
  for (const MethodInfo& m : methodTable()) {
    if (name == m.name) return m.method;
  }
  return std::nullopt;
}

std::string methodNames() {
  std::string out;
  for (const MethodInfo& m : methodTable()) {
    if (!out.empty()) out += ", ";
    out += m.name;
  }
  return out;
}

}  // namespace logrid
