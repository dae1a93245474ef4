// world_model.h: the immutable model of one world, derived once from its spec (MuJoCo's model
// beside its data): the checked spec, the body's derived numbers, the eyes' camera, the noise
// model and the static occupancy grid. A World and an Agent hold it by const reference, and
// controllers read it through ControlInput::model; nothing in it changes during an episode, and
// nothing derived from the world is computed anywhere else.
#pragma once

#include "core/body.h"
#include "core/robot.h"
#include "core/spec.h"
#include "senses/noise.h"
#include "sim/occupancy.h"

namespace roger {

// Simulation settings, with the defaults the engine's tests and benchmarks use.
struct WorldParams {
  double dt = 0.01;             // physics time step (s)
  int substeps = 2;             // physics steps per control tick (a tick is 20 ms)
  int velocity_iterations = 6;  // Box2D solver iterations
  int position_iterations = 2;
};

struct WorldModel {
  WorldSpec spec;        // checked and put in form (check_world_spec)
  WorldParams params;    // the physics step and the control tick
  BodyMetrics body;      // the controllers' numbers that follow from the body (core/body.h)
  Camera camera;         // the eyes' pinhole model
  NoiseModel noise;      // what the noise does to the senses (noise.any: whether it does anything)
  OccupancyGrid grid;    // the static obstacles and walls, grown by grid_inflate
  double grid_inflate = 0.0;  // m

  const RobotParams& robot() const { return spec.body; }
  double tick_seconds() const { return params.dt * params.substeps; }
};

// Checks a spec and puts it in the one form worlds are built from: the poses' angles wrapped to
// (-pi, pi] (a heading written as 3 pi / 2 or with turns added builds the same world as its
// principal value) and polygons counter-clockwise (validate_shape). Throws roger::Error saying what
// makes it unbuildable: a shape Box2D would refuse, an empty arena, a body or eyes that cannot be
// built (body_problems). A spec that passes never reaches one of Box2D's asserts.
void check_world_spec(WorldSpec& spec);

// Derives `model` from `spec` (checked first: nothing changes when it throws). `grid_inflate` < 0
// grows the obstacles by the body's BodyMetrics::grid_inflate. A model that last held a world of
// the same arena, obstacles and growth, to the bit, keeps its grid (episodes of one scenario
// mostly share them).
void derive_world_model(const WorldSpec& spec, const WorldParams& params, double grid_inflate,
                        WorldModel& model);

}  // namespace roger
