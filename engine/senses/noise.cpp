#include "senses/noise.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/shape.h"
#include "senses/senses_internal.h"

namespace roger {

namespace {

// The variance one channel's kinds add to a reading: white, bias and drift, and a resolution's
// rounding (uniform over a step).
double variance(const ChannelNoise& n) {
  const double drift = n.drift_tau > 0.0 ? n.drift : 0.0;
  return n.sigma * n.sigma + n.bias * n.bias + drift * drift + n.quantum * n.quantum / 12.0;
}

// The standard normal quantile at p in (0, 1): Acklam's rational approximation (relative error
// 1.2e-9), refined by one Halley step on the complementary error function.
double normal_quantile(double p) {
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                             1.383577518672690e+02, -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01, -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00, 2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  double x;
  if (p < 0.02425) {
    const double q = std::sqrt(-2.0 * std::log(p));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  } else if (p > 1.0 - 0.02425) {
    const double q = std::sqrt(-2.0 * std::log(1.0 - p));
    x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  } else {
    const double q = p - 0.5, r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
  }
  const double e = 0.5 * std::erfc(-x / std::sqrt(2.0)) - p;
  const double u = e * std::sqrt(2.0 * M_PI) * std::exp(x * x / 2.0);
  return x - u / (1.0 + x * u / 2.0);
}

// The quantiles at the midpoints of the upper 32768 of the 65536 equal slices of probability,
// made once (128 KiB: the lower half is their mirror image, and a table that stays in the cache is
// what makes a thousand draws a tick cheap).
const float* normal_table() {
  static const std::vector<float> table = [] {
    std::vector<float> t(32768);
    for (int k = 0; k < 32768; ++k) t[size_t(k)] = float(normal_quantile((32768 + k + 0.5) / 65536.0));
    return t;
  }();
  return table.data();
}

// The standard normal of 16 bits from `table`: the low 15 bits pick the slice of the upper half,
// the top bit the side.
// The sign goes on by its bit, not by a branch (which the random bits would mispredict half the time).
inline float table_value(const float* table, uint64_t bits) {
  const float v = table[bits & 0x7FFF];
  uint32_t u;
  std::memcpy(&u, &v, sizeof u);
  u ^= uint32_t(bits & 0x8000) << 16;
  float out;
  std::memcpy(&out, &u, sizeof out);
  return out;
}

// The stream names: a channel's kind, mixed into the world's seed.
enum Kind : uint64_t { kWhite = 1, kBias = 2, kDrift = 3, kDropout = 4 };
uint64_t stream_seed(uint64_t world_seed, NoiseChannel channel, Kind kind) {
  return Rng::mix(Rng::mix(world_seed, 0x6E6F697365ull /* "noise" */), uint64_t(channel) * 16 + kind);
}

// An offset rounded to a whole level, half up (an offset beyond 300 levels saturates a byte either
// way). Selections rather than std::min/max/clamp (which return references): the vectorizer
// if-converts these.
inline int rounded_level(float noise) {
  noise = noise < -300.0f ? -300.0f : noise;
  noise = noise > 300.0f ? 300.0f : noise;
  return int(noise + 300.5f) - 300;
}

// Every colour channel of an image moved by its noise (three per pixel, as the colours lie: a
// Colour is three bytes): the value moved by its offset rounded to a whole level (`levels`, or
// `noise` rounded here when levels is null), on the resolution's grid (none when 0), clamped to a
// byte. Branch-free and contiguous, so the compiler runs it on vectors.
__attribute__((always_inline)) inline void noisy_channels(const uint8_t* was, const int16_t* levels, const float* noise,
                                                          int quantum, uint8_t* out, int n) {
  alignas(32) int16_t moved[3 * kMaxPixels];
  if (levels)
    for (int k = 0; k < n; ++k) moved[k] = int16_t(was[k] + levels[k]);
  else
    for (int k = 0; k < n; ++k) moved[k] = int16_t(was[k] + rounded_level(noise[k]));
  auto to_byte = [](int v) { return uint8_t(v < 0 ? 0 : v > 255 ? 255 : v); };
  if (quantum > 0) {  // integer division: no vectors, and rare
    for (int k = 0; k < n; ++k) out[k] = to_byte((moved[k] + quantum / 2) / quantum * quantum);
    return;
  }
  for (int k = 0; k < n; ++k) out[k] = to_byte(moved[k]);
}
static_assert(sizeof(Colour) == 3, "a row of colours is a row of bytes");

// threshold_coverage's body, inlined into it and into each image noise kernel below.
__attribute__((always_inline)) inline void threshold_body(EyeImage& image) {
  const int pixels = image.pixels();
  float* coverage = image.stimulus.data();
  // Masks with a clear pixel at each end (index u + 1 is pixel u), so no test needs a bound.
  uint8_t strong[kMaxPixels + 2], opened[kMaxPixels + 2], run[kMaxPixels + 2];
  strong[0] = strong[pixels + 1] = opened[0] = opened[pixels + 1] = run[0] = run[pixels + 1] = 0;
  for (int u = 0; u < pixels; ++u) strong[u + 1] = coverage[u] >= kStimulusStrong;
  for (int k = 1; k <= pixels; ++k) opened[k] = strong[k] & (strong[k - 1] | strong[k + 1]);
  for (int k = 1; k <= pixels; ++k) run[k] = opened[k] | (opened[k - 1] & opened[k + 1]);
  // Selections, so these passes run on vectors too; the bounds from the mask of what is left,
  // eight pixels a word.
  uint8_t kept[kMaxPixels];
  for (int u = 0; u < pixels; ++u) kept[u] = run[u] | run[u + 1] | run[u + 2];
  alignas(8) uint8_t left[kMaxPixels + 8] = {};
  for (int u = 0; u < pixels; ++u) {
    const float raised = std::max(coverage[u], run[u + 1] ? kStimulusStrong : 0.0f);  // coverage >= 0
    coverage[u] = kept[u] ? raised : 0.0f;
    left[u] = coverage[u] > 0.0f;
  }
  int first = pixels, last = -1;
  for (int w = 0; w < pixels; w += 8) {
    uint64_t word;
    std::memcpy(&word, left + w, sizeof word);
    if (!word) continue;  // a word with a pixel left has one in [w, w + 8)
    if (first == pixels)
      for (first = w; !left[first];) ++first;
    for (last = w + 7; !left[last];) --last;
  }
  image.stimulus_first = int16_t(first), image.stimulus_last = int16_t(last);
}

// Colour noise on one eye's image, from its offsets (three per pixel: `levels`, else `noise`):
// each pixel's stimulus coverage moves by the colour's change projected on the axis from the
// pixel's background colour to the stimulus colour (a pixel whose centre is on the stimulus has no
// colour of its own to mix with: grey stands in), and is clamped to [0, 1]; then the mask is
// cleaned. Integer colours, so the projection is exact; one division per pixel. Two passes that
// run on vectors: the colours, then each pixel's projection and coverage (the compiler gathers
// the three colours of each pixel; selections, not the branches the noise's sign would
// mispredict). A body inlined into each kernel below.
__attribute__((always_inline)) inline void image_noise_body(EyeImage& image, const int16_t* levels, const float* noise,
                                                            int quantum) {
  const Colour s = image.stimulus_colour;
  const int pixels = image.pixels(), n = 3 * pixels;
  uint8_t* colours = &image.colour[0].r;
  alignas(32) uint8_t was[3 * kMaxPixels];
  std::memcpy(was, colours, size_t(n));
  noisy_channels(was, levels, noise, quantum, colours, n);
  // Each pixel's change projected on its axis; a pixel of the stimulus colour (no axis of its
  // own) on grey's. Selections, not branches: the pixels of an object in view are of its colour.
  const int s0 = s.r, s1 = s.g, s2 = s.b, g0 = s0 - 128, g1 = s1 - 128, g2 = s2 - 128;
  const int grey2 = std::max(1, g0 * g0 + g1 * g1 + g2 * g2);
  float* coverage = image.stimulus.data();
  for (int u = 0; u < pixels; ++u) {
    const int w0 = was[3 * u], w1 = was[3 * u + 1], w2 = was[3 * u + 2];
    const int d0 = colours[3 * u] - w0, d1 = colours[3 * u + 1] - w1, d2 = colours[3 * u + 2] - w2;
    const int a0 = s0 - w0, a1 = s1 - w1, a2 = s2 - w2;
    const int axis2 = a0 * a0 + a1 * a1 + a2 * a2;
    const int along = d0 * a0 + d1 * a1 + d2 * a2, along_grey = d0 * g0 + d1 * g1 + d2 * g2;
    const float moved = float(axis2 != 0 ? along : along_grey), length2 = float(axis2 != 0 ? axis2 : grey2);
    const float c = coverage[u] + moved / length2;
    coverage[u] = c < 0.0f ? 0.0f : c > 1.0f ? 1.0f : c;
  }
  threshold_body(image);
  image.noisy = true;
}

// The image noise compiled three times: for any x86-64 processor, for one with AVX2 (twice the
// lanes, and 32-bit integer multiplies in one instruction where SSE2 needs several) and for one
// with AVX-512 (twice again, and byte and word operations on them), chosen once by the processor it
// runs on. The passes are integer ones, and the float ones the same operations in the same order:
// a sum of a quotient, never a product a fused multiply-add could join (and the file is compiled
// with -ffp-contract=off), so every width gives the same bits.
void image_noise_generic(EyeImage& image, const int16_t* levels, const float* noise, int quantum) {
  image_noise_body(image, levels, noise, quantum);
}
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define ROGER_WIDE_IMAGE_NOISE 1
__attribute__((target("avx2"))) void image_noise_avx2(EyeImage& image, const int16_t* levels, const float* noise,
                                                      int quantum) {
  image_noise_body(image, levels, noise, quantum);
}
__attribute__((target("avx512f,avx512bw,avx512vl,avx512dq"))) void image_noise_avx512(EyeImage& image,
                                                                                      const int16_t* levels,
                                                                                      const float* noise, int quantum) {
  image_noise_body(image, levels, noise, quantum);
}
#endif

// The kernel of `width`, or null where this processor cannot run it.
using ImageNoiseKernel = void (*)(EyeImage&, const int16_t*, const float*, int);
ImageNoiseKernel kernel_of(senses_internal::NoiseWidth width) {
  using senses_internal::NoiseWidth;
  if (width == NoiseWidth::kGeneric) return image_noise_generic;
#ifdef ROGER_WIDE_IMAGE_NOISE
  static const bool avx2 = __builtin_cpu_supports("avx2");
  static const bool avx512 = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
                             __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq");
  if (width == NoiseWidth::kAvx2 && avx2) return image_noise_avx2;
  if (width == NoiseWidth::kAvx512 && avx512) return image_noise_avx512;
#endif
  return nullptr;
}

void image_noise(EyeImage& image, const int16_t* levels, const float* noise, int quantum) {
  static const ImageNoiseKernel widest = kernel_of(senses_internal::widest_image_noise());
  widest(image, levels, noise, quantum);
}

// A reading the channel has lost this tick keeps the value delivered last.
template <size_t N>
void hold_lost(const ChannelProcess& p, std::array<double, N>& values, std::array<double, N>& held, bool& valid) {
  for (size_t k = 0; k < N; ++k) {
    if (valid && p.lost(int(k))) values[k] = held[k];
    held[k] = values[k];
  }
  valid = true;
}

}  // namespace

void threshold_coverage(EyeImage& image) { threshold_body(image); }

namespace senses_internal {
NoiseWidth widest_image_noise() {
  for (NoiseWidth width : {NoiseWidth::kAvx512, NoiseWidth::kAvx2})
    if (kernel_of(width)) return width;
  return NoiseWidth::kGeneric;
}
bool image_noise_kernel(NoiseWidth width, EyeImage& image, const int16_t* levels, const float* noise, int quantum) {
  const ImageNoiseKernel kernel = kernel_of(width);
  if (kernel) kernel(image, levels, noise, quantum);
  return kernel != nullptr;
}
}  // namespace senses_internal

NoiseModel noise_model(const NoiseParams& params, const Camera& camera) {
  constexpr double kLevelsPerPixel = 100.0;  // colour levels of noise that shift the centre a pixel
  NoiseModel m;
  m.params = params;
  const double image = std::sqrt(variance(params.image)) / kLevelsPerPixel / camera.focal;
  m.stereo = StereoNoise{std::hypot(std::sqrt(variance(params.joints)), image), std::sqrt(variance(params.base))};
  m.any = params.any();
  return m;
}

float table_normal(uint16_t bits) { return table_value(normal_table(), bits); }

void ChannelProcess::reset(const ChannelNoise& noise, uint64_t world_seed, NoiseChannel channel, int components,
                           int readings, double tick_seconds, bool whole_levels) {
  noise_ = noise;
  table_ = normal_table();
  const bool drifts = noise.drift > 0.0 && noise.drift_tau > 0.0;
  // Levels only for white noise alone: a bias or drift is added before the rounding.
  const bool levels = whole_levels && noise.sigma > 0.0 && !(noise.bias > 0.0) && !drifts;
  levels_.assign(levels ? size_t(components) : 0, 0);
  if (levels && float(noise.sigma) != level_sigma_) {
    // What fill_normals and the rounding give for each 16 bits: products first, as fill_normals
    // stores them, then rounded as noisy_channels rounds an offset.
    level_sigma_ = float(noise.sigma);
    std::vector<float> products(65536);
    for (uint32_t b = 0; b < 65536; ++b) products[b] = level_sigma_ * table_value(table_, b);
    level_table_.resize(65536);
    for (uint32_t b = 0; b < 65536; ++b) level_table_[b] = int16_t(rounded_level(products[b]));
  }
  white_.reseed(stream_seed(world_seed, channel, kWhite));
  bias_.reseed(stream_seed(world_seed, channel, kBias));
  drift_.reseed(stream_seed(world_seed, channel, kDrift));
  dropout_.reseed(stream_seed(world_seed, channel, kDropout));
  offsets_.assign(size_t(components), 0.0f);
  normals_.assign(size_t(components), 0.0f);
  lost_.assign(size_t(readings), 0);
  held_bias_.assign(noise.bias > 0.0 ? size_t(components) : 0, 0.0f);
  if (!held_bias_.empty()) fill_normals(bias_, noise.bias, held_bias_.data(), held_bias_.size());
  drift_state_.assign(drifts ? size_t(components) : 0, 0.0);
  if (drifts) {
    // x' = a x + sigma sqrt(1 - a^2) n keeps the stationary sigma; its autocorrelation after t is
    // exp(-t / tau). The episode starts in the stationary distribution.
    drift_decay_ = std::exp(-tick_seconds / noise.drift_tau);
    drift_step_ = noise.drift * std::sqrt(1.0 - drift_decay_ * drift_decay_);
    fill_normals(drift_, noise.drift, normals_.data(), normals_.size());
    std::copy(normals_.begin(), normals_.end(), drift_state_.begin());
  }
}

namespace {

// Calls put(k, bits) with 16 bits for each k in [0, n): four per 64-bit draw from `stream`, the
// last few from one more draw (its unused bits dropped), so a channel draws ceil(n / 4) a tick
// whatever it makes of the bits.
template <class Put>
void for_each_16_bits(Rng& stream, size_t n, Put put) {
  size_t k = 0;
  for (; k + 4 <= n; k += 4) {
    const uint64_t bits = stream.next();
    put(k, bits & 0xFFFF), put(k + 1, (bits >> 16) & 0xFFFF), put(k + 2, (bits >> 32) & 0xFFFF), put(k + 3, bits >> 48);
  }
  if (k < n)
    for (uint64_t bits = stream.next(); k < n; ++k, bits >>= 16) put(k, bits & 0xFFFF);
}

}  // namespace

void ChannelProcess::fill_normals(Rng& stream, double sigma_in, float* out, size_t n) const {
  const float* table = table_;
  const float sigma = float(sigma_in);
  for_each_16_bits(stream, n, [&](size_t k, uint64_t bits) { out[k] = sigma * table_value(table, bits); });
}

void ChannelProcess::fill_levels(Rng& stream, int16_t* out, size_t n) const {
  const int16_t* table = level_table_.data();
  for_each_16_bits(stream, n, [&](size_t k, uint64_t bits) { out[k] = table[bits]; });
}

void ChannelProcess::draw() {
  const size_t n = offsets_.size();
  if (!levels_.empty()) {
    fill_levels(white_, levels_.data(), n);
  } else if (noise_.offsets()) {
    float* o = offsets_.data();
    if (noise_.sigma > 0.0) fill_normals(white_, noise_.sigma, o, n);
    else std::fill(offsets_.begin(), offsets_.end(), 0.0f);
    for (size_t k = 0; k < held_bias_.size(); ++k) o[k] += held_bias_[k];
    if (!drift_state_.empty()) {
      fill_normals(drift_, drift_step_, normals_.data(), n);
      for (size_t k = 0; k < n; ++k) {
        double& x = drift_state_[k];
        x = drift_decay_ * x + normals_[k];
        o[k] += float(x);
      }
    }
  }
  if (noise_.dropout > 0.0)
    for (uint8_t& l : lost_) l = dropout_.uniform() < noise_.dropout;
}

double ChannelProcess::quantize(double value) const {
  return noise_.quantum > 0.0 ? std::nearbyint(value / noise_.quantum) * noise_.quantum : value;
}

void SenseNoise::reset(const NoiseParams& n, uint64_t seed, int eye_pixels, double tick_seconds) {
  image_.reset(n.image, seed, NoiseChannel::kImage, 2 * eye_pixels * 3, 2, tick_seconds, true);
  joints_.reset(n.joints, seed, NoiseChannel::kJoints, 6, 6, tick_seconds);
  base_.reset(n.base, seed, NoiseChannel::kBase, 4, 4, tick_seconds);
  touch_.reset(n.touch, seed, NoiseChannel::kTouch, 2 * kTactileCount, kTactileCount, tick_seconds);
  effort_.reset(n.effort, seed, NoiseChannel::kEffort, kDofCount, kDofCount, tick_seconds);
  joint_delay_.reset(n.joints.delay);
  base_delay_.reset(n.base.delay);
  for (auto& d : eye_delay_) d.reset(n.image.delay);
  touch_delay_.reset(n.touch.delay);
  command_delay_.reset(n.effort.delay);
  joints_valid_ = base_valid_ = false;
  eye_valid_[0] = eye_valid_[1] = false;
  factors_ = DofVector::Ones();
}

void SenseNoise::pose(Senses& s) {
  if (joints_.noise().any()) {
    joints_.draw();
    std::array<double, 6> q;
    for (int k = 0; k < 6; ++k) q[size_t(k)] = joints_.quantize(s.q[kLeftEye + k] + joints_.offset(k));
    if (joints_.noise().delay > 0) q = joint_delay_.push(q);
    if (joints_.noise().dropout > 0.0) hold_lost(joints_, q, joints_held_, joints_valid_);
    for (int k = 0; k < 6; ++k) s.q[kLeftEye + k] = q[size_t(k)];
  }
  if (base_.noise().any()) {
    base_.draw();
    std::array<double, 4> b = {s.base.x + base_.offset(0), s.base.y + base_.offset(1),
                               s.base.theta + base_.offset(2), s.q[kBaseForward] + base_.offset(3)};
    for (double& v : b) v = base_.quantize(v);
    if (base_.noise().delay > 0) b = base_delay_.push(b);
    if (base_.noise().dropout > 0.0) hold_lost(base_, b, base_held_, base_valid_);
    s.base.x = b[0], s.base.y = b[1], s.base.theta = wrap_angle(b[2]), s.q[kBaseForward] = b[3];
    s.q[kBaseHeading] = s.base.theta;
  }
}

void SenseNoise::images(Senses& s, bool arrived[2]) {
  arrived[0] = arrived[1] = true;
  if (!image_.noise().any()) return;
  image_.draw();
  const bool colours = image_.noise().offsets() || image_.noise().quantum > 0.0;
  const int quantum = int(std::lround(image_.noise().quantum));
  for (int e = 0; e < 2; ++e) {
    EyeImage& image = s.image[e];
    const size_t first = size_t(e * image.pixels() * 3);
    if (colours)
      image_noise(image, image_.levels() ? image_.levels() + first : nullptr,
                  image_.levels() ? nullptr : image_.offsets() + first, quantum);
    if (image_.noise().delay > 0) image = eye_delay_[e].push(image);
    if (image_.noise().dropout > 0.0) {
      if (eye_valid_[e] && image_.lost(e)) image = last_eye_[e], arrived[e] = false;
      else last_eye_[e] = image;
      eye_valid_[e] = true;
    }
  }
}

void SenseNoise::touch(Senses& s) {
  if (!touch_.noise().any()) return;
  touch_.draw();
  for (int t = 0; t < kTactileCount; ++t) {
    Touch& c = s.touch[t];
    if (!c.contact) continue;
    c.force = touch_.quantize(c.force * std::max(0.0, 1.0 + touch_.offset(2 * t)));
    c.friction = touch_.quantize(c.friction * std::max(0.0, 1.0 + touch_.offset(2 * t + 1)));
  }
  if (touch_.noise().delay > 0) {
    std::array<Touch, kTactileCount> now;
    std::copy(std::begin(s.touch), std::end(s.touch), now.begin());
    const auto& late = touch_delay_.push(now);
    std::copy(late.begin(), late.end(), std::begin(s.touch));
  }
  if (touch_.noise().dropout > 0.0)
    for (int t = 0; t < kTactileCount; ++t)
      if (touch_.lost(t)) s.touch[t] = Touch{};  // not felt this tick
}

const double* SenseNoise::effort() {
  if (!effort_.noise().any()) return nullptr;
  effort_.draw();  // the factors and the lost commands of this tick
  if (!effort_.noise().offsets()) return nullptr;
  for (int d = 0; d < kDofCount; ++d) factors_[d] = std::max(0.0, 1.0 + effort_.offset(d));
  return factors_.data();
}

bool SenseNoise::alters_commands() const {
  const ChannelNoise& n = effort_.noise();
  return n.delay > 0 || n.dropout > 0.0 || n.quantum > 0.0;
}

DofVector SenseNoise::commands(const DofVector& errors) {
  const ChannelNoise& n = effort_.noise();
  DofVector out = errors;
  for (int d = 0; d < kDofCount; ++d) out[d] = effort_.quantize(out[d]);
  if (n.delay > 0) out = command_delay_.push(out);
  if (n.dropout > 0.0)
    for (int d = 0; d < kDofCount; ++d)
      if (effort_.lost(d)) out[d] = NAN;  // lost: that setpoint stays where it was
  return out;
}

}  // namespace roger
