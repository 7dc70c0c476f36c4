// What the CPU occlusion buffer (logrid/cpu/occlusion_buffer.hpp) rasterises for each
// object of a prepared scene: the object's own mesh, or the scene's occluder model of it
// (Scene::occluder_models: the forest's trees as trunk and inner crown hulls; the city's
// chunks as the boxes inside their buildings, Scene::occluder_solids), with the
// mesh as the fallback where the model cannot be used. Objects without a model use their
// mesh either way. Built on first use and kept with the scene.
#pragma once

#include <optional>
#include <string>

#include "logrid/cpu/occluder_mesh.hpp"
#include "scene/prepare.hpp"

namespace logrid::samples {

enum class OccluderChoice : std::uint8_t {
  Mesh,   // every object's own triangles
  Model,  // the scene's occluder models where it has them
};

const char* toString(OccluderChoice choice);
std::optional<OccluderChoice> parseOccluderChoice(const std::string& name);

// Object i of the result is ObjectId i of the scene; fallbacks follow them. Moving
// objects (ids from PreparedScene::static_objects on) hold their own mesh in their own
// coordinates, to be drawn with the frame's transform.
// `within_objects`: every model stays inside its object's box (boxes of solids that
// reach beyond it are clipped to it; an object with nothing left uses its mesh), as
// methods with occlusion-state semantics need (TestSemantics::OcclusionState: a pixel
// counts as hidden wherever anything was drawn, sound only because the two-list order
// draws only objects whose boxes lie in front of every box still to be tested).
const cpu::OccluderMeshes& sceneOccluders(const PreparedScene& scene, OccluderChoice choice,
                                          bool within_objects);

}  // namespace logrid::samples
