// Writes a scene as a Wavefront OBJ model file (one `o` group per object, vertices
// shared within an object as the scene shares them) and its camera path as the JSON the
// --path option reads: the way a procedural scene becomes "a scene from a file".
#pragma once

#include <string>

#include "scene/scene.hpp"

namespace logrid::samples {

// Throws logrid::Error: InvalidArgument for a scene whose objects are the hierarchy's
// chunks (split_by_triangles: it has no objects of its own to write), Environment when the
// file cannot be written.
void writeObj(const Scene& scene, const std::string& path);
void writeCameraPathJson(const CameraPath& path, const std::string& file);

}  // namespace logrid::samples
