// noise.h: the sensor noise model (world:robot{ noise = ... }, docs/scenarios.md, Noise): what a
// noisy eye, joint encoder, base estimate and touch sensor report, given the exact senses and a
// seeded stream. Every draw is guarded by its sigma: a sigma of 0 draws nothing and changes nothing.
#pragma once

#include "core/rng.h"
#include "core/robot.h"
#include "senses/senses.h"

namespace roger {

// How noisy the stereo fix is, from the senses' noise: the standard deviation of each eye's world
// bearing of the stimulus (rad: its pan's noise and the image's) and of the base pose (m and rad).
// All zero for true senses: the fix is then taken as it is.
struct StereoNoise {
  double bearing = 0.0;
  double base = 0.0;
  bool any() const { return bearing > 0.0 || base > 0.0; }
};

// The noise of one world, derived once (WorldModel): what its spec asks of each channel, what that
// does to a stereo fix, and whether there is any (a world without noise draws nothing).
struct NoiseModel {
  NoiseParams params;
  StereoNoise stereo;
  bool any = false;
};

// The noise model of `params` for eyes of `camera`. Each eye's world bearing of the stimulus
// carries its pan's noise and the image's: about a hundredth of a pixel per colour level, measured
// on the stimulus' centre (test_noise), over the focal length.
NoiseModel noise_model(const NoiseParams& params, const Camera& camera);

// Coverage at or above which a noisy pixel reads as the stimulus colour (its colour nearer the
// stimulus's than its background's); a pixel next to one keeps its coverage below it (an edge).
constexpr float kStimulusStrong = 0.5f;

// Adds Gaussian noise of `sigma` colour levels to each channel of each pixel, and re-estimates
// each pixel's stimulus coverage from its noisy colour (the noise projected on the axis from the
// pixel's background colour to the stimulus colour), keeping pixels that read as the stimulus and
// their neighbours. Marks the image noisy (detection then splits runs by coverage, not colour).
void add_image_noise(EyeImage& image, double sigma, Rng& rng);

// Adds noise to the joint angles (eyes and arms, `joints` rad) and to the base pose and odometer
// (`base` m and rad) of s; the heading joint reads the noisy heading. Velocities stay exact.
void add_pose_noise(Senses& s, const NoiseParams& noise, Rng& rng);

// Scales each contact's normal and friction force by max(0, 1 + sigma N(0, 1)).
void add_touch_noise(Senses& s, double sigma, Rng& rng);

// One factor per degree of freedom, max(0, 1 + sigma N(0, 1)), for the commands of one tick.
void draw_effort_noise(DofVector& factors, double sigma, Rng& rng);

}  // namespace roger
