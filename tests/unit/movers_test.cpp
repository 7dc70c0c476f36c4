// Moving objects of the sample scenes (samples/scene/movers.hpp, motion.hpp), without
// GL: deterministic from the seed, meshes of the promised sizes, boxes that hold every
// vertex as a float renderer transforms it, stop-and-go timing, vehicles in their lanes,
// the prepared scene's layout (movers after the static objects, shared geometry), and
// the --motion file format's errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>

#include "logrid/error.hpp"
#include "scene/generators.hpp"
#include "scene/movers.hpp"
#include "scene/prepare.hpp"

namespace logrid::samples {
namespace {

bool holds(const Aabb& b, float x, float y, float z) {
  return b.min.x <= x && x <= b.max.x && b.min.y <= y && y <= b.max.y && b.min.z <= z &&
         z <= b.max.z;
}

Scene forestWithMovers(std::uint32_t movers, std::uint64_t seed) {
  Scene s = makeForest({0.05, 1});
  addMovers(s, movers, seed);
  return s;
}

TEST(Movers, AreDeterministicFromTheSeed) {
  const Scene a = forestWithMovers(30, 4), b = forestWithMovers(30, 4), c = forestWithMovers(30, 5);
  ASSERT_EQ(a.motion.movers.size(), 30u);
  ASSERT_EQ(a.moving.size(), 30u);
  bool differs = false;
  for (std::size_t i = 0; i < 30; ++i) {
    for (double t : {0.0, 17.5, 400.0}) {
      const Aabb ba = a.motion.boxAt(i, t), bb = b.motion.boxAt(i, t), bc = c.motion.boxAt(i, t);
      EXPECT_EQ(ba.min.x, bb.min.x);
      EXPECT_EQ(ba.max.z, bb.max.z);
      differs |= ba.min.x != bc.min.x;
    }
  }
  EXPECT_TRUE(differs) << "another seed moves them differently";
  EXPECT_EQ(a.positions, b.positions);
}

TEST(Movers, MeshesHaveAFewHundredToAFewThousandTriangles) {
  for (const char* name : {"forest", "city"}) {
    Scene s = std::string(name) == "city" ? makeCity({0.01, 1}) : makeForest({0.05, 1});
    const std::size_t before = s.indices.size();
    addMovers(s, 200, 1);
    std::set<std::uint32_t> shapes;
    for (const MoverSpec& m : s.motion.movers) {
      EXPECT_GE(m.triangles, 300u) << name;
      EXPECT_LE(m.triangles, 5000u) << name;
      shapes.insert(m.triangles);
    }
    EXPECT_EQ(shapes.size(), 3u) << name << ": three shapes";
    // Movers of one shape share one copy of its mesh.
    std::size_t template_triangles = 0;
    for (std::uint32_t t : shapes) template_triangles += t;
    EXPECT_EQ(s.indices.size() - before, template_triangles * 3) << name;
    EXPECT_NO_THROW(validateScene(s));
  }
}

// The renderer computes u_rotation * p + (translation - origin) in float
// (mesh_renderer.hpp); boxAt() must hold every vertex so computed.
TEST(Movers, BoxesHoldEveryVertexAsAFloatRendererPlacesIt) {
  for (const char* name : {"forest", "city"}) {
    Scene s = std::string(name) == "city" ? makeCity({0.01, 1}) : makeForest({0.05, 1});
    addMovers(s, 40, 3);
    for (std::size_t i = 0; i < s.motion.movers.size(); ++i) {
      const SceneObject& mesh = s.moving[i];
      for (double t : {0.0, 3.3, 77.7, 1234.5}) {
        const RigidTransform tr = s.motion.transformAt(i, t);
        const Aabb box = s.motion.boxAt(i, t);
        float r[9];
        for (int k = 0; k < 9; ++k) r[k] = static_cast<float>(tr.rotation[k]);
        const float off[3] = {float(tr.translation.x), float(tr.translation.y),
                              float(tr.translation.z)};
        for (std::uint32_t k = mesh.first_index; k < mesh.first_index + mesh.index_count; ++k) {
          const float* p = &s.positions[std::size_t(s.indices[k]) * 3];
          float v[3];
          for (int row = 0; row < 3; ++row) {
            v[row] = r[row] * p[0] + r[3 + row] * p[1] + r[6 + row] * p[2] + off[row];
          }
          ASSERT_TRUE(holds(box, v[0], v[1], v[2]))
              << name << " mover " << i << " at t " << t << ": vertex (" << v[0] << ", " << v[1]
              << ", " << v[2] << ") outside its box";
        }
      }
    }
  }
}

TEST(Movers, StopAndGoStandsStillAndMovesOn) {
  Motion motion;
  MotionPath path;
  path.points = {{0, 0, 0}, {100, 0, 0}};
  path.finish("test");
  motion.paths.push_back(path);
  MoverSpec m;
  m.speed = 2;
  m.move_seconds = 10;
  m.stop_seconds = 5;
  m.mesh_box = {{-1, 0, -1}, {1, 1, 1}};
  motion.movers.push_back(m);
  EXPECT_DOUBLE_EQ(motion.travelled(0, 0), 0);
  EXPECT_DOUBLE_EQ(motion.travelled(0, 10), 20);
  EXPECT_DOUBLE_EQ(motion.travelled(0, 14), 20);  // standing
  EXPECT_DOUBLE_EQ(motion.travelled(0, 16), 22);  // and on again
  EXPECT_DOUBLE_EQ(motion.travelled(0, 30), 40);
  // A phase starts it inside the cycle: 8 s in, 2 s of moving left.
  motion.movers[0].phase = 8;
  EXPECT_DOUBLE_EQ(motion.travelled(0, 2), 4);
  EXPECT_DOUBLE_EQ(motion.travelled(0, 6), 4);
  EXPECT_DOUBLE_EQ(motion.travelled(0, 9), 8);
  // Back and forth along an open path: at 60 m travelled it is 40 m back at x = 40,
  // facing -x.
  motion.movers[0] = m;
  motion.movers[0].stop_seconds = 0;
  motion.movers[0].speed = 1;
  const RigidTransform t = motion.transformAt(0, 160);
  EXPECT_NEAR(t.translation.x, 40, 1e-9);
  EXPECT_NEAR(t.rotation[0], -1, 1e-12);
}

TEST(Movers, VehiclesDriveOnTheStreets) {
  Scene s = makeCity({0.01, 1});
  addMovers(s, 60, 2);
  const std::vector<double>& streets = s.mover_site.streets_x;
  ASSERT_GE(streets.size(), 2u);
  for (std::size_t i = 0; i < s.motion.movers.size(); ++i) {
    for (double t : {0.0, 50.0, 500.0}) {
      const RigidTransform tr = s.motion.transformAt(i, t);
      auto near = [&](double v) {
        for (double st : streets) {
          if (std::fabs(std::fabs(v - st) - 3.0) < 1e-6) return true;
        }
        return false;
      };
      EXPECT_TRUE(near(tr.translation.x) || near(tr.translation.z))
          << "mover " << i << " at " << tr.translation.x << ", " << tr.translation.z;
      EXPECT_EQ(tr.translation.y, 0.0);
    }
  }
}

TEST(Movers, PreparedSceneKeepsThemAfterTheStaticObjects) {
  for (const char* name : {"forest", "city"}) {
    Scene s = std::string(name) == "city" ? makeCity({0.01, 1}) : makeForest({0.05, 1});
    Scene plain = std::string(name) == "city" ? makeCity({0.01, 1}) : makeForest({0.05, 1});
    addMovers(s, 25, 1);
    const bvh::BuildArgs args = defaultBuildArgs(s);
    const PreparedScene moving = prepareScene(std::move(s), args);
    const PreparedScene still = prepareScene(std::move(plain), args);
    EXPECT_EQ(moving.static_objects, still.mesh.draws.size()) << name;
    EXPECT_EQ(moving.mesh.draws.size(), still.mesh.draws.size() + 25) << name;
    EXPECT_EQ(moving.hierarchy.nodes().size(), still.hierarchy.nodes().size())
        << name << ": the static hierarchy holds no mover";
    std::uint64_t mover_triangles = 0;
    for (const MoverSpec& m : moving.motion.movers) mover_triangles += m.triangles;
    EXPECT_EQ(moving.triangles, still.triangles + mover_triangles) << name;
    for (std::size_t i = 0; i < 25; ++i) {
      const Aabb a = moving.object_boxes[moving.static_objects + i];
      const Aabb b = moving.motion.boxAt(i, 0.0);
      EXPECT_EQ(a.min.x, b.min.x);
      EXPECT_EQ(a.max.y, b.max.y);
    }
  }
}

TEST(Movers, TooManyAreRefused) {
  Scene s = makeForest({0.02, 1});
  EXPECT_THROW(addMovers(s, kMaxMovers + 1, 1), Error);
}

std::string writeTemp(const std::string& name, const std::string& text) {
  const std::string path = (std::filesystem::temp_directory_path() / name).string();
  std::ofstream(path) << text;
  return path;
}

TEST(MeshAnimations, FileFormatErrorsNameTheProblem) {
  auto message = [](const std::string& text) {
    const std::string path = writeTemp("logrid_motion_test.json", text);
    try {
      loadMeshAnimations(path, 4);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message("{").find("not valid JSON"), std::string::npos);
  EXPECT_NE(message("[]").find("\"objects\""), std::string::npos);
  EXPECT_NE(message(R"({"objects":[{"mesh":9,"path":[[0,0,0],[1,0,0]]}]})").find("mesh 9"),
            std::string::npos);
  EXPECT_NE(message(R"({"objects":[{"mesh":1,"path":[[0,0,0]]}]})").find("two points"),
            std::string::npos);
  EXPECT_NE(message(R"({"objects":[{"mesh":1,"path":[[0,0,0],[0,0,0]]}]})").find("zero length"),
            std::string::npos);
  EXPECT_NE(message(R"({"objects":[{"mesh":1,"path":[[0,0,0],[1,0,0]]},)"
                    R"({"mesh":1,"path":[[0,0,0],[1,0,0]]}]})")
                .find("twice"),
            std::string::npos);
  EXPECT_NE(
      message(R"({"objects":[{"mesh":1,"path":[[0,0,0],[1,0,0]],"speed":"fast"}]})").find("speed"),
      std::string::npos);
  const auto ok = loadMeshAnimations(
      writeTemp("logrid_motion_ok.json",
                R"({"objects":[{"mesh":2,"path":[[0,0,0],[4,0,0]],"speed":2,"loop":true}]})"),
      4);
  ASSERT_EQ(ok.size(), 1u);
  EXPECT_EQ(ok[0].mesh, 2u);
  EXPECT_TRUE(ok[0].path.loop);
  EXPECT_DOUBLE_EQ(ok[0].path.length(), 8.0);
  EXPECT_THROW(loadMeshAnimations("/nonexistent/motion.json", 4), Error);
}

TEST(MeshAnimations, AnimatedMeshesLeaveTheStaticObjectsAndMoveByTranslation) {
  Scene s = makeForest({0.02, 1});
  s.origin = {1000, 0, 0};  // paths are in world coordinates
  const std::size_t objects = s.objects.size();
  const Aabb original = s.objects[1].box;
  const std::string path =
      writeTemp("logrid_motion_anim.json",
                R"({"objects":[{"mesh":1,"path":[[1000,0,0],[1010,0,0]],"speed":1}]})");
  animateMeshes(s, path);
  EXPECT_EQ(s.objects.size(), objects - 1);
  ASSERT_EQ(s.moving.size(), 1u);
  const Aabb at5 = s.motion.boxAt(0, 5.0);
  EXPECT_NEAR(at5.min.x, original.min.x + 5, 1e-3);
  EXPECT_NEAR(at5.max.z, original.max.z, 1e-3);
  EXPECT_NO_THROW(validateScene(s));
}

}  // namespace
}  // namespace logrid::samples
