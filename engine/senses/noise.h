// noise.h: the sensor and actuator noise model (world:robot{ noise = ... }, docs/scenarios.md,
// Noise): what a noisy eye, joint encoder, base estimate, touch sensor and motor do, given the
// exact readings and seeded streams.
//
// Each channel (image, joints, base, touch, effort) has kinds of noise (ChannelNoise, core/robot.h):
// white, a bias held for the episode, a Gauss-Markov drift, a delay in ticks, dropped readings and
// a resolution. Each kind that draws has a stream of its own, seeded by the world's seed, the
// channel and the kind, and draws the same number of values every tick whatever happens in the
// world: switching one kind on changes no other draw, and two policies under the same noise meet
// the same noise. A channel without noise draws nothing and changes nothing.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

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

// The noise model of `params` for eyes of `camera`. A fix's error has each kind's share: white,
// bias and drift add their variances, a resolution q adds q^2 / 12. Each eye's world bearing of
// the stimulus carries its pan's error and the image's: about a hundredth of a pixel per colour
// level, measured on the stimulus' centre (test_noise), over the focal length.
NoiseModel noise_model(const NoiseParams& params, const Camera& camera);

// The channels, which name the streams.
enum class NoiseChannel : int { kImage = 0, kJoints, kBase, kTouch, kEffort };

// A standard normal value from 16 random bits: the normal's quantile at the midpoint of the bits'
// slice of probability, from a table (resolution 1/65536 in probability; nothing beyond 4.17
// standard deviations). Four per 64-bit draw, and no logarithm or cosine: what an image's
// thousand draws a tick need. Every channel draws its normals so.
float table_normal(uint16_t bits);

// One channel's noise in one episode: the streams of the kinds that draw (white, bias, drift,
// dropout), the bias drawn at the start, the drift's state, and the readings held back by a delay
// or a lost reading.
class ChannelProcess {
 public:
  // Starts an episode: `components` values offset per tick, `readings` that can be lost (each
  // lost reading holds its components). A channel read in `whole_levels` (the image's colours,
  // each moved by its offset rounded to a whole level, half up) whose only offset is white noise
  // draws that noise as the rounded levels themselves (levels()), from a table of every 16 bits'
  // level made once per sigma: the same values, without the float work per component.
  void reset(const ChannelNoise& noise, uint64_t world_seed, NoiseChannel channel, int components,
             int readings, double tick_seconds, bool whole_levels = false);
  const ChannelNoise& noise() const { return noise_; }

  // Draws this tick's offsets (white + bias + drift, per component) and losses (per reading): a
  // fixed number from each stream.
  void draw();
  double offset(int component) const { return offsets_[size_t(component)]; }
  // The offsets, or null when this tick's are in levels() instead.
  const float* offsets() const { return levels_.empty() ? offsets_.data() : nullptr; }
  // The offsets rounded to whole levels (white noise alone in whole_levels), or null.
  const int16_t* levels() const { return levels_.empty() ? nullptr : levels_.data(); }
  bool lost(int reading) const { return lost_[size_t(reading)] != 0; }
  // `value` on the channel's grid (unchanged without a quantum).
  double quantize(double value) const;

 private:
  // n normal values of deviation sigma from `stream`, four per draw (table_normal).
  void fill_normals(Rng& stream, double sigma, float* out, size_t n) const;
  // The same draws as fill_normals(stream, noise_.sigma, ...), as their rounded levels.
  void fill_levels(Rng& stream, int16_t* out, size_t n) const;
  ChannelNoise noise_;
  const float* table_ = nullptr;
  std::vector<int16_t> level_table_, levels_;  // the level of each 16 bits (for level_sigma_); this tick's
  float level_sigma_ = -1.0f;
  Rng white_, bias_, drift_, dropout_;
  std::vector<float> offsets_, normals_, held_bias_;  // float: what a sensor's error needs
  std::vector<double> drift_state_;
  std::vector<uint8_t> lost_;
  double drift_decay_ = 0.0, drift_step_ = 0.0;
};

// A reading held back `delay` ticks: push this tick's, get the one that arrives now (until `delay`
// ticks have passed, the first one). No allocation once reset.
template <class Reading>
class DelayLine {
 public:
  void reset(int delay) {
    // Sized, not filled: a slot is read only after it was pushed (an Eigen vector's Reading{}
    // holds no values to copy).
    ring_.clear();
    ring_.resize(size_t(delay) + 1);
    pushed_ = 0;
  }
  const Reading& push(const Reading& now) {
    const size_t n = ring_.size();
    ring_[pushed_ % n] = now;
    ++pushed_;
    return pushed_ <= n ? ring_[0] : ring_[pushed_ % n];
  }

 private:
  std::vector<Reading> ring_;
  size_t pushed_ = 0;
};

// Which pixels of a noisy image read as the stimulus, from their coverage, the way a robot cleans
// a colour mask: a pixel reads as it when its coverage is at least kStimulusStrong; then an
// opening drops a pixel that reads so alone (at 40 levels of noise a few in a hundred pixels of a
// colour 130 levels from the stimulus's read as it, each by itself), and a closing fills a single
// pixel between two that read so (as a few of the stimulus's own pixels read otherwise); a filled
// pixel's coverage is raised to kStimulusStrong. The coverage of those pixels and of their
// neighbours (the edges) is kept, the rest cleared, and [stimulus_first, stimulus_last] narrowed
// to what is left. (Images without noise are exact and never pass through it.)
void threshold_coverage(EyeImage& image);

// The noise of every sense of one episode (World::sense_noise applies it to a copy of the true
// senses each tick).
class SenseNoise {
 public:
  void reset(const NoiseParams& params, uint64_t world_seed, int eye_pixels, double tick_seconds);
  // The joints and the base: offsets, resolution, delay, dropped readings (held). The heading
  // joint reads the noisy heading; velocities stay exact.
  void pose(Senses& s);
  // Both eyes' images: colour noise per pixel and channel, coverage re-estimated from the noisy
  // colours, resolution; then delay and dropped frames (an eye whose frame is lost keeps its last
  // one). Returns, per eye, whether a frame arrived (else the image is the last one delivered).
  void images(Senses& s, bool arrived[2]);
  // Touch: each contact's forces scaled by max(0, 1 + noise), resolution, delay, lost contacts.
  void touch(Senses& s);
  // Effort, once per tick before the physics steps: draws the tick's factors and lost commands,
  // and returns the factor per degree of freedom, max(0, 1 + noise) (null when none).
  const double* effort();
  // Whether commands are delivered otherwise than given (late, lost or on a grid).
  bool alters_commands() const;
  // The commanded errors as delivered this tick: late, lost (NaN: that setpoint stays), on the grid.
  DofVector commands(const DofVector& errors);

 private:
  ChannelProcess image_, joints_, base_, touch_, effort_;
  DelayLine<std::array<double, 6>> joint_delay_;
  DelayLine<std::array<double, 4>> base_delay_;
  DelayLine<EyeImage> eye_delay_[2];
  DelayLine<std::array<Touch, kTactileCount>> touch_delay_;
  DelayLine<DofVector> command_delay_;
  std::array<double, 6> joints_held_{};
  std::array<double, 4> base_held_{};
  bool joints_valid_ = false, base_valid_ = false;  // a reading has been delivered to hold
  EyeImage last_eye_[2];  // the frames delivered last (held when a frame is lost)
  bool eye_valid_[2] = {false, false};
  DofVector factors_ = DofVector::Ones();
};

}  // namespace roger
