// A user of an installed logrid with its GL parts. The install test only compiles and
// links this (every GL library is referenced, so the link checks their dependencies);
// run it with any argument to cull one box on a headless context.
#include <cstdio>
#include <vector>

#include "logrid/bvh/bvh.hpp"
#include "logrid/cpu/software_rasterizer.hpp"
#include "logrid/culler.hpp"
#include "logrid/gl/context.hpp"
#include "logrid/gl/framebuffer.hpp"
#include "logrid/gl/mesh_renderer.hpp"
#include "logrid/zread/gl_sources.hpp"

int main(int argc, char** argv) {
  (void)argv;
  if (argc < 2) {
    std::printf("consumer_gl: linked; pass an argument to run on a headless GL context\n");
    return 0;
  }
  logrid::gl::Context context;
  std::printf("consumer_gl: %s\n", context.info().renderer.c_str());

  const logrid::Aabb box{{-1, -1, -1}, {1, 1, 1}};
  const logrid::bvh::FlatHierarchy hierarchy = logrid::bvh::buildOverBoxes({box});
  logrid::gl::RenderMesh mesh;
  logrid::cpu::appendBox(box, mesh.positions, mesh.indices32);
  mesh.draws.push_back({0, static_cast<std::uint32_t>(mesh.indices32.size()), 0, 0xFFFFFFFFu});
  logrid::gl::MeshRenderer renderer(mesh);

  logrid::Camera camera;
  camera.width = 64;
  camera.height = 64;
  camera.view_projection = logrid::multiply(logrid::perspective(1.0, 1.0, 0.5, 100.0, camera.depth),
                                            logrid::lookAt({0, 0, 10}, {0, 0, 0}, {0, 1, 0}));
  logrid::gl::Framebuffer framebuffer({64, 64, camera.depth, false});
  framebuffer.bind();
  const float background[4] = {0, 0, 0, 1};
  framebuffer.clear(background);
  logrid::zread::ReadPixelsSource depth(framebuffer.handle());
  logrid::Culler culler;
  renderer.begin(logrid::gl::Pass::Shaded, camera);
  const logrid::FrameStats stats =
      culler.cullFrame(camera, hierarchy, depth, [&](logrid::ObjectId id) { renderer.draw(id); });
  renderer.end();
  context.check("consumer_gl");
  std::printf("consumer_gl: drew %llu object(s)\n",
              static_cast<unsigned long long>(stats.objects_drawn));
  return stats.objects_drawn == 1 ? 0 : 1;
}
