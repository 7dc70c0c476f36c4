// Small model files of each format the scene loader reads, written byte for byte by the
// loader tests (tests/unit/loader_test.cpp) and the loader fuzzer
// (tests/fuzz/loader_fuzz_test.cpp), and the temporary files they are written to.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

namespace logrid::test {

// Two objects: a unit quad at z = 0 and a triangle at z = 5; bounds [0,2]x[0,3]x[0,5].
inline constexpr const char* kObjTwoObjects =
    "# two objects\n"
    "o first\n"
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
    "f 1 2 3\nf 2 4 3\n"
    "o second\n"
    "v 0 0 5\nv 2 0 5\nv 0 3 5\n"
    "f 5 6 7\n";

// A quad (split in two) and a triangle sharing its vertices; bounds [-1,1]x[0,2]x[0,4].
inline constexpr const char* kPlyAscii =
    "ply\n"
    "format ascii 1.0\n"
    "comment logrid test\n"
    "element vertex 5\n"
    "property float x\nproperty float y\nproperty float z\n"
    "element face 2\n"
    "property list uchar int vertex_indices\n"
    "end_header\n"
    "-1 0 0\n1 0 0\n1 2 0\n-1 2 0\n0 1 4\n"
    "4 0 1 2 3\n"
    "3 0 1 4\n";

// PLY files as real exporters wrote them, each bending the format in a way assimp 5.2
// reads correctly. All hold the geometry of kPlyAscii.
//
// Blender 2.4x's exporter before August 2008 (ply_export.py 0.93): its "Created by"
// line has no "comment" keyword, vertices carry normals, texture coordinates and
// colours, and face lines end with a blank.
inline constexpr const char* kPlyBlender245 =
    "ply\n"
    "format ascii 1.0\n"
    "Created by Blender3D 245 - www.blender.org, source file: untitled.blend\n"
    "element vertex 5\n"
    "property float x\nproperty float y\nproperty float z\n"
    "property float nx\nproperty float ny\nproperty float nz\n"
    "property float s\nproperty float t\n"
    "property uchar red\nproperty uchar green\nproperty uchar blue\n"
    "element face 2\n"
    "property list uchar uint vertex_indices\n"
    "end_header\n"
    "-1.000000 0.000000 0.000000 0.000000 0.000000 1.000000 0.000000 0.000000 255 255 255\n"
    "1.000000 0.000000 0.000000 0.000000 0.000000 1.000000 1.000000 0.000000 255 255 255\n"
    "1.000000 2.000000 0.000000 0.000000 0.000000 1.000000 1.000000 1.000000 255 255 255\n"
    "-1.000000 2.000000 0.000000 0.000000 0.000000 1.000000 0.000000 1.000000 255 255 255\n"
    "0.000000 1.000000 4.000000 0.000000 -0.970143 0.242536 0.500000 0.500000 255 0 0\n"
    "4 0 1 2 3 \n"
    "3 0 1 4 \n";

// The same exporter after August 2008 (Blender 2.49): "comment" added, the source file
// name in UTF-8, and without colours every data line ends with a blank.
inline constexpr const char* kPlyBlender249 =
    "ply\n"
    "format ascii 1.0\n"
    "comment Created by Blender3D 249 - www.blender.org, source file: "
    "maison_\xC3\xA9t\xC3\xA9.blend\n"
    "element vertex 5\n"
    "property float x\nproperty float y\nproperty float z\n"
    "property float nx\nproperty float ny\nproperty float nz\n"
    "element face 2\n"
    "property list uchar uint vertex_indices\n"
    "end_header\n"
    "-1.000000 0.000000 0.000000 0.000000 0.000000 1.000000 \n"
    "1.000000 0.000000 0.000000 0.000000 0.000000 1.000000 \n"
    "1.000000 2.000000 0.000000 0.000000 0.000000 1.000000 \n"
    "-1.000000 2.000000 0.000000 0.000000 0.000000 1.000000 \n"
    "0.000000 1.000000 4.000000 0.000000 -0.970143 0.242536 \n"
    "4 0 1 2 3 \n"
    "3 0 1 4 \n";

// A C program that printed its numbers with printf("%f") under a German locale, on
// Windows: decimal commas, CR LF line ends, an obj_info line, and a closing remark after
// the data.
inline constexpr const char* kPlyDecimalCommaCrLf =
    "ply\r\n"
    "format ascii 1.0\r\n"
    "obj_info exported by scan2ply 1.3\r\n"
    "element vertex 5\r\n"
    "property float x\r\nproperty float y\r\nproperty float z\r\n"
    "element face 2\r\n"
    "property list uchar int vertex_indices\r\n"
    "end_header\r\n"
    "-1,000000 0,000000 0,000000\r\n"
    "1,000000 0,000000 0,000000\r\n"
    "1,000000 2,000000 0,000000\r\n"
    "-1,000000 2,000000 0,000000\r\n"
    "0,000000 1,000000 4,000000\r\n"
    "4 0 1 2 3\r\n"
    "3 0 1 4\r\n"
    "end of scan2ply output\r\n";

// Two facets of a square in the y = 0 plane; bounds [0,3]x[0,0]x[0,3].
inline constexpr const char* kStlAscii =
    "solid square\n"
    " facet normal 0 1 0\n  outer loop\n"
    "   vertex 0 0 0\n   vertex 0 0 3\n   vertex 3 0 0\n"
    "  endloop\n endfacet\n"
    " facet normal 0 1 0\n  outer loop\n"
    "   vertex 3 0 0\n   vertex 0 0 3\n   vertex 3 0 3\n"
    "  endloop\n endfacet\n"
    "endsolid square\n";

// Appends the bytes of `value` as they lie in memory (the tests run on little-endian machines).
template <typename T>
void appendRaw(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

// kStlAscii as binary STL: 80-byte header, facet count, 50 bytes a facet.
inline std::string binaryStl() {
  std::string out(80, ' ');
  out.replace(0, 11, "logrid test");
  appendRaw(out, std::uint32_t{2});
  const float facets[2][12] = {{0, 1, 0, 0, 0, 0, 0, 0, 3, 3, 0, 0},
                               {0, 1, 0, 3, 0, 0, 0, 0, 3, 3, 0, 3}};
  for (const auto& facet : facets) {
    for (const float v : facet) appendRaw(out, v);
    appendRaw(out, std::uint16_t{0});  // attribute byte count
  }
  return out;
}

// Binary little-endian PLY with the given vertices and triangles.
inline std::string binaryPly(const std::vector<float>& xyz,
                             const std::vector<std::int32_t>& triangles) {
  std::string out = "ply\nformat binary_little_endian 1.0\nelement vertex " +
                    std::to_string(xyz.size() / 3) +
                    "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                    std::to_string(triangles.size() / 3) +
                    "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const float v : xyz) appendRaw(out, v);
  for (std::size_t t = 0; t < triangles.size(); t += 3) {
    out.push_back(3);
    for (std::size_t k = 0; k < 3; ++k) appendRaw(out, triangles[t + k]);
  }
  return out;
}

// A tetrahedron as binary PLY; bounds [0,1]x[0,2]x[0,3].
inline std::string binaryPlyTetrahedron() {
  return binaryPly({0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 3}, {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3});
}

// Standard base64 of `bytes`, padded with '='.
inline std::string base64(const std::string& bytes) {
  static const char* const kDigits =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::uint32_t bits = 0;
  int count = 0;
  for (const char c : bytes) {
    bits = bits << 8 | static_cast<unsigned char>(c);
    count += 8;
    while (count >= 6) {
      count -= 6;
      out.push_back(kDigits[(bits >> count) & 63u]);
    }
  }
  if (count > 0) out.push_back(kDigits[(bits << (6 - count)) & 63u]);
  while (out.size() % 4 != 0) out.push_back('=');
  return out;
}

// The buffer of the glTF files: a triangle's positions and indices, padded to 44 bytes.
inline std::string gltfBuffer() {
  std::string buffer;
  for (const float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) appendRaw(buffer, v);
  for (const int i : {0, 1, 2}) appendRaw(buffer, static_cast<std::uint16_t>(i));
  buffer.append(2, '\0');
  return buffer;
}

// glTF 2.0: one red triangle (0,0,0) (1,0,0) (0,1,0) instanced by two nodes under a root
// scaled by 2, translated by (10,0,0) and (0,0,-10); world bounds [0,22]x[0,2]x[-20,0].
// `generator` goes into the asset; `buffer_uri` empty: the buffer is a GLB's binary chunk.
inline std::string gltfInstanced(const std::string& generator, const std::string& buffer_uri) {
  return R"({
  "asset": {"version": "2.0", "generator": ")" +
         generator + R"("},
  "scene": 0,
  "scenes": [{"nodes": [0]}],
  "nodes": [
    {"name": "root", "scale": [2, 2, 2], "children": [1, 2]},
    {"name": "east", "mesh": 0, "translation": [10, 0, 0]},
    {"name": "south", "mesh": 0, "translation": [0, 0, -10]}
  ],
  "meshes": [{"name": "triangle", "primitives": [
    {"attributes": {"POSITION": 0}, "indices": 1, "material": 0, "mode": 4}]}],
  "materials": [{"name": "red", "pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1]}}],
  "accessors": [
    {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
     "min": [0, 0, 0], "max": [1, 1, 0]},
    {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}
  ],
  "bufferViews": [
    {"buffer": 0, "byteOffset": 0, "byteLength": 36, "target": 34962},
    {"buffer": 0, "byteOffset": 36, "byteLength": 6, "target": 34963}
  ],
  "buffers": [{"byteLength": 44)" +
         (buffer_uri.empty() ? std::string() : ", \"uri\": \"" + buffer_uri + "\"") + R"(}]
})";
}

// The .gltf file: gltfInstanced with the buffer embedded as a base64 data: URI.
inline std::string gltfEmbedded(const std::string& generator) {
  return gltfInstanced(generator, "data:application/octet-stream;base64," + base64(gltfBuffer()));
}

// The same as binary glTF: header, JSON chunk, BIN chunk.
inline std::string glbInstanced(const std::string& generator) {
  std::string json = gltfInstanced(generator, "");
  json.append((4 - json.size() % 4) % 4, ' ');
  const std::string bin = gltfBuffer();
  std::string out = "glTF";
  auto word = [&out](std::size_t value) { appendRaw(out, static_cast<std::uint32_t>(value)); };
  word(2);
  word(12 + 8 + json.size() + 8 + bin.size());
  word(json.size());
  out += "JSON" + json;
  word(bin.size());
  out += std::string("BIN\0", 4) + bin;
  return out;
}

// A path in the test's temporary directory unique to this process: <prefix>_<pid>_<name>.
inline std::string tempFilePath(const std::string& prefix, const std::string& name) {
  return testing::TempDir() + prefix + "_" + std::to_string(::getpid()) + "_" + name;
}

// Writes `bytes` to `path` unchanged, replacing any file there.
inline void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

}  // namespace logrid::test
