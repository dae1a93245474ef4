// test_noise.cpp: the sensor and actuator noise (senses/noise.cpp, world:robot{ noise = ... }):
// refused when out of range, each kind (white, bias, drift, delay, dropout, resolution) doing what
// it says, each channel and kind its own stream, seeded by the world's seed alone, nothing when its
// levels are 0, judges as exact as the true senses allow, and the scripted task still done under
// the moderate level M.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <filesystem>
#include <fstream>
#include <string>

#include "batch/batch.h"
#include "batch/trainer.h"
#include "control/agent.h"
#include "learn/episode.h"
#include "script/curriculum/curriculum.h"
#include "script/scenario/scenario.h"
#include "script/skills/skill_script.h"
#include "senses/noise.h"
#include "senses/senses_internal.h"
#include "sim/world.h"
#include "scenario_text.h"
#include "world_fixtures.h"

using namespace roger;
using Catch::Matchers::Contains;
using roger::test::robot_error;

namespace {

// The moderate level M (docs/results.md, Noise), scaled.
NoiseParams moderate(double scale) {
  NoiseParams n;
  n.image.sigma = 10.0 * scale, n.joints.sigma = 0.01 * scale, n.base.sigma = 0.01 * scale;
  n.touch.sigma = 0.1 * scale, n.effort.sigma = 0.1 * scale;
  return n;
}

// Every kind on every channel at once (the parameters noise_<channel>_<kind>), on top of M.
void set_every_kind(Scenario& s) {
  const std::pair<const char*, const char*> kinds[] = {
      {"noise_image_bias", "5"},       {"noise_image_drift", "5"},       {"noise_image_tau", "5"},
      {"noise_image_dropout", "0.05"}, {"noise_image_quantum", "2"},     {"noise_joints_bias", "0.01"},
      {"noise_joints_drift", "0.01"},  {"noise_joints_tau", "10"},       {"noise_joints_delay", "2"},
      {"noise_joints_dropout", "0.05"},{"noise_joints_quantum", "0.005"},{"noise_base_bias", "0.01"},
      {"noise_touch_dropout", "0.05"}, {"noise_touch_delay", "1"},       {"noise_effort_delay", "1"},
      {"noise_effort_dropout", "0.02"}};
  for (const auto& [k, v] : kinds) s.set_param(k, v);
}

// The scenario parameters of M, scaled, on a loaded scenario.
void set_moderate(Scenario& s, double scale) {
  const std::pair<const char*, const char*> m[] = {{"noise_image", "10"},  {"noise_joints", "0.01"},
                                                   {"noise_base", "0.01"}, {"noise_touch", "0.1"},
                                                   {"noise_effort", "0.1"}};
  for (const auto& [k, v] : m) s.set_param(k, v);
  s.set_param("noise_scale", std::to_string(scale));
}

// Whether two sets of senses agree to the bit in what the controllers read.
bool same_senses(const Senses& a, const Senses& b) {
  bool same = std::memcmp(a.q.data(), b.q.data(), sizeof(double) * kDofCount) == 0 &&
              std::memcmp(&a.base, &b.base, sizeof a.base) == 0 && a.stereo_valid == b.stereo_valid &&
              std::memcmp(a.stimulus_world.data(), b.stimulus_world.data(), 2 * sizeof(double)) == 0;
  for (int e = 0; e < 2; ++e) {
    same = same && a.stimulus[e].seen == b.stimulus[e].seen && a.stimulus[e].bearing == b.stimulus[e].bearing;
    same = same && std::memcmp(a.image[e].stimulus.data(), b.image[e].stimulus.data(), sizeof(float) * 128) == 0;
    for (int u = 0; u < 128; ++u) same = same && a.image[e].colour[u] == b.image[e].colour[u];
  }
  for (int t = 0; t < kTactileCount; ++t) same = same && a.touch[t].force == b.touch[t].force;
  return same;
}

// Drives a world with a fixed command for `ticks` ticks and returns its state hash.
uint64_t drive(World& w, const WorldSpec& spec, int ticks) {
  w.reset(spec);
  DofVector cmd = DofVector::Zero();
  cmd[kBaseForward] = 0.05, cmd[kBaseHeading] = 0.05, cmd[kLeftEye] = 0.1, cmd[kLeftShoulder] = 0.1;
  for (int i = 0; i < ticks; ++i) {
    w.command(cmd);
    w.tick();
  }
  return w.state_hash();
}

// Replays recorded errors, one per tick: a trajectory that owes nothing to what the senses say.
class Replay final : public Controller {
 public:
  explicit Replay(std::vector<DofVector> errors) : errors_(std::move(errors)) { set_name("replay"); }
  const char* kind() const override { return "replay"; }

 protected:
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    out.command = errors_[std::min<size_t>(in.tick, errors_.size() - 1)];
    gamma = Gamma::kNotConv;
  }

 private:
  std::vector<DofVector> errors_;
};

}  // namespace

TEST_CASE("world:robot refuses bad noise with the file, line, field and range", "[noise]") {
  CHECK_THAT(robot_error("noise_image", "{ x = 0, y = 0, noise = { image = 300 } }"),
             Contains("roger_test_noise_image.lua:2:") &&
                 Contains("world:robot: noise: field 'image' must be within [0, 255] colour levels, got 300"));
  CHECK_THAT(robot_error("noise_negative", "{ x = 0, y = 0, noise = { joints = -0.1 } }"),
             Contains(":2:") && Contains("field 'joints' must be within [0, 1] rad, got -0.1"));
  CHECK_THAT(robot_error("noise_unknown", "{ x = 0, y = 0, noise = { odometry = 1 } }"),
             Contains(":2:") && Contains("unknown field 'odometry'; known fields: base, effort, image, joints, touch"));
  CHECK_THAT(robot_error("noise_type", "{ x = 0, y = 0, noise = 3 }"), Contains(":2:") && Contains("noise"));
  CHECK_THAT(robot_error("noise_delay", "{ x = 0, y = 0, noise = { joints = { sigma = 0.01, delay = 60 } } }"),
             Contains(":2:") && Contains("field 'delay' must be within [0, 50] ticks, got 60"));
  CHECK_THAT(robot_error("noise_tau", "{ x = 0, y = 0, noise = { base = { drift = { sigma = 0.01 } } } }"),
             Contains(":2:") && Contains("field 'tau' is missing: a drift with a sigma needs its correlation time"));
  CHECK_THAT(robot_error("noise_drift_sigma", "{ x = 0, y = 0, noise = { joints = { drift = { tau = 10 } } } }"),
             Contains(":2:") && Contains("noise.joints.drift: field 'sigma' is missing: a drift is its stationary "
                                         "sigma, in rad, and its correlation time tau (sigma = 0 for none)"));
  CHECK_THAT(robot_error("noise_tau0", "{ x = 0, y = 0, noise = { base = { drift = { sigma = 0.01, tau = 0 } } } }"),
             Contains(":2:") && Contains("noise.base.drift: field 'tau' must be within (0, 3600] s, got 0"));
  CHECK_THAT(robot_error("noise_kind", "{ x = 0, y = 0, noise = { touch = { jitter = 1 } } }"),
             Contains(":2:") && Contains("unknown field 'jitter'") && Contains("bias, delay, drift, dropout, quantum, sigma"));
  CHECK_THAT(robot_error("noise_dropout", "{ x = 0, y = 0, noise = { image = { dropout = 1.5 } } }"),
             Contains(":2:") && Contains("field 'dropout' must be within [0, 1]"));
  Scenario s = Scenario::load("unobstructed");
  set_moderate(s, 2.0);
  s.set_param("noise_joints_bias", "0.01");
  s.set_param("noise_joints_drift", "0.005");
  s.set_param("noise_joints_tau", "4");
  s.set_param("noise_image_delay", "2");
  s.set_param("noise_touch_dropout", "0.1");
  s.set_param("noise_base_quantum", "0.001");
  const WorldSpec w = s.generate(5);
  CHECK(w.noise.image.sigma == 20.0);
  CHECK(w.noise.joints.sigma == 0.02);
  CHECK(w.noise.effort.sigma == 0.2);
  CHECK(w.noise.joints.bias == 0.02);                 // scaled by noise_scale
  CHECK(w.noise.joints.drift == 0.01);
  CHECK(w.noise.joints.drift_tau == 4.0);             // a time, not scaled
  CHECK(w.noise.image.delay == 4);                    // scaled, whole ticks
  CHECK(w.noise.touch.dropout == Approx(0.2));
  CHECK(w.noise.base.quantum == Approx(0.002));
  CHECK(w.noise.any());
  CHECK(!Scenario::load("unobstructed").generate(5).noise.any());
}

// Found by a probe: a scenario with body.with_params that did not pass body.noise_of(p) to its
// robot took --set noise_image=200, echoed it, and ran without noise.
TEST_CASE("a noise parameter the world does not use is refused at the generator", "[noise]") {
  const std::string head = "local body = require('lib.body')\nreturn { params = body.with_params{},\n"
                           "  generate = function(world, rng, p)\n";
  Scenario none = test::scenario_from("noise_unused", head + "    world:robot{ x = 0, y = 0 }\n  end }\n");
  CHECK_NOTHROW(none.generate(0));  // at their defaults (0) the parameters ask for nothing
  none.set_param("noise_image", "200");
  CHECK_THROWS_WITH(none.generate(0),
                    Contains("roger_test_noise_unused.lua:3:") &&
                        Contains("the parameter noise_image = 200 asks for image noise, but the world has none: pass "
                                 "body.noise_of(params) to world:robot{ noise = ... }"));
  // Scaled to nothing, or a delay that rounds to no tick, asks for none.
  none.set_param("noise_scale", "0");
  CHECK_NOTHROW(none.generate(0));
  none.set_param("noise_image", "0");
  none.set_param("noise_image_delay", "1");
  none.set_param("noise_scale", "0.4");
  CHECK_NOTHROW(none.generate(0));
  // Noise of the scenario's own: at their defaults the parameters ask nothing of it; a kind it
  // lacks is asked for in vain. Found by a later probe: a level or a scale set away from its
  // default was recorded while the scenario's own levels ran, so each must give the world's very
  // level, as body.noise_of makes it.
  Scenario undeclared = test::scenario_from("noise_undeclared", head + "    world:robot{ x = 0, y = 0, noise = { joints = 0.01 } }\n  end }\n");
  CHECK_THROWS_WITH(undeclared.generate(0),
                    Contains("the parameter noise_joints = 0 (its default) asks for joints sigma = 0, but the world's "
                             "Roger has 0.01: its generator sets the noise itself rather than passing "
                             "body.noise_of(params) to world:robot{ noise = ... } (scenarios/lib/body.lua); pass it, or "
                             "give the world's levels as the parameters' defaults (body.with_params(params, { "
                             "noise_joints = ... }))"));
  const std::string with_defaults = "local body = require('lib.body')\n"
                                    "return { params = body.with_params({}, { noise_joints = 0.01 }),\n"
                                    "  generate = function(world, rng, p)\n";
  Scenario own = test::scenario_from("noise_own", with_defaults + "    world:robot{ x = 0, y = 0, noise = { joints = 0.01 } }\n  end }\n");
  CHECK_NOTHROW(own.generate(0));  // the parameters' defaults are the world's levels
  own.set_param("noise_joints", "0.02");
  CHECK_THROWS_WITH(own.generate(0), Contains("roger_test_noise_own.lua:3:") &&
                                         Contains("the parameter noise_joints = 0.02 asks for joints sigma = 0.02, but "
                                                  "the world's Roger has 0.01: its generator sets the noise itself"));
  own.set_param("noise_joints", "0.01");
  own.set_param("noise_joints_delay", "1");
  CHECK_THROWS_WITH(own.generate(0), Contains("the parameter noise_joints_delay = 1 asks for joints noise, but the "
                                              "world has none"));
  own.set_param("noise_joints_delay", "0");
  own.set_param("noise_joints_tau", "3");  // a drift's time, unscaled, that the world's noise has not
  CHECK_THROWS_WITH(own.generate(0), Contains("the parameter noise_joints_tau = 3 asks for joints drift tau = 3, but "
                                              "the world's Roger has no drift:"));
  own.set_param("noise_joints_tau", "10");
  own.set_param("noise_scale", "8");
  CHECK_THROWS_WITH(own.generate(0), Contains("noise_scale = 8 (times noise_joints = 0.01) asks for joints sigma = 0.08, "
                                              "but the world's Roger has 0.01") &&
                                         Contains("leave noise_scale at 1"));
}

TEST_CASE("sigma 0 is no noise, to the bit", "[noise]") {
  WorldSpec plain = test::open_world();
  plain.seed = 42;
  WorldSpec zero = plain;
  zero.noise = NoiseParams{};
  World a, b;
  CHECK(drive(a, plain, 150) == drive(b, zero, 150));
  CHECK(same_senses(a.senses(), b.senses()));
  CHECK(&a.senses() == &a.true_senses());
  // Each channel alone moves something (so the comparison above could fail).
  for (int k = 0; k < 5; ++k) {
    WorldSpec one = plain;
    ChannelNoise* channel[5] = {&one.noise.image, &one.noise.joints, &one.noise.base, &one.noise.touch,
                                &one.noise.effort};
    channel[k]->sigma = k == 0 ? 10.0 : 0.1;
    World c;
    const uint64_t h = drive(c, one, 150);
    INFO("noise channel " << k);
    if (k == 4) CHECK(h != drive(a, plain, 150));  // effort moves the world
    else if (k != 3) CHECK(!same_senses(c.senses(), c.true_senses()));
  }
}

// Found by a probe: an image quantum of 0.1 or 1 level rounds no colour, yet turned the noisy
// image's processing on and changed every trajectory. Colours are whole levels: such a quantum is
// none, and the world is the noise-free one to the bit; 1.6 rounds to 2 levels.
TEST_CASE("an image quantum of one level or less is none, to the bit", "[noise]") {
  Scenario s = Scenario::load("unobstructed");
  const WorldSpec plain = s.generate(3);
  for (const char* q : {"0.1", "0.5", "1", "1.4"}) {
    s.set_param("noise_image_quantum", q);
    const WorldSpec w = s.generate(3);
    INFO("quantum " << q);
    CHECK(w.noise.image.quantum == 0.0);
    CHECK_FALSE(w.noise.any());
    World a, b;
    CHECK(drive(a, plain, 100) == drive(b, w, 100));
  }
  s.set_param("noise_image_quantum", "1.6");
  CHECK(s.generate(3).noise.image.quantum == 2.0);
  s.set_param("noise_image_quantum", "2.5");
  CHECK(s.generate(3).noise.image.quantum == 3.0);  // half away from 0, as the senses round
}

TEST_CASE("the noise is a function of the world's seed alone", "[noise]") {
  WorldSpec spec = test::open_world();
  spec.seed = 7;
  spec.noise = moderate(2.0);
  World a, b, c;
  const uint64_t h = drive(a, spec, 200);
  drive(b, test::open_world(), 37);  // another world first: nothing of it carries over
  CHECK(drive(b, spec, 200) == h);
  CHECK(same_senses(a.senses(), b.senses()));
  spec.seed = 8;
  CHECK(drive(c, spec, 200) != h);
}

TEST_CASE("image noise moves colours and coverage but keeps the stimulus found", "[noise]") {
  World w;
  w.reset(test::open_world());
  const EyeImage& true_image = w.true_senses().image[kLeft];
  const Sighting truth = detect_stimulus(true_image);
  REQUIRE(truth.seen);
  NoiseParams params;
  params.image.sigma = 10.0;
  SenseNoise noise;
  noise.reset(params, 3, true_image.pixels(), 0.02);
  Senses s = w.true_senses();
  bool arrived[2];
  noise.images(s, arrived);
  CHECK((arrived[0] && arrived[1]));
  const EyeImage& image = s.image[kLeft];
  int moved = 0, stray = 0;
  double sum2 = 0.0;
  for (int u = 0; u < image.pixels(); ++u) {
    const int dr = int(image.colour[u].r) - int(true_image.colour[u].r);
    moved += image.colour[u] != true_image.colour[u];
    if (true_image.colour[u].r > 40 && true_image.colour[u].r < 215) sum2 += dr * dr;  // away from the clamps
    stray += image.stimulus[u] > 0.0f && true_image.stimulus[u] == 0.0f &&
             std::abs(u - truth.u) > 0.5 * (truth.u_hi - truth.u_lo) + 1.5;
  }
  CHECK(moved > image.pixels() / 2);
  CHECK(std::sqrt(sum2 / image.pixels()) == Approx(10.0).epsilon(0.25));  // whole levels of about sigma
  CHECK(stray == 0);  // no pixel of wall reads as the red ball at 10 levels
  const Sighting noisy = detect_stimulus(image);
  REQUIRE(noisy.seen);
  CHECK(std::abs(noisy.u - truth.u) < 0.3);
  CHECK(image.noisy);
}

// The mask a noisy image's stimulus is read from: a lone pixel reading as the stimulus is noise,
// a single pixel between two that read so is the stimulus, two side by side are kept, and each
// kept run keeps its edge pixels' coverage.
TEST_CASE("a noisy image's stimulus mask drops lone pixels and fills single gaps", "[noise]") {
  EyeImage image;
  image.camera.pixels = 32;
  std::fill(image.stimulus.begin(), image.stimulus.end(), 0.0f);
  auto set = [&](int u, float c) { image.stimulus[size_t(u)] = c; };
  set(2, 0.3f), set(3, 0.7f), set(4, 0.3f);                          // alone: noise
  set(9, 0.3f), set(10, 1.0f), set(11, 1.0f), set(12, 0.2f), set(13, 1.0f), set(14, 0.6f),
      set(15, 0.2f);                                                  // a run with a gap at 12
  set(20, 0.8f), set(21, 0.9f), set(22, 0.1f);                        // two pixels: kept
  set(25, 0.4f);                                                      // under half, alone
  set(31, 0.9f);                                                      // alone at the border
  threshold_coverage(image);
  for (int u : {2, 3, 4, 25, 31}) {
    INFO("pixel " << u);
    CHECK(image.stimulus[size_t(u)] == 0.0f);
  }
  CHECK(image.stimulus[12] == kStimulusStrong);  // the gap, filled
  for (int u : {9, 10, 11, 13, 14, 15, 20, 21, 22}) {
    INFO("pixel " << u);
    CHECK(image.stimulus[size_t(u)] > 0.0f);
  }
  CHECK(image.stimulus[9] == 0.3f);  // an edge keeps its coverage
  CHECK(image.stimulus_first == 9);
  CHECK(image.stimulus_last == 22);
  // Detection then finds the longer run, whole: the gap no longer splits it.
  image.noisy = true;
  std::fill(image.kind.begin(), image.kind.end(), SurfaceKind::kObject);
  std::fill(image.index.begin(), image.index.end(), int16_t(0));
  const Sighting seen = detect_stimulus(image);
  REQUIRE(seen.seen);
  CHECK(seen.u_lo < 10.0);
  CHECK(seen.u_hi > 14.0);
}

namespace {

// The image noise as docs/scenarios.md states it, one pixel and one colour at a time: each colour
// moved by its offset rounded half up to a whole level, put on the grid, clamped to a byte; the
// coverage moved by the colour's change projected on the axis from the pixel's colour to the
// stimulus's (grey's for a pixel of the stimulus colour), clamped to [0, 1]; then the mask
// cleaned: an opening, a closing, gaps raised to kStimulusStrong, all but runs and their edges
// cleared.
void reference_image_noise(EyeImage& image, const int16_t* levels, const float* noise, int quantum) {
  const Colour s = image.stimulus_colour;
  const int stim[3] = {s.r, s.g, s.b}, grey[3] = {s.r - 128, s.g - 128, s.b - 128};
  const int grey2 = std::max(1, grey[0] * grey[0] + grey[1] * grey[1] + grey[2] * grey[2]);
  const int n = image.pixels();
  for (int u = 0; u < n; ++u) {
    uint8_t* colour = &image.colour[size_t(u)].r;
    int d[3], a[3];
    for (int ch = 0; ch < 3; ++ch) {
      const int k = 3 * u + ch, was = colour[ch];
      int offset = levels ? levels[k] : 0;
      if (!levels) {
        const float x = std::clamp(noise[k], -300.0f, 300.0f);
        offset = int(x + 300.5f) - 300;
      }
      int moved = was + offset;
      if (quantum > 0) moved = (moved + quantum / 2) / quantum * quantum;
      colour[ch] = uint8_t(std::clamp(moved, 0, 255));
      d[ch] = colour[ch] - was, a[ch] = stim[ch] - was;
    }
    int along = d[0] * a[0] + d[1] * a[1] + d[2] * a[2], axis2 = a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
    if (axis2 == 0) along = d[0] * grey[0] + d[1] * grey[1] + d[2] * grey[2], axis2 = grey2;
    float& c = image.stimulus[size_t(u)];
    c = std::clamp(c + float(along) / float(axis2), 0.0f, 1.0f);
  }
  auto at = [&](const std::vector<int>& m, int u) { return u < 0 || u >= n ? 0 : m[size_t(u)]; };
  std::vector<int> strong(static_cast<size_t>(n), 0), opened = strong, run = strong;
  for (int u = 0; u < n; ++u) strong[size_t(u)] = image.stimulus[size_t(u)] >= kStimulusStrong;
  for (int u = 0; u < n; ++u) opened[size_t(u)] = at(strong, u) && (at(strong, u - 1) || at(strong, u + 1));
  for (int u = 0; u < n; ++u) run[size_t(u)] = at(opened, u) || (at(opened, u - 1) && at(opened, u + 1));
  int first = n, last = -1;
  for (int u = 0; u < n; ++u) {
    float& c = image.stimulus[size_t(u)];
    if (run[size_t(u)] && c < kStimulusStrong) c = kStimulusStrong;
    if (!at(run, u - 1) && !run[size_t(u)] && !at(run, u + 1)) c = 0.0f;
    if (c > 0.0f) first = std::min(first, u), last = u;
  }
  image.stimulus_first = int16_t(first), image.stimulus_last = int16_t(last);
  image.noisy = true;
}

// An image as the painter makes them, more varied: runs of surfaces, an object of the stimulus
// colour with edges of partial coverage, lone pixels of any colour and coverage.
EyeImage random_image(Rng& rng, int pixels) {
  EyeImage image;
  image.camera.pixels = pixels;
  auto byte = [&] { return uint8_t(rng.next() & 0xFF); };
  image.stimulus_colour = Colour{byte(), byte(), byte()};
  Colour surface{byte(), byte(), byte()};
  for (int u = 0; u < pixels; ++u) {
    const uint64_t roll = rng.next() % 100;
    if (roll < 8) surface = Colour{byte(), byte(), byte()};
    const bool object = roll >= 8 && roll < 30;
    image.colour[size_t(u)] = object ? image.stimulus_colour : roll < 35 ? Colour{byte(), byte(), byte()} : surface;
    image.stimulus[size_t(u)] = object ? 1.0f : roll < 45 ? float(rng.uniform()) : 0.0f;
  }
  if (rng.next() % 4 == 0) image.colour[0] = Colour{0, 0, 0}, image.colour[size_t(pixels - 1)] = Colour{255, 255, 255};
  return image;
}

}  // namespace

TEST_CASE("the image noise's kernels give the per-pixel model's image, bit for bit", "[noise]") {
  // Every kernel this processor runs (any x86-64, AVX2, AVX-512: every image goes through the
  // widest) against the model one pixel at a time, on whole levels and on float offsets (bias or
  // drift), with and without a resolution, on widths that are not whole vectors.
  using senses_internal::NoiseWidth;
  const NoiseWidth widths[] = {NoiseWidth::kGeneric, NoiseWidth::kAvx2, NoiseWidth::kAvx512};
  Rng rng(2024);
  int images[3] = {0, 0, 0}, moved = 0, kept = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int pixels = trial % 5 == 0 ? kMaxPixels : trial % 5 == 1 ? 37 : trial % 5 == 2 ? 256 : 128;
    const EyeImage clean = random_image(rng, pixels);
    const double sigma = trial % 3 == 0 ? 40.0 : trial % 3 == 1 ? 10.0 : 150.0;
    std::vector<int16_t> levels(size_t(3 * pixels));
    std::vector<float> noise(size_t(3 * pixels));
    for (size_t k = 0; k < noise.size(); ++k) {
      const float x = float(sigma) * table_normal(uint16_t(rng.next()));
      noise[k] = k % 17 == 0 ? std::round(x) + 0.5f : x;  // halves: the rounding's tie
      levels[k] = int16_t(std::clamp(int(std::lround(x)), -300, 300));
    }
    const bool whole = trial % 2 == 0;
    const int quantum = trial % 7 == 3 ? 5 : trial % 7 == 5 ? 2 : 0;
    const int16_t* l = whole ? levels.data() : nullptr;
    const float* f = whole ? nullptr : noise.data();
    EyeImage expected = clean;
    reference_image_noise(expected, l, f, quantum);
    for (const NoiseWidth width : widths) {
      EyeImage got = clean;
      if (!senses_internal::image_noise_kernel(width, got, l, f, quantum)) continue;
      INFO("trial " << trial << ", " << pixels << " pixels, width " << int(width) << ", quantum " << quantum);
      REQUIRE(std::memcmp(got.colour.data(), expected.colour.data(), sizeof(Colour) * size_t(pixels)) == 0);
      REQUIRE(std::memcmp(got.stimulus.data(), expected.stimulus.data(), sizeof(float) * size_t(pixels)) == 0);
      REQUIRE(got.stimulus_first == expected.stimulus_first);
      REQUIRE(got.stimulus_last == expected.stimulus_last);
      REQUIRE(got.noisy);
      ++images[int(width)];
    }
    for (int u = 0; u < pixels; ++u) {
      moved += expected.stimulus[size_t(u)] != clean.stimulus[size_t(u)];
      kept += expected.stimulus[size_t(u)] > 0.0f;
    }
  }
  // Each kernel up to the widest this processor runs took every image; none wider took any.
  const int widest = int(senses_internal::widest_image_noise());
  for (int w = 0; w < 3; ++w) CHECK(images[w] == (w <= widest ? 400 : 0));
  // The images exercise the model: coverages moved, raised and cleared, runs kept.
  CHECK(moved > 40000);  // 42503 of 89104 pixels
  CHECK(kept > 25000);   // 27048
}

// The table's normal: symmetric, of unit variance, and its quantiles where the normal's are.
TEST_CASE("the table normal is a standard normal to its resolution", "[noise]") {
  double sum = 0.0, sum2 = 0.0, sum4 = 0.0;
  int beyond2 = 0;
  for (int b = 0; b < 65536; ++b) {
    const double z = table_normal(uint16_t(b));
    sum += z, sum2 += z * z, sum4 += z * z * z * z;
    beyond2 += std::abs(z) > 1.959964;
  }
  CHECK(std::abs(sum) < 1e-3);
  CHECK(sum2 / 65536 == Approx(1.0).epsilon(1e-3));
  CHECK(sum4 / 65536 == Approx(3.0).epsilon(5e-3));  // the normal's kurtosis: its tails, not a uniform's
  CHECK(beyond2 / 65536.0 == Approx(0.05).epsilon(0.01));
  CHECK(table_normal(0x7FFF) == Approx(-table_normal(0xFFFF)).epsilon(1e-6));
}

// The image's white noise drawn as whole levels from a table (ChannelProcess, whole_levels) is the
// float noise of the same draws rounded as the colours round it, value for value, for any sigma
// and any count (four values a draw, and the rest of the last draw dropped).
TEST_CASE("white noise in whole levels is the float noise rounded, draw for draw", "[noise]") {
  for (const double sigma : {0.3, 10.0, 40.0, 255.0}) {
    for (const int components : {768, 6 * 33, 5}) {
      ChannelNoise white;
      white.sigma = sigma;
      ChannelProcess levels, floats;
      levels.reset(white, 77, NoiseChannel::kImage, components, 2, 0.02, true);
      floats.reset(white, 77, NoiseChannel::kImage, components, 2, 0.02, false);
      REQUIRE(levels.levels() != nullptr);
      REQUIRE(levels.offsets() == nullptr);
      REQUIRE(floats.levels() == nullptr);
      int differ = 0, nonzero = 0;
      for (int tick = 0; tick < 20; ++tick) {
        levels.draw(), floats.draw();
        for (int k = 0; k < components; ++k) {
          const float x = std::clamp(floats.offsets()[k], -300.0f, 300.0f);
          differ += levels.levels()[k] != int(x + 300.5f) - 300;
          nonzero += levels.levels()[k] != 0;
        }
      }
      INFO("sigma " << sigma << ", " << components << " components");
      CHECK(differ == 0);
      CHECK(nonzero > (sigma < 1.0 ? 0 : 10 * components));
    }
  }
  // A bias or a drift is added before the rounding: such a channel keeps its float offsets.
  ChannelNoise biased;
  biased.sigma = 10.0, biased.bias = 5.0;
  ChannelProcess p;
  p.reset(biased, 77, NoiseChannel::kImage, 12, 2, 0.02, true);
  CHECK(p.levels() == nullptr);
  CHECK(p.offsets() != nullptr);
}

TEST_CASE("touch and effort noise scale forces by about their sigma", "[noise]") {
  NoiseParams params;
  params.touch.sigma = 0.1;
  params.effort.sigma = 0.1;
  SenseNoise noise;
  noise.reset(params, 11, 128, 0.02);
  double sum = 0.0, sum2 = 0.0, f_sum2 = 0.0;
  for (int i = 0; i < 2000; ++i) {
    Senses z;
    z.touch[kLeftHand].contact = true;
    z.touch[kLeftHand].force = 10.0;
    noise.touch(z);
    sum += z.touch[kLeftHand].force, sum2 += z.touch[kLeftHand].force * z.touch[kLeftHand].force;
    CHECK(z.touch[kBody].force == 0.0);
    const double* f = noise.effort();
    REQUIRE(f);
    f_sum2 += (f[kLeftShoulder] - 1.0) * (f[kLeftShoulder] - 1.0);
  }
  const double mean = sum / 2000, sd = std::sqrt(sum2 / 2000 - mean * mean);
  CHECK(mean == Approx(10.0).epsilon(0.01));
  CHECK(sd == Approx(1.0).epsilon(0.05));
  CHECK(std::sqrt(f_sum2 / 2000) == Approx(0.1).epsilon(0.05));
  SenseNoise none;
  none.reset(NoiseParams{}, 11, 128, 0.02);
  CHECK(none.effort() == nullptr);
}

// A bias is drawn at the start of an episode and held: each tick's offset is the first one, and
// the next episode (another world seed) draws another. Over many episodes the biases spread as
// N(0, bias).
TEST_CASE("a bias holds all episode and is drawn afresh for the next", "[noise]") {
  ChannelNoise n;
  n.bias = 0.02;
  ChannelProcess p;
  p.reset(n, 11, NoiseChannel::kJoints, 6, 6, 0.02);
  p.draw();
  double first[6];
  for (int k = 0; k < 6; ++k) first[k] = p.offset(k);
  int changed = 0;
  for (int t = 1; t < 300; ++t) {
    p.draw();
    for (int k = 0; k < 6; ++k) changed += p.offset(k) != first[k];
  }
  CHECK(changed == 0);
  p.reset(n, 12, NoiseChannel::kJoints, 6, 6, 0.02);
  p.draw();
  for (int k = 0; k < 6; ++k) CHECK(p.offset(k) != first[k]);
  double sum2 = 0.0;
  for (uint64_t seed = 0; seed < 1000; ++seed) {
    p.reset(n, seed, NoiseChannel::kJoints, 6, 6, 0.02);
    p.draw();
    for (int k = 0; k < 6; ++k) sum2 += p.offset(k) * p.offset(k);
  }
  CHECK(std::sqrt(sum2 / 6000) == Approx(0.02).epsilon(0.03));  // 6000 draws: 1% standard error
}

// The drift is a Gauss-Markov process: stationary at its sigma, its autocorrelation after a lag
// exp(-lag / tau). The correlation time read from 768 components over 60 s is within 20% of tau
// (6% standard error), and a longer tau is read as longer.
TEST_CASE("a drift wanders with its sigma and correlation time", "[noise]") {
  for (double tau : {2.0, 10.0}) {
    ChannelNoise n;
    n.drift = 5.0, n.drift_tau = tau;
    ChannelProcess p;
    p.reset(n, 21, NoiseChannel::kImage, 768, 2, 0.02);
    const int lag = int(tau / 0.02), ticks = 3000;
    std::vector<double> history(size_t(768) * ticks);
    for (int t = 0; t < ticks; ++t) {
      p.draw();
      for (int k = 0; k < 768; ++k) history[size_t(t) * 768 + size_t(k)] = p.offset(k);
    }
    double var = 0.0, cov = 0.0;
    for (int t = 0; t + lag < ticks; ++t)
      for (int k = 0; k < 768; ++k) {
        const double x = history[size_t(t) * 768 + size_t(k)];
        var += x * x, cov += x * history[size_t(t + lag) * 768 + size_t(k)];
      }
    const double n_pairs = double(ticks - lag) * 768;
    const double measured_tau = lag * 0.02 / -std::log(cov / var);
    INFO("tau " << tau << " s: measured " << measured_tau << " s, sigma " << std::sqrt(var / n_pairs));
    CHECK(measured_tau == Approx(tau).epsilon(0.2));
    CHECK(std::sqrt(var / n_pairs) == Approx(5.0).epsilon(0.1));
  }
}

// A delay of d ticks hands over at tick t the reading of tick t - d, exactly (the first reading
// until d ticks have passed), on every channel that reads, and on the commands.
TEST_CASE("a delay is exact to the tick on every channel", "[noise]") {
  NoiseParams params;
  params.joints.delay = 3, params.base.delay = 2, params.touch.delay = 4, params.image.delay = 1;
  params.effort.delay = 5;
  SenseNoise noise;
  noise.reset(params, 5, 32, 0.02);
  CHECK(noise.alters_commands());
  for (int t = 0; t < 40; ++t) {
    Senses s;
    for (int k = 0; k < 6; ++k) s.q[kLeftEye + k] = t + 0.1 * k;
    s.base.x = t;
    s.touch[kLeftHand].contact = true;
    s.touch[kLeftHand].force = t;
    s.image[kRight].camera.pixels = s.image[kLeft].camera.pixels = 32;
    s.image[kLeft].colour[0] = Colour{uint8_t(t), 0, 0};
    noise.pose(s);
    noise.touch(s);
    bool arrived[2];
    noise.images(s, arrived);
    DofVector errors = DofVector::Constant(double(t));
    const DofVector delivered = noise.commands(errors);
    INFO("tick " << t);
    CHECK(s.q[kLeftEye + 2] == std::max(t - 3, 0) + 0.2);
    CHECK(s.base.x == std::max(t - 2, 0));
    CHECK(s.touch[kLeftHand].force == std::max(t - 4, 0));
    CHECK(s.image[kLeft].colour[0].r == std::max(t - 1, 0));
    CHECK(delivered[kLeftShoulder] == std::max(t - 5, 0));
  }
}

// Each reading is lost with the dropout's probability, independently: the rate over 120000
// readings lies within its 95% interval. A lost joint reading holds the last one delivered, a lost
// contact is not felt, a lost frame is the last frame again.
TEST_CASE("dropped readings come at their rate and hold what was read", "[noise]") {
  ChannelNoise n;
  n.dropout = 0.05;
  ChannelProcess p;
  p.reset(n, 31, NoiseChannel::kJoints, 6, 6, 0.02);
  int lost = 0;
  const int trials = 20000 * 6;
  for (int t = 0; t < 20000; ++t) {
    p.draw();
    for (int k = 0; k < 6; ++k) lost += p.lost(k);
  }
  const double half = 1.96 * std::sqrt(0.05 * 0.95 / trials);
  INFO(lost << " of " << trials << " lost");
  CHECK(std::abs(double(lost) / trials - 0.05) < half);

  NoiseParams params;
  params.joints.dropout = 0.3, params.touch.dropout = 0.3, params.image.dropout = 0.3;
  SenseNoise noise;
  noise.reset(params, 8, 32, 0.02);
  double last_q = -1.0;
  int held = 0, unfelt = 0, stale = 0;
  uint8_t last_red = 0;
  for (int t = 0; t < 200; ++t) {
    Senses s;
    s.q[kLeftShoulder] = t;
    s.touch[kLeftHand].contact = true;
    s.touch[kLeftHand].force = 1.0;
    s.image[kLeft].camera.pixels = s.image[kRight].camera.pixels = 32;
    s.image[kLeft].colour[0] = Colour{uint8_t(t), 0, 0};
    noise.pose(s);
    noise.touch(s);
    bool arrived[2];
    noise.images(s, arrived);
    if (s.q[kLeftShoulder] != t) {
      CHECK(s.q[kLeftShoulder] == last_q);
      ++held;
    }
    if (!s.touch[kLeftHand].contact) {
      CHECK(s.touch[kLeftHand].force == 0.0);
      ++unfelt;
    }
    if (!arrived[kLeft]) {
      CHECK(s.image[kLeft].colour[0].r == last_red);
      ++stale;
    } else {
      CHECK(s.image[kLeft].colour[0].r == t);
    }
    last_q = s.q[kLeftShoulder], last_red = s.image[kLeft].colour[0].r;
  }
  INFO(held << " held joint readings, " << unfelt << " contacts not felt, " << stale << " stale frames of 200");
  CHECK((held > 40 && held < 80));
  CHECK((unfelt > 40 && unfelt < 80));
  CHECK((stale > 40 && stale < 80));
}

// A resolution puts every reading on its grid, at most half a step from the value read.
TEST_CASE("a resolution puts readings on its grid", "[noise]") {
  NoiseParams params;
  params.joints.quantum = 0.005, params.base.quantum = 0.01, params.touch.quantum = 0.5, params.image.quantum = 8;
  SenseNoise noise;
  noise.reset(params, 9, 32, 0.02);
  Rng rng(4);
  for (int t = 0; t < 200; ++t) {
    Senses s;
    const double q = rng.uniform(-2.0, 2.0), x = rng.uniform(-3.0, 3.0), f = rng.uniform(0.0, 20.0);
    s.q[kLeftElbow] = q, s.base.x = x;
    s.touch[kRightHand].contact = true, s.touch[kRightHand].force = f;
    s.image[kLeft].camera.pixels = s.image[kRight].camera.pixels = 32;
    s.image[kLeft].colour[3] = Colour{uint8_t(rng.integer(0, 255)), 0, 0};
    noise.pose(s);
    noise.touch(s);
    bool arrived[2];
    noise.images(s, arrived);
    INFO("tick " << t);
    CHECK(std::abs(s.q[kLeftElbow] / 0.005 - std::round(s.q[kLeftElbow] / 0.005)) < 1e-9);
    CHECK(std::abs(s.q[kLeftElbow] - q) <= 0.0025 + 1e-12);
    CHECK(std::abs(s.base.x / 0.01 - std::round(s.base.x / 0.01)) < 1e-9);
    CHECK(std::abs(s.touch[kRightHand].force - f) <= 0.25 + 1e-12);
    CHECK(std::fmod(s.touch[kRightHand].force, 0.5) == Approx(0.0).margin(1e-9));
    CHECK((s.image[kLeft].colour[3].r % 8 == 0 || s.image[kLeft].colour[3].r == 255));
  }
}

// Each channel and kind draws from a stream of its own, a fixed number of values a tick: the
// joints' white noise is the same draw for draw whatever else is switched on, a bias switched on
// adds its constant and nothing else, and the noise met does not depend on what the robot does
// (two trajectories, the same joint errors tick for tick).
TEST_CASE("each channel and kind is a stream of its own", "[noise]") {
  auto joint_errors = [](const NoiseParams& params, int ticks, double command) {
    WorldSpec spec = test::open_world();
    spec.seed = 77;
    spec.noise = params;
    World w;
    w.reset(spec);
    DofVector cmd = DofVector::Zero();
    cmd[kBaseForward] = command, cmd[kLeftShoulder] = command, cmd[kLeftEye] = -command;
    std::vector<double> errors;
    for (int t = 0; t < ticks; ++t) {
      w.command(cmd);
      w.tick();
      for (int k = 0; k < 6; ++k) errors.push_back(w.senses().q[kLeftEye + k] - w.true_senses().q[kLeftEye + k]);
    }
    return errors;
  };
  NoiseParams white;
  white.joints.sigma = 0.01;
  const std::vector<double> alone = joint_errors(white, 120, 0.1);
  NoiseParams crowded = moderate(2.0);
  crowded.joints = white.joints;
  crowded.image.dropout = 0.1, crowded.touch.dropout = 0.2, crowded.touch.delay = 2, crowded.base.bias = 0.01;
  crowded.effort.delay = 1, crowded.effort.quantum = 0.001;
  // (An error is the reading less the true angle, so equal draws agree to the angle's rounding.)
  auto same_draws = [&](const std::vector<double>& errors) {
    REQUIRE(errors.size() == alone.size());
    int differ = 0;
    for (size_t k = 0; k < alone.size(); ++k) differ += std::abs(errors[k] - alone[k]) > 1e-12;
    return differ;
  };
  CHECK(same_draws(joint_errors(crowded, 120, 0.1)) == 0);  // other channels on: the same draws
  CHECK(same_draws(joint_errors(white, 120, -0.3)) == 0);   // another trajectory: the same draws
  NoiseParams other_seed_white = white;
  other_seed_white.joints.sigma = 0.011;
  CHECK(same_draws(joint_errors(other_seed_white, 120, 0.1)) > 600);  // the comparison can fail
  NoiseParams biased = white;
  biased.joints.bias = 0.02;
  const std::vector<double> with_bias = joint_errors(biased, 120, 0.1);
  for (size_t k = 6; k < alone.size(); ++k)
    CHECK(with_bias[k] - alone[k] == Approx(with_bias[k % 6] - alone[k % 6]).margin(1e-12));
  CHECK(with_bias[0] - alone[0] != 0.0);
}

// The judges read the true world: the object map's `held` follows the true touch, whatever the
// noisy touch says.
TEST_CASE("no noise reaches the object map's held", "[noise]") {
  const SkillScript script = SkillScript::load("curricula/scripted.lua");
  const SkillScript::NamedPolicy& task = script.policy("search_grasp");
  Scenario scenario = Scenario::load("unobstructed");
  set_moderate(scenario, 2.0);
  scenario.set_param("noise_touch", "1");  // forces that swing by their own size
  Agent agent;
  agent.reset(scenario.generate(7390001));
  reset_predicate(*task.goal, 7390001);
  task.action->reset(7390001);
  int differ = 0, ticks = 0;
  for (; ticks < 250; ++ticks) {
    agent.step(*task.action);
    const Senses& truth = agent.world().true_senses();
    for (size_t i = 0; i < agent.objects().size(); ++i) {
      bool held = false;
      for (const Touch& t : truth.touch) held |= t.contact && t.kind == SurfaceKind::kObject && t.index == int(i);
      CHECK(agent.objects()[i].held == held);
    }
    for (int t = 0; t < kTactileCount; ++t)
      differ += agent.world().senses().touch[t].force != truth.touch[t].force;
  }
  CHECK(differ > 0);  // the controllers did read other forces
}

// The scripted task exercises every primitive: phi6 search and phi0, search_grasp phi1, phi2, phi4
// and phi3, the task the carrying phi1 and phi5 too. Each part is done under M in (nearly) every
// world of both scenarios, and the task under 4M in most.
TEST_CASE("the scripted task and its parts are done under the moderate noise M", "[noise]") {
  const SkillScript script = SkillScript::load("curricula/scripted.lua");
  // Each part under M on 20 seeds; the task under 4M on docs/results.md's 200 (Noise, the bar 95%).
  struct Run {
    const char* policy;
    double scale;
    int episodes;
    uint64_t seed;
  };
  const Run runs[] = {{"phi6", 1.0, 20, 7380000}, {"search_grasp", 1.0, 20, 7380000}, {"task", 1.0, 20, 7380000},
                      {"task", 4.0, 200, 9200000}};
  for (const Run& run : runs) {
    const SkillScript::NamedPolicy& task = script.policy(run.policy);
    EpisodeOptions options;
    options.time_limit = task.time_limit;
    for (const char* world : {"unobstructed", "cluttered"}) {
      Scenario scenario = Scenario::load(world);
      set_moderate(scenario, run.scale);
      const EvalSummary r = evaluate_action([&](uint64_t s) { return scenario.generate(s); }, *task.action,
                                            *task.goal, run.episodes, run.seed, options);
      INFO(run.policy << " in " << world << " at " << run.scale << " M");
      // 4M: 197 of 200 unobstructed and 196 in clutter (roger eval curricula/scripted.lua --policy task
      // --scenario W --episodes 200 --seed 9200000 $M --set noise_scale=4); before the stimulus mask's
      // opening and the pose estimate, 193 and 183.
      const std::string w = world;
      CHECK(r.successes >= (run.scale == 1.0 ? 19 : w == "unobstructed" ? 197 : 196));
    }
  }
}

// Mixed noise levels on one agent give each episode what a fresh agent gives it; and the judge an
// evaluation keeps for all its episodes (its copies of the goal's controllers made once, reset each
// episode) judges each as the fresh judge of a one-episode evaluation does.
TEST_CASE("an episode's noise owes nothing to the previous episode's", "[noise]") {
  const SkillScript script = SkillScript::load("curricula/scripted.lua");
  const SkillScript::NamedPolicy& task = script.policy("task");
  EpisodeOptions options;
  options.time_limit = task.time_limit;
  std::vector<Scenario> scenarios;
  for (double scale : {0.0, 1.0, 4.0}) {
    scenarios.push_back(Scenario::load("cluttered"));
    set_moderate(scenarios.back(), scale);
  }
  auto make = [&](uint64_t seed) { return scenarios[seed % scenarios.size()].generate(seed); };
  const EvalSummary mixed = evaluate_action(make, *task.action, *task.goal, 6, 7370000, options);
  for (const EpisodeResult& r : mixed.results) {
    const EvalSummary alone = evaluate_action(make, *task.action, *task.goal, 1, r.seed, options);
    INFO("seed " << r.seed);
    CHECK(alone.results[0].ticks == r.ticks);
    CHECK(alone.results[0].reward == r.reward);
    CHECK(alone.results[0].success == r.success);
  }
}

// Episodes under noise of every kind run as a batch's trials, one or three at a time: the same
// results, as the noise is a function of the world's seed alone, not of the thread or the order.
TEST_CASE("noisy episodes do not depend on the number of jobs", "[noise]") {
  auto episode = [](const std::string& id, const std::string&) {
    const SkillScript script = SkillScript::load("curricula/scripted.lua");
    const SkillScript::NamedPolicy& task = script.policy("task");
    Scenario scenario = Scenario::load("cluttered");
    set_moderate(scenario, 2.0);
    set_every_kind(scenario);
    EpisodeOptions options;
    options.time_limit = task.time_limit;
    const uint64_t seed = 7360000 + std::stoull(id.substr(id.find('-') + 1));
    const EvalSummary r = evaluate_action([&](uint64_t s) { return scenario.generate(s); }, *task.action,
                                          *task.goal, 1, seed, options);
    return nlohmann::json{{"ticks", r.results[0].ticks}, {"reward", r.results[0].reward},
                          {"success", r.results[0].success}};
  };
  std::vector<std::string> ids;
  for (int i = 0; i < 6; ++i) ids.push_back("noise/seed-" + std::to_string(i));
  const auto dir = std::filesystem::temp_directory_path() / "roger_test_noise_jobs";
  std::filesystem::remove_all(dir);
  const auto one = run_trials(ids, episode, BatchOptions{1, (dir / "one").string()});
  const auto three = run_trials(ids, episode, BatchOptions{3, (dir / "three").string()});
  REQUIRE(one.size() == ids.size());
  for (size_t i = 0; i < ids.size(); ++i) {
    INFO(ids[i]);
    CHECK(one[i].ok);
    CHECK(one[i].result == three[i].result);
  }
  std::filesystem::remove_all(dir);
}

// The task's absorbing predicate reads controllers, and the actions' controllers read the noisy
// senses; the judge (Judge) asks copies of them reading the true senses. Its phi1 converges on the
// carried object's centre as Roger's body places it (0.36 m ahead of the base), so even without
// noise the true centre ends up to 0.30 m from the region's (radius 0.25 m). Each episode the judge
// calls done under M and 2M must be done in the true world: the object's centre within 0.1 m of
// the region's edge, and the object touched by Roger as the true touch has it. (At 4M the grasp
// slips in the hands, so the object may lie up to 0.15 m beyond the edge when Roger's body is at
// the goal: the judge reads the true world, but phi1 places the carried object by the body.)
TEST_CASE("the task done under noise is done in the true world", "[noise]") {
  const SkillScript script = SkillScript::load("curricula/scripted.lua");
  const SkillScript::NamedPolicy& task = script.policy("task");
  for (double scale : {0.0, 1.0, 2.0}) {
    Scenario scenario = Scenario::load("unobstructed");
    set_moderate(scenario, scale);
    int done = 0;
    for (uint64_t seed = 7350000; seed < 7350040; ++seed) {
      Agent agent;
      agent.reset(scenario.generate(seed));
      task.action->reset(seed);
      reset_predicate(*task.goal, seed);
      Judge judge(task.goal.get());
      judge.reset(seed);
      bool holds = false;
      for (int t = 0; t < 500 && !holds; ++t) {
        agent.step(*task.action);
        holds = judge.holds(agent.input());
      }
      if (!holds) continue;
      ++done;
      const GoalRegion& g = agent.world().spec().goals.at(0);
      const double d = (agent.objects()[0].center - g.center).norm();
      INFO("seed " << seed << " at " << scale << " M: the object's centre " << d << " m from the region's");
      CHECK(d < g.radius + 0.1);
      CHECK(agent.objects()[0].held);
    }
    INFO("at " << scale << " M");
    CHECK(done >= 39);
  }
}

// The judge's copies follow the goal's controllers: asked to judge through them even without noise
// (always_judge_truth), at every tick each copy was evaluated and executed as its original was and
// gives the same state and command, and the verdict is the goal's own. So under
// noise the judge gives the verdict the goal would give on the true senses (plateaus, a binding's
// invocations, acted_last_tick and holds included), and runs with and without noise are judged by
// one rule. Scripted task, its parts and the hand-written sort of four objects (whose goal reads the
// world alone: the verdicts agree with no copy to follow).
TEST_CASE("the judge's copies follow the goal's controllers tick for tick", "[noise]") {
  struct Case {
    const char* script;
    const char* policy;
    const char* scenario;
    int objects;
  };
  const Case cases[] = {{"curricula/scripted.lua", "phi6", "unobstructed", 0},
                        {"curricula/scripted.lua", "search_grasp", "cluttered", 0},
                        {"curricula/scripted.lua", "task", "cluttered", 0},
                        {"curricula/sort_by_hand.lua", "sort", "sorting", 4}};
  AgentParams copies;
  copies.always_judge_truth = true;
  for (const Case& c : cases) {
    const SkillScript script = SkillScript::load(c.script);
    const SkillScript::NamedPolicy& task = script.policy(c.policy);
    Scenario scenario = Scenario::load(c.scenario);
    if (c.objects) scenario.set_param("objects", std::to_string(c.objects));
    const int limit = int((task.time_limit + task.time_per_object * c.objects) / 0.02);
    int successes = 0, compared = 0;
    for (uint64_t seed = 7340000; seed < 7340004; ++seed) {
      Agent agent(WorldParams{}, copies);
      agent.reset(scenario.generate(seed));
      task.action->reset(seed);
      reset_predicate(*task.goal, seed);
      Judge judge(task.goal.get());
      judge.reset(seed);
      agent.set_judge(&judge);
      bool done = false;
      for (int t = 0; t < limit && !done; ++t) {
        const bool judged = judge.holds(agent.input());  // the copies, on the (true) senses
        done = task.goal->holds(agent.input());         // the goal itself
        INFO(c.policy << ", seed " << seed << ", tick " << t);
        REQUIRE(judged == done);
        if (done) break;
        agent.step(*task.action);
        for (const auto& [original, copy] : judge.copies().controllers) {
          INFO(original->name());
          REQUIRE(copy->evaluated_tick() == original->evaluated_tick());
          REQUIRE(copy->executed_tick() == original->executed_tick());
          REQUIRE(copy->output().gamma == original->output().gamma);
          REQUIRE(copy->output().command == original->output().command);
          ++compared;
        }
      }
      agent.set_judge(nullptr);
      successes += done;
    }
    INFO(c.policy << ": " << successes << " of 4 done, " << compared << " comparisons");
    CHECK(successes >= 3);
    // 248 for phi6, the shortest; the sort's goal (roger.sorted) reads the world, no controller.
    if (c.objects) CHECK(compared == 0);
    else CHECK(compared > 200);
  }
}

// The same on learned policies (tests/policies: Phi_SG of SG/DC2 and T/DC6 above it, trained by
// roger train): a greedy evaluation judged through the copies gives every episode the outcome,
// reward, decisions and time it gets when judged by the goal itself.
TEST_CASE("learned policies are judged through copies as by their goal", "[noise]") {
  for (const char* file : {"tests/policies/sg_dc2.json", "tests/policies/t_dc6.json"}) {
    PolicyEvalOptions plain;
    plain.curriculum = "paper";
    plain.policy_file = file;
    plain.episodes = 10;
    PolicyEvalOptions copies = plain;
    copies.agent.always_judge_truth = true;
    const PolicyEvalResult a = evaluate_policy_file(plain), b = evaluate_policy_file(copies);
    INFO(file << ": " << a.eval.successes << " successes");
    CHECK(a.eval.successes >= 8);
    CHECK(b.eval.successes == a.eval.successes);
    CHECK(b.eval.reward_mean == a.eval.reward_mean);
    CHECK(b.eval.decisions == a.eval.decisions);
    CHECK(b.eval.time_mean == a.eval.time_mean);
  }
}

// No noise reaches a judge: the same true trajectory, sensed without noise and with 8M on every
// sense, gets the same verdict from the task's judge at every tick. The trajectory is a successful
// noise-free episode's errors replayed without the gaze reflex (the motors' effort noise is off, so
// the senses' noise cannot move the robot). The goal asked directly on the noisy senses does
// disagree on some tick, so the noise would have reached it.
TEST_CASE("no noise reaches the task's judge", "[noise]") {
  const SkillScript script = SkillScript::load("curricula/scripted.lua");
  const SkillScript::NamedPolicy& task = script.policy("task");
  AgentParams replaying;
  replaying.gaze_reflex = false;
  int disagreements = 0, verdicts = 0;
  for (uint64_t seed = 7330000; seed < 7330006; ++seed) {
    Scenario clean = Scenario::load("unobstructed"), noisy = Scenario::load("unobstructed");
    set_moderate(noisy, 8.0);
    noisy.set_param("noise_effort", "0");
    Agent recorder;
    recorder.reset(clean.generate(seed));
    task.action->reset(seed);
    reset_predicate(*task.goal, seed);
    std::vector<DofVector> errors;
    for (bool done = false; !done && errors.size() < 500;) {
      recorder.step(*task.action);
      errors.push_back(recorder.last_errors());
      done = task.goal->holds(recorder.input());
    }
    Replay replay(errors);
    Agent a(WorldParams{}, replaying), b(WorldParams{}, replaying);
    a.reset(clean.generate(seed));
    b.reset(noisy.generate(seed));
    Judge judge_a(task.goal.get());
    std::shared_ptr<Predicate> goal_b = duplicate(task.goal, *std::make_unique<Duplicates>());
    Judge judge_b(goal_b.get());
    reset_predicate(*task.goal, seed), reset_predicate(*goal_b, seed);
    judge_a.reset(seed), judge_b.reset(seed);
    for (size_t t = 0; t < errors.size() + 50; ++t) {
      a.step(replay), b.step(replay);
      REQUIRE(a.world().state_hash() == b.world().state_hash());
      const bool verdict = judge_a.holds(a.input());
      INFO("seed " << seed << ", tick " << t);
      CHECK(judge_b.holds(b.input()) == verdict);
      verdicts += verdict;
      disagreements += goal_b->holds(b.input()) != verdict;
    }
  }
  INFO(verdicts << " ticks judged done, " << disagreements << " where the noisy goal disagreed");
  CHECK(verdicts > 0);
  CHECK(disagreements > 0);
}

// A stereo fix that jumps: with M's 0.01 rad on the eye pans, a fix at 2 m is off by about half a
// metre (the eyes are 0.16 m apart). Fused over the ticks (StereoFilter) the estimate the
// controllers read is off by about half as much, measured against the fix the true senses make
// (the mean of fixes whose range is the baseline over a noisy vergence keeps some of their bias).
TEST_CASE("under noise the stereo fixes are fused into a steady estimate", "[noise]") {
  const SkillScript script = SkillScript::load("curricula/scripted.lua");
  const SkillScript::NamedPolicy& task = script.policy("search_grasp");
  Scenario scenario = Scenario::load("unobstructed");
  set_moderate(scenario, 1.0);
  double raw2 = 0.0, fused2 = 0.0;
  int n = 0;
  for (uint64_t seed = 7320000; seed < 7320010; ++seed) {
    Agent agent;
    agent.reset(scenario.generate(seed));
    task.action->reset(seed);
    for (int t = 0; t < 250; ++t) {
      agent.step(*task.action);
      const VisualObject& o = agent.percepts().object;
      const Senses& true_senses = agent.world().true_senses();
      if (!o.seen || o.by_touch || !agent.world().senses().stereo_valid || !true_senses.stereo_valid) continue;
      const Vec2 truth = true_senses.stimulus_world;  // the fix without noise
      raw2 += (agent.world().senses().stimulus_world - truth).squaredNorm();
      fused2 += (o.center - truth).squaredNorm();
      ++n;
    }
  }
  REQUIRE(n > 500);
  const double raw = std::sqrt(raw2 / n), fused = std::sqrt(fused2 / n);
  INFO("RMS error of the fixes " << raw << " m, of the fused estimate " << fused << " m, over " << n << " ticks");
  CHECK(raw > 0.2);
  CHECK(fused < 0.6 * raw);  // 0.15 m against 0.29 m
}

// Under joint and base noise the controllers read the pose Roger estimates (PoseFilter): white
// noise shrinks to about a quarter on the base (sqrt(0.1 / 1.9) = 0.23), less on the arms, whose
// fast moves the prediction from the rates follows less closely; a bias stays, episode by episode.
TEST_CASE("under joint and base noise the controllers read a steadier pose", "[noise]") {
  const SkillScript script = SkillScript::load("curricula/scripted.lua");
  const SkillScript::NamedPolicy& task = script.policy("search_grasp");
  for (const char* bias : {"0", "0.03"}) {
    Scenario scenario = Scenario::load("unobstructed");
    scenario.set_param("noise_joints", "0.04");
    scenario.set_param("noise_base", "0.04");
    scenario.set_param("noise_base_bias", bias);
    double raw2[2] = {0, 0}, est2[2] = {0, 0};  // [0]: base x, [1]: left shoulder
    int n = 0;
    for (uint64_t seed = 7330000; seed < 7330005; ++seed) {
      Agent agent;
      agent.reset(scenario.generate(seed));
      task.action->reset(seed);
      double raw_mean = 0.0, est_mean = 0.0;  // of x's error, this episode
      for (int t = 0; t < 200; ++t) {
        agent.step(*task.action);
        const Senses& truth = agent.world().true_senses();
        const Senses& raw = agent.world().senses();
        const SenseReadings& estimate = *agent.input().senses;
        raw2[0] += std::pow(raw.base.x - truth.base.x, 2), est2[0] += std::pow(estimate.base.x - truth.base.x, 2);
        raw2[1] += std::pow(raw.q[kLeftShoulder] - truth.q[kLeftShoulder], 2);
        est2[1] += std::pow(estimate.q[kLeftShoulder] - truth.q[kLeftShoulder], 2);
        raw_mean += (raw.base.x - truth.base.x) / 200, est_mean += (estimate.base.x - truth.base.x) / 200;
        ++n;
      }
      INFO("seed " << seed << " with bias " << bias << ": mean error of x read " << raw_mean << ", estimated " << est_mean);
      CHECK(std::abs(est_mean - raw_mean) < 0.005);  // a bias (up to about 0.06) is not noise to a filter
    }
    if (std::string(bias) != "0") continue;
    const double raw[2] = {std::sqrt(raw2[0] / n), std::sqrt(raw2[1] / n)};
    const double est[2] = {std::sqrt(est2[0] / n), std::sqrt(est2[1] / n)};
    INFO("RMS error of the readings and the estimate: base x " << raw[0] << ", " << est[0] << "; left shoulder "
                                                              << raw[1] << ", " << est[1]);
    CHECK(raw[0] == Approx(0.04).epsilon(0.1));
    CHECK(raw[1] == Approx(0.04).epsilon(0.1));
    CHECK(est[0] < 0.3 * raw[0]);   // 0.26
    CHECK(est[1] < 0.47 * raw[1]);  // 0.43
  }
}

// The hand-written 8-object sort under 4M: its colours lie 127-157 levels apart, where 40 levels
// of image noise make a few per cent of another type's pixels read as the one sought (the
// stimulus mask's opening drops them), and joint and base noise of 0.04 put a delivered object at
// its region's edge (the pose estimate keeps it inside). Before both, 2 of 40 episodes.
TEST_CASE("the 8-object sort is done under 4M", "[noise]") {
  const SkillScript script = SkillScript::load("curricula/sort_by_hand.lua");
  const SkillScript::NamedPolicy& sort = script.policy("sort");
  Scenario scenario = Scenario::load("sorting");
  scenario.set_param("objects", "8");
  set_moderate(scenario, 4.0);
  EpisodeOptions options;
  options.time_limit = sort.time_limit;
  options.time_per_object = sort.time_per_object;
  const EvalSummary r = evaluate_action([&](uint64_t s) { return scenario.generate(s); }, *sort.action, *sort.goal,
                                        20, 9500000, options);
  // 19 of 20 (roger eval curricula/sort_by_hand.lua --policy sort --set objects=8 --seed 9500000
  // --episodes 20 $M --set noise_scale=4; of 40 episodes, 39).
  CHECK(r.successes >= 19);
}

// A CONV that flickers: every change of an action's state is a decision of the learner, so a
// state that flips with the noise multiplies the decisions and slows learning (SG under M took
// 240-390 episodes to its threshold instead of 20-30 before the fixes were fused). The states of
// SG's actions in B1 over search-grasp episodes under M change about as often as without noise.
TEST_CASE("under M the actions' states change about as often as without noise", "[noise]") {
  Curriculum cur = Curriculum::load("paper");
  const CurriculumContext& b1 = cur.stage("SG").context("B1");
  const SkillScript script = SkillScript::load("curricula/scripted.lua");
  const SkillScript::NamedPolicy& task = script.policy("search_grasp");
  int changes[2] = {0, 0};
  for (int noisy = 0; noisy < 2; ++noisy) {
    Scenario scenario = Scenario::load("unobstructed");
    set_moderate(scenario, noisy);
    for (uint64_t seed = 7310000; seed < 7310020; ++seed) {
      Agent agent;
      EpisodeOptions options;
      options.time_limit = task.time_limit;
      const EpisodeResult r = run_episode(agent, scenario.generate(seed), seed, *task.action, *task.goal, options, b1.actions);
      for (const GammaTrace& g : r.gammas)
        for (size_t t = 1; t < g.states.size(); ++t) changes[noisy] += g.states[t] != g.states[t - 1];
    }
  }
  INFO(changes[0] << " changes of state without noise, " << changes[1] << " under M");
  CHECK(changes[0] > 100);
  CHECK(changes[1] < 1.5 * changes[0]);
}

// Found by a probe: the docs' example of noise kinds placed no goal region, so the scripted task,
// which the docs evaluate in it, failed every episode.
TEST_CASE("docs/examples/worn_sensors.lua: the docs' noise example is the file and the task succeeds in it", "[noise]") {
  std::ifstream in("docs/examples/worn_sensors.lua"), doc_in("docs/scenarios.md");
  const std::string source((std::istreambuf_iterator<char>(in)), {}), doc((std::istreambuf_iterator<char>(doc_in)), {});
  REQUIRE(!source.empty());
  CHECK(doc.find("```lua\n" + source + "```\n") != std::string::npos);  // shown verbatim
  SkillScript script = SkillScript::load("curricula/scripted.lua");
  const SkillScript::NamedPolicy& task = script.policy("task");
  Scenario scenario = Scenario::load("docs/examples/worn_sensors.lua");
  EpisodeOptions options;
  options.time_limit = task.time_limit;
  const EvalSummary r = evaluate_action([&](uint64_t s) { return scenario.generate(s); }, *task.action, *task.goal,
                                        20, 1000, options);
  CHECK(r.successes == 14);  // docs/scenarios.md says so (roger eval ... --episodes 20)
}
