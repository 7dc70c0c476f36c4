// logrid.hpp: what an application that integrates logrid includes. Conventions first,
// then the camera, the hierarchy, the depth sources, the culler and its frame statistics.
// Everything else under logrid/ is for the methods' implementers and tools (the grid and
// the baselines' internals: grid.hpp, depth_pyramid.hpp, depth_kernels.hpp); a GL
// application adds the GL depth sources (logrid/zread/gl_sources.hpp, linked as
// logrid::zread).
//
// ---- Conventions (types.hpp has them in full) -----------------------------------------
// * Matrices: column-major 4x4 doubles, as OpenGL and GLM lay them out; the camera's is
//   world to clip (projection * view).
// * Pixels: OpenGL window coordinates, origin bottom-left, pixel (i, j) centred at
//   (i + 0.5, j + 0.5); rectangles half-open [x0, x1) x [y0, y1); the viewport is
//   width x height from (0, 0).
// * Depth: compared as a depth key, the window depth for the standard convention and its
//   negation for the reversed one: a smaller key is always nearer and the cleared buffer
//   holds the largest.
// * The frame's contract (culler.hpp): the depth buffer is cleared before the frame
//   begins; everything drawn during it is what the culler hands out (or is announced
//   with Culler::noteDrawn), drawn with a depth test that keeps the nearer fragment and
//   depth writes on.
// * Errors: invalid input and an environment logrid cannot work in are an ErrorCode and
//   a message that names the value and what to do (error.hpp), in two forms: the result
//   forms (Culler::create(), tryBeginFrame(), ...: a Status or a Result, never an
//   exception; for builds with -fno-exceptions) and the throwing forms used below
//   (logrid::Error; inline, where exceptions are enabled).
//
// ---- The smallest integration (README.md, "Integrating logrid") ----------------------
//
//   MyHierarchy hierarchy(my_tree);                      // a logrid::Hierarchy adapter
//   logrid::Culler culler;                               // the lazy occlusion grid
//   MyDepthSource depth;                                 // or zread::ReadPixelsSource
//   logrid::Camera camera;                               // GL's default depth set-up
//   camera.view_projection = my_projection_times_view;   // column-major doubles
//   camera.width = width, camera.height = height;
//   // every frame, after clearing the depth buffer:
//   culler.beginFrame(camera, hierarchy, {&depth});
//   for (logrid::DrawBatch batch = culler.nextBatch(); !batch.empty();
//        batch = culler.nextBatch())
//     drawObjects(batch.begin(), batch.end());           // depth test and writes on
//   logrid::FrameStats stats = culler.endFrame();
#pragma once

// Conventions: ids, boxes, matrices, depth conventions and formats, pixel rectangles.
#include "logrid/types.hpp"
// Errors: Status, Result, ErrorCode; logrid::Error where exceptions are enabled.
#include "logrid/error.hpp"
// The camera: matrix, viewport, depth set-up; matrix helpers; validateCamera().
#include "logrid/camera.hpp"
// The application's bounding-volume hierarchy, seen through an adapter.
#include "logrid/hierarchy.hpp"
// Depth sources: the interface the grid reads through, and a base for one's own that
// only fetches depth values (pixel_source.hpp).
#include "logrid/depth_source.hpp"
#include "logrid/pixel_source.hpp"
// Hardware occlusion queries and occluder pre-passes, for the methods that need them.
#include "logrid/occluder_source.hpp"
#include "logrid/occlusion_queries.hpp"
// The culler: descriptor, methods, the pull form (beginFrame, nextBatch, endFrame) and
// the callback form (cullFrame).
#include "logrid/culler.hpp"
#include "logrid/method.hpp"
// Settings from files: a configuration `logrid tune --auto` measured, the cost model
// `logrid calibrate` measured (what `auto` chooses with).
#include "logrid/config.hpp"
#include "logrid/costs.hpp"
// What a frame did.
#include "logrid/stats.hpp"
