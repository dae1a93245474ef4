// Module senses: Roger's sensor models, pure geometry with no physics engine. Owns eye images,
// sightings, stereo and touch records. Depends only on core (the simulator feeds it, not the reverse).
//
// senses.h: what Roger perceives at a control tick: two 1-D colour images, the stimulus seen in
// each, its stereo position, touch on the body and hands, joint angles and the base pose.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/robot.h"
#include "core/spec.h"

namespace roger {

// What a surface seen by a pixel belongs to.
enum class SurfaceKind : uint8_t { kNone = 0, kWall, kObject, kObstacle };

// One eye's image, of camera.pixels pixels (the arrays hold the largest eye; pixels beyond
// camera.pixels are never read). Pixel u looks along camera.angle_of_pixel(u) in the eye frame
// (counter-clockwise positive): pixel 0 sees half the field of view to the right, the last pixel
// half of it to the left (45 degrees for the default eye of 128 pixels).
struct EyeImage {  // a new member goes before `noisy` and into operator= (senses.cpp)
  Camera camera;                                // the eye that made it (paint_eye sets it)
  std::array<Colour, kMaxPixels> colour;        // the nearest surface at the pixel's centre
  std::array<SurfaceKind, kMaxPixels> kind;     // what that surface is
  std::array<int16_t, kMaxPixels> index;        // its index in WorldSpec objects or obstacles, or -1
  std::array<float, kMaxPixels> stimulus;       // fraction of the pixel covered by the stimulus colour
  // The colour painted as stimulus (paint_eye sets it): pixels of that colour are centred on an
  // object detection may tell apart from another (an image made by hand has none: its runs whole).
  Colour stimulus_colour{};
  // Every pixel with stimulus coverage lies in [stimulus_first, stimulus_last] (empty when first >
  // last): paint_eye narrows it to what it painted, so detection scans only that; an image made
  // by hand keeps the whole width.
  int16_t stimulus_first = 0, stimulus_last = kMaxPixels - 1;
  // Its colours and coverage carry sensor noise (SenseNoise::images): a pixel is on the stimulus when
  // its coverage reads as the stimulus colour, not when its colour equals it. paint_eye clears it.
  bool noisy = false;
  int pixels() const { return camera.pixels; }

  EyeImage() = default;
  // A copy takes the camera's pixels, not the whole capacity: an eye of 128 pixels copies a
  // quarter of what a 512-pixel array holds (the noisy senses are a copy of the true ones every
  // tick). What lies beyond pixels() is never read.
  EyeImage(const EyeImage& other) { *this = other; }
  EyeImage& operator=(const EyeImage& other);
};

// Coverage at or above which a pixel of a noisy image reads as the stimulus colour (its colour
// nearer the stimulus's than its background's): detection reads a noisy image's pixels so, and
// its mask (threshold_coverage, noise.h) is cleaned at the same level.
constexpr float kStimulusStrong = 0.5f;

// The stimulus as one eye detects it in its image (sub-pixel, from the edge pixels' coverage).
struct Sighting {
  bool seen = false;
  double u = 0.0;                // centre of the detected extent, in pixels
  double u_lo = 0.0, u_hi = 0.0; // its edges, in pixels
  double bearing = 0.0;          // angle of the centre in the eye frame (rad)
  double half_width = 0.0;       // half the angle from u_lo to u_hi (rad)
  bool clipped = false;          // the extent runs off the image: its centre is not the stimulus's
  int index = -1;                // the surface it is of (its middle pixel's index), for stereo pairing
};

// One tactile sensor, averaged over the physics steps of the last control tick.
struct Touch {
  bool contact = false;
  SurfaceKind kind = SurfaceKind::kNone;  // what is touched
  int index = -1;                 // which object or obstacle (-1 for walls or nothing)
  double force = 0.0;             // normal force (N)
  double friction = 0.0;          // tangential force magnitude (N)
  Vec2 normal = Vec2::Zero();     // unit, world frame, from the touched surface towards the sensor
  Vec2 point = Vec2::Zero();      // contact point, world frame
};

// Everything perceived at one control tick but the eyes' pixels: what control reads (it sees
// through the sightings) and what a pose estimate is made from, copied without the images.
struct SenseReadings {
  double time = 0.0;
  std::array<Sighting, 2> stimulus;  // kLeft, kRight
  bool stereo_valid = false;         // both eyes see it and the rays meet in front
  Vec2 stimulus_base = Vec2::Zero(); // triangulated position, base frame
  Vec2 stimulus_world = Vec2::Zero();// the same, world frame
  std::array<Touch, kTactileCount> touch;  // kBody, kLeftHand, kRightHand
  DofVector q = DofVector::Zero();         // joint positions (see Dof)
  DofVector qdot = DofVector::Zero();      // joint velocities
  Pose base;                               // base pose, world frame
};

// Everything perceived at one control tick.
struct Senses : SenseReadings {
  std::array<EyeImage, 2> image;  // kLeft, kRight
};

// A surface in the eyes' world: one convex part (disk or polygon) of an object or obstacle,
// already placed in the world frame. The world refreshes these each tick; the painter reads them.
struct SeenSurface {
  SurfaceKind kind = SurfaceKind::kObject;
  int16_t index = -1;
  Colour colour;
  bool is_disk = true;
  Vec2 center = Vec2::Zero();  // disk centre, or polygon centroid
  double radius = 0.0;         // disk radius; polygon: the largest distance of a vertex from the centroid
  int vertex_count = 0;        // polygon vertices, world frame
  std::array<Vec2, 8> vertices;
  bool ignored = false;        // never a stimulus, whatever its colour (attention has put it away)
};

// Appends the eyes' view of a shape placed at a pose: one world-frame surface per convex part.
void append_seen_surfaces(std::vector<SeenSurface>& out, const Shape& shape, const Pose& pose,
                          SurfaceKind kind, int index, const Colour& colour);

// Paints one eye's image through `camera` analytically: each surface's angular extent, nearest
// first, clipped by what is already covered (the same result as painting far-to-near, with exact
// sub-pixel edges). eye_heading is the world angle of the optical axis.
void paint_eye(const Camera& camera, const Vec2& eye, double eye_heading,
               const std::vector<SeenSurface>& surfaces, const Colour& wall_colour,
               const Colour& stimulus_colour, EyeImage& image);

// Finds the largest run of stimulus pixels and its sub-pixel centre. A run whose pixels' centres
// lie on two objects of the stimulus colour (side by side in the image) is two runs, split where
// the one ends and the other begins.
Sighting detect_stimulus(const EyeImage& image, int prefer_index = -1);

// Intersects the two eyes' rays to the stimulus. Returns false when they do not meet in front.
bool triangulate(const Vec2& left_eye, double left_angle, const Vec2& right_eye, double right_angle,
                 Vec2& out);

}  // namespace roger
