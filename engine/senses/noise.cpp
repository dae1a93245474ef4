#include "senses/noise.h"

#include <algorithm>
#include <cmath>

#include "core/shape.h"

namespace roger {

NoiseModel noise_model(const NoiseParams& params, const Camera& camera) {
  constexpr double kLevelsPerPixel = 100.0;  // colour levels of noise that shift the centre a pixel
  NoiseModel m;
  m.params = params;
  m.stereo = StereoNoise{std::hypot(params.joints, params.image / kLevelsPerPixel / camera.focal), params.base};
  m.any = params.any();
  return m;
}

namespace {

// Standard normal values drawn two at a time (Box-Muller's both outputs, one logarithm and one
// square root per pair): the image noise draws three per pixel, six per pair of pixels.
class NormalPairs {
 public:
  explicit NormalPairs(Rng& rng) : rng_(rng) {}
  double next() {
    if (has_spare_) return has_spare_ = false, spare_;
    double u1 = rng_.uniform();
    while (u1 <= 0.0) u1 = rng_.uniform();
    const double r = std::sqrt(-2.0 * std::log(u1)), a = 6.283185307179586 * rng_.uniform();
    spare_ = r * std::sin(a), has_spare_ = true;
    return r * std::cos(a);
  }

 private:
  Rng& rng_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

// The noisy reading of one colour channel, rounded and clamped to a byte.
uint8_t noisy_channel(uint8_t value, double noise) {
  return uint8_t(std::clamp(std::lround(double(value) + noise), 0L, 255L));
}

// The stimulus coverage a noise vector adds to a pixel whose background colour is `back`: its
// projection on the axis from the background to the stimulus, in units of that axis's length.
double coverage_noise(const Colour& stimulus, const Colour& back, const double n[3]) {
  const double d[3] = {double(stimulus.r) - back.r, double(stimulus.g) - back.g, double(stimulus.b) - back.b};
  const double d2 = std::max(1.0, d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  return (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]) / d2;
}

// Keeps the coverage of pixels that read as the stimulus and of their neighbours (edge pixels);
// clears the rest, and narrows [stimulus_first, stimulus_last] to what is left.
void threshold_coverage(EyeImage& image) {
  const int pixels = image.pixels();
  int first = pixels, last = -1;
  bool strong_before = false;  // pixel u - 1 read as the stimulus (before clearing)
  for (int u = 0; u < pixels; ++u) {
    const bool strong = image.stimulus[size_t(u)] >= kStimulusStrong;
    const bool strong_after = u + 1 < pixels && image.stimulus[size_t(u + 1)] >= kStimulusStrong;
    if (!strong && !strong_before && !strong_after) image.stimulus[size_t(u)] = 0.0f;
    strong_before = strong;
    if (image.stimulus[size_t(u)] > 0.0f) first = std::min(first, u), last = u;
  }
  image.stimulus_first = int16_t(first), image.stimulus_last = int16_t(last);
}

}  // namespace

void add_image_noise(EyeImage& image, double sigma, Rng& rng) {
  if (!(sigma > 0.0)) return;
  const Colour grey{128, 128, 128};
  const Colour s = image.stimulus_colour;
  NormalPairs normal(rng);
  for (int u = 0; u < image.pixels(); ++u) {
    Colour& c = image.colour[size_t(u)];
    const double n[3] = {sigma * normal.next(), sigma * normal.next(), sigma * normal.next()};
    // A pixel whose centre is on the stimulus has no colour of its own to mix with: grey stands in.
    const double e = coverage_noise(s, c == s ? grey : c, n);
    float& coverage = image.stimulus[size_t(u)];
    coverage = float(std::clamp(double(coverage) + e, 0.0, 1.0));
    c = Colour{noisy_channel(c.r, n[0]), noisy_channel(c.g, n[1]), noisy_channel(c.b, n[2])};
  }
  threshold_coverage(image);
  image.noisy = true;
}

void add_pose_noise(Senses& s, const NoiseParams& noise, Rng& rng) {
  if (noise.joints > 0.0)
    for (int d = kLeftEye; d < kDofCount; ++d) s.q[d] += rng.normal(0.0, noise.joints);
  if (noise.base > 0.0) {
    s.base.x += rng.normal(0.0, noise.base);
    s.base.y += rng.normal(0.0, noise.base);
    s.base.theta = wrap_angle(s.base.theta + rng.normal(0.0, noise.base));
    s.q[kBaseForward] += rng.normal(0.0, noise.base);
    s.q[kBaseHeading] = s.base.theta;
  }
}

void add_touch_noise(Senses& s, double sigma, Rng& rng) {
  if (!(sigma > 0.0)) return;
  for (Touch& t : s.touch) {
    if (!t.contact) continue;
    t.force *= std::max(0.0, 1.0 + rng.normal(0.0, sigma));
    t.friction *= std::max(0.0, 1.0 + rng.normal(0.0, sigma));
  }
}

void draw_effort_noise(DofVector& factors, double sigma, Rng& rng) {
  if (!(sigma > 0.0)) return;
  for (int d = 0; d < kDofCount; ++d) factors[d] = std::max(0.0, 1.0 + rng.normal(0.0, sigma));
}

}  // namespace roger
