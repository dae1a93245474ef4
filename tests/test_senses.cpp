// Tests of engine/senses: the 1-D pinhole eyes, stimulus detection, occlusion, stereo.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "core/rng.h"
#include "core/shape.h"
#include "senses/senses.h"
#include "senses/senses_internal.h"
#include "sim/world.h"
#include "world_fixtures.h"

using namespace roger;
using namespace roger::test;

namespace {
SeenSurface disk(Vec2 c, double r, Colour colour, SurfaceKind kind = SurfaceKind::kObject) {
  SeenSurface s;
  s.kind = kind, s.index = 0, s.colour = colour, s.is_disk = true, s.center = c, s.radius = r;
  return s;
}
const Colour kRed{220, 30, 30}, kGrey{90, 90, 110}, kWall{200, 200, 200};
}  // namespace

TEST_CASE("a ball at a known bearing lands on the pixel the pinhole model predicts", "[senses]") {
  // The ball (8.8 degrees half-width at 1.3 m) stays wholly inside the +-45 degree field of view.
  for (double bearing_deg : {-35.0, -25.0, -10.0, 0.0, 7.5, 20.0, 35.0}) {
    const double b = bearing_deg * M_PI / 180.0;
    const Vec2 eye(0.3, -0.2);
    const double heading = 0.4;
    const Vec2 ball = eye + 1.3 * Vec2(std::cos(heading + b), std::sin(heading + b));
    EyeImage image;
    paint_eye(Camera{}, eye, heading, {disk(ball, 0.2, kRed)}, kWall, kRed, image);
    const Sighting s = detect_stimulus(image);
    const double predicted = 63.5 + 64.0 * std::tan(b);
    INFO("bearing " << bearing_deg << " deg, predicted pixel " << predicted << ", seen " << s.u);
    REQUIRE(s.seen);
    CHECK(std::abs(s.u - predicted) < 1.0);
    CHECK(image.colour[int(std::lround(predicted))] == kRed);
    CHECK(std::abs(s.bearing - b) < 1e-4);
    CHECK(std::abs(s.half_width - std::asin(0.2 / 1.3)) < 1e-3);  // the ball's angular half-width
  }
}

TEST_CASE("pixels carry the colour of the nearest surface", "[senses]") {
  const Vec2 eye(0, 0);
  // A grey disk in front of the red one, partly overlapping in angle.
  EyeImage image;
  paint_eye(Camera{}, eye, 0.0, {disk({2.0, 0.0}, 0.3, kRed), disk({1.0, 0.1}, 0.1, kGrey, SurfaceKind::kObstacle)},
            kWall, kRed, image);
  const int near_pixel = int(std::lround(63.5 + 64.0 * std::tan(std::atan2(0.1, 1.0))));
  CHECK(image.colour[near_pixel] == kGrey);
  CHECK(image.kind[near_pixel] == SurfaceKind::kObstacle);
  CHECK(image.colour[int(std::lround(63.5 + 64.0 * std::tan(-0.1)))] == kRed);
  CHECK(image.colour[0] == kWall);
  CHECK(image.colour[127] == kWall);
  // Out of the field of view: behind the eye.
  paint_eye(Camera{}, eye, 0.0, {disk({-2.0, 0.0}, 0.3, kRed)}, kWall, kRed, image);
  CHECK_FALSE(detect_stimulus(image).seen);
}

TEST_CASE("a stimulus covers each pixel by its exact overlap with the stimulus's extent", "[senses]") {
  // Random balls wholly or partly in view; the coverage of every pixel must be, to the bit, the
  // overlap of the pixel [i - 0.5, i + 0.5] with the ball's extent in pixels, capped at 1.
  Rng rng(5);
  for (int trial = 0; trial < 500; ++trial) {
    const Vec2 eye(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0));
    const double heading = rng.uniform(-M_PI, M_PI), bearing = rng.uniform(-1.0, 1.0);
    const double distance = rng.uniform(0.4, 4.0), radius = rng.uniform(0.02, 0.35);
    const Vec2 ball = eye + distance * Vec2(std::cos(heading + bearing), std::sin(heading + bearing));
    EyeImage image;
    paint_eye(Camera{}, eye, heading, {disk(ball, radius, kRed)}, kWall, kRed, image);
    // The extent as the painter finds it for a disk.
    const Vec2 to_ball = ball - eye;
    const double centre = wrap_angle(std::atan2(to_ball.y(), to_ball.x()) - heading);
    const double half = std::asin(radius / to_ball.norm());
    const double lo_angle = std::max(centre - half, -M_PI / 4), hi_angle = std::min(centre + half, M_PI / 4);
    const double lo = std::clamp(Camera{}.pixel_of_angle(lo_angle), -0.5, Camera{}.pixels - 0.5);
    const double hi = std::clamp(Camera{}.pixel_of_angle(hi_angle), -0.5, Camera{}.pixels - 0.5);
    const bool in_view = centre + half > -M_PI / 4 && centre - half < M_PI / 4 && hi > lo;
    for (int i = 0; i < Camera{}.pixels; ++i) {
      const double overlap = std::min(hi, i + 0.5) - std::max(lo, i - 0.5);
      const float expected = in_view && overlap > 0 ? float(std::min(1.0, 0.0f + overlap)) : 0.0f;
      if (std::memcmp(&expected, &image.stimulus[i], sizeof expected) != 0)
        FAIL("trial " << trial << ", pixel " << i << ": " << image.stimulus[i] << " for " << expected);
    }
  }
  SUCCEED();
}

TEST_CASE("a surface at the edge of the field of view is painted as far as it reaches in", "[senses]") {
  // Squares and disks all around the eye, turned about it so that their nearest part lies a
  // micro-radian inside or outside an edge of the field of view (45 degrees either side): inside,
  // the edge pixel gets its sliver of coverage; outside, nothing is painted. A polygon goes through
  // its own path (the bounding-disk test, then its vertices' angles), so both shapes are tried.
  // Both pass the view cone's cull first (two half-planes, widened by a micro-radian), which must
  // keep every surface a micro-radian in.
  Rng rng(23);
  int inside = 0, outside = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const Vec2 eye(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0));
    const double heading = rng.uniform(-M_PI, M_PI), distance = rng.uniform(0.5, 6.0);
    const bool left = rng.uniform() < 0.5, square = rng.uniform() < 0.5, in_view = rng.uniform() < 0.5;
    const double size = rng.uniform(0.05, 0.4), turn = rng.uniform(-M_PI, M_PI);
    SeenSurface s = disk(eye + distance * Vec2(std::cos(heading), std::sin(heading)), size, kRed);
    if (square) {
      s.is_disk = false, s.vertex_count = 4, s.radius = size * M_SQRT2;
      for (int k = 0; k < 4; ++k) {
        const double a = turn + k * M_PI / 2 + M_PI / 4;
        s.vertices[size_t(k)] = s.center + s.radius * Vec2(std::cos(a), std::sin(a));
      }
    }
    // Its angular extent about the optical axis, from its points, then the turn about the eye that
    // puts its edge nearest the axis at 45 degrees plus or minus a micro-radian.
    auto angle_of = [&](const Vec2& p) { return wrap_angle(std::atan2(p.y() - eye.y(), p.x() - eye.x()) - heading); };
    double lo = angle_of(s.center) - std::asin(size / distance), hi = angle_of(s.center) + std::asin(size / distance);
    if (square) {
      lo = INFINITY, hi = -INFINITY;
      for (int k = 0; k < 4; ++k) lo = std::min(lo, angle_of(s.vertices[size_t(k)])), hi = std::max(hi, angle_of(s.vertices[size_t(k)]));
    }
    const double edge = M_PI / 4 + (in_view ? -1e-6 : 1e-6);
    const double rotate = left ? edge - lo : -edge - hi;
    auto turned = [&](const Vec2& p) {
      const Vec2 d = p - eye;
      return Vec2(eye + Vec2(std::cos(rotate) * d.x() - std::sin(rotate) * d.y(), std::sin(rotate) * d.x() + std::cos(rotate) * d.y()));
    };
    s.center = turned(s.center);
    for (int k = 0; k < s.vertex_count; ++k) s.vertices[size_t(k)] = turned(s.vertices[size_t(k)]);
    EyeImage image;
    paint_eye(Camera{}, eye, heading, {s}, kWall, kRed, image);
    const int edge_pixel = left ? Camera{}.pixels - 1 : 0;
    INFO("trial " << trial << (square ? ": square" : ": disk") << (left ? " at the left edge" : " at the right edge")
                  << (in_view ? ", a micro-radian in" : ", a micro-radian out"));
    if (in_view) {
      CHECK(image.stimulus[size_t(edge_pixel)] > 0.0f);
      ++inside;
    } else {
      const int n = image.pixels();
      CHECK(std::all_of(image.stimulus.begin(), image.stimulus.begin() + n, [](float c) { return c == 0.0f; }));
      CHECK(std::all_of(image.colour.begin(), image.colour.begin() + n, [](const Colour& c) { return c == kWall; }));
      ++outside;
    }
  }
  CHECK(inside > 150);
  CHECK(outside > 150);
}

TEST_CASE("detection scans only the painted stimulus pixels and finds what a full scan finds", "[senses]") {
  // Scenes of several stimulus and grey disks, some hiding others: the painter narrows the range
  // detection scans to the pixels it gave coverage; the same image scanned over its whole width
  // must give the same sighting to the bit, and no pixel outside the range may have coverage.
  Rng rng(11);
  int seen = 0, split = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const Vec2 eye(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0));
    const double heading = rng.uniform(-M_PI, M_PI);
    std::vector<SeenSurface> surfaces;
    const int count = int(rng.integer(1, 5));
    for (int k = 0; k < count; ++k) {
      const double bearing = rng.uniform(-1.0, 1.0), distance = rng.uniform(0.4, 4.0);
      const Vec2 c = eye + distance * Vec2(std::cos(heading + bearing), std::sin(heading + bearing));
      surfaces.push_back(disk(c, rng.uniform(0.02, 0.4), rng.uniform() < 0.6 ? kRed : kGrey));
    }
    EyeImage image;
    paint_eye(Camera{}, eye, heading, surfaces, kWall, kRed, image);
    for (int i = 0; i < Camera{}.pixels; ++i)
      if (i < image.stimulus_first || i > image.stimulus_last) REQUIRE(image.stimulus[size_t(i)] == 0.0f);
    EyeImage whole = image;
    whole.stimulus_first = 0, whole.stimulus_last = Camera{}.pixels - 1;
    const Sighting a = detect_stimulus(image), b = detect_stimulus(whole);
    REQUIRE(a.seen == b.seen);
    CHECK(a.clipped == b.clipped);
    CHECK(std::memcmp(&a.u, &b.u, sizeof a.u) == 0);
    CHECK(std::memcmp(&a.u_lo, &b.u_lo, sizeof a.u_lo) == 0);
    CHECK(std::memcmp(&a.u_hi, &b.u_hi, sizeof a.u_hi) == 0);
    CHECK(std::memcmp(&a.bearing, &b.bearing, sizeof a.bearing) == 0);
    CHECK(std::memcmp(&a.half_width, &b.half_width, sizeof a.half_width) == 0);
    seen += a.seen;
    // Runs separated by a grey disk in front: the range spans both, and the larger run wins.
    int runs = 0;
    for (int i = 0; i < Camera{}.pixels; ++i)
      runs += image.stimulus[size_t(i)] > 0.0f && (i == 0 || image.stimulus[size_t(i - 1)] == 0.0f);
    split += runs > 1;
  }
  // The scenes exercised what matters: sightings, and images with more than one run.
  CHECK(seen > 200);
  CHECK(split > 20);
}

TEST_CASE("two objects of the stimulus colour side by side in the image are two runs", "[senses]") {
  // Two red balls, objects 0 and 1, next to each other as the eye sees them: apart by a sliver of
  // wall (up to two pixels), touching, or ball 1 partly behind ball 0. Each is found as itself,
  // whichever detection prefers: its centre within half a pixel of where it lies alone, or, half
  // hidden, within the part of it in view. As one run, the centre lay between the two balls.
  const Vec2 eye(0.0, 0.0);
  const double heading = 0.0, r = 0.15;
  int cases = 0;
  for (double gap_px = -6.0; gap_px <= 2.0; gap_px += 0.25) {
    // Ball 0 at 1.5 m, 8 degrees left; ball 1 to its right, `gap_px` pixels of wall between their
    // edges (negative: ball 1, 0.5 m further, overlaps ball 0 by that much and is behind it).
    const double half0 = std::asin(r / 1.5), b0 = 8.0 * M_PI / 180.0;
    const double d1 = gap_px < 0.0 ? 2.0 : 1.5, half1 = std::asin(r / d1);
    const double edge0 = Camera{}.angle_of_pixel(Camera{}.pixel_of_angle(b0 - half0) - gap_px);  // ball 1's left edge
    const double b1 = edge0 - half1;
    SeenSurface s0 = disk(eye + 1.5 * Vec2(std::cos(b0), std::sin(b0)), r, kRed);
    SeenSurface s1 = disk(eye + d1 * Vec2(std::cos(b1), std::sin(b1)), r, kRed);
    s0.index = 0, s1.index = 1;
    EyeImage both, alone0, alone1;
    paint_eye(Camera{}, eye, heading, {s0, s1}, kWall, kRed, both);
    paint_eye(Camera{}, eye, heading, {s0}, kWall, kRed, alone0);
    paint_eye(Camera{}, eye, heading, {s1}, kWall, kRed, alone1);
    const Sighting a0 = detect_stimulus(alone0), a1 = detect_stimulus(alone1);
    const Sighting p0 = detect_stimulus(both, 0), p1 = detect_stimulus(both, 1);
    INFO("gap " << gap_px << " px: ball 0 alone at " << a0.u << ", found at " << p0.u << " [" << p0.u_lo << ", "
                << p0.u_hi << "]; ball 1 alone at " << a1.u << " [" << a1.u_lo << ", " << a1.u_hi << "], found at "
                << p1.u << " [" << p1.u_lo << ", " << p1.u_hi << "]");
    REQUIRE(p0.seen);
    REQUIRE(p1.seen);
    CHECK(p0.index == 0);
    CHECK(p1.index == 1);
    CHECK(std::abs(p0.u - a0.u) < 0.5);  // ball 0 is in front: all of it is in view
    if (gap_px >= 0.0) {
      CHECK(std::abs(p1.u - a1.u) < 0.5);
    } else {  // what is in view of ball 1: from its right edge to ball 0's
      CHECK(std::abs(p1.u_lo - a1.u_lo) < 0.5);
      CHECK(std::abs(p1.u_hi - a0.u_lo) < 0.5);
    }
    ++cases;
  }
  CHECK(cases == 33);
}

TEST_CASE("an obstacle between eye and ball hides it", "[senses]") {
  WorldSpec spec = open_world(true, Vec2(1.6, 0.0));
  ObstacleSpec wall;
  wall.shape = box_shape(0.1, 0.4);
  wall.pose = {0.8, 0.0, 0.0};
  World world;
  world.reset(open_world(true, Vec2(1.6, 0.0)));
  REQUIRE(world.senses().stimulus[kLeft].seen);
  REQUIRE(world.senses().stimulus[kRight].seen);
  spec.obstacles.push_back(wall);
  world.reset(spec);
  CHECK_FALSE(world.senses().stimulus[kLeft].seen);
  CHECK_FALSE(world.senses().stimulus[kRight].seen);
  CHECK_FALSE(world.senses().stereo_valid);
  CHECK(world.senses().image[kLeft].colour[64] == wall.colour);
  // A narrow post hides part of the ball only: it is still seen, and the estimate moves little.
  spec.obstacles[0].shape = box_shape(0.02, 0.02);
  spec.obstacles[0].pose = {0.8, 0.12, 0.0};
  world.reset(spec);
  CHECK(world.senses().stimulus[kLeft].seen);
}

TEST_CASE("stereo places the ball within 2 cm at 1 to 2 m in the open", "[senses]") {
  World world;
  int checked = 0;
  for (double range : {1.0, 1.25, 1.5, 1.75, 2.0})
    for (double bearing : {-0.5, -0.25, 0.0, 0.2, 0.45}) {
      const Vec2 ball = range * Vec2(std::cos(bearing), std::sin(bearing));
      WorldSpec spec = open_world(true, ball);
      spec.robot.pose = {-0.3, 0.0, 0.0};
      spec.objects[0].pose.x -= 0.3;
      // Point the eyes at it, as tracking would.
      spec.robot.left_eye = spec.robot.right_eye = bearing * 0.8;
      world.reset(spec);
      const Senses& s = world.senses();
      INFO("range " << range << " bearing " << bearing);
      REQUIRE(s.stereo_valid);
      const Vec2 truth(world.object_pose(0).x, world.object_pose(0).y);
      CHECK((s.stimulus_world - truth).norm() < 0.02);
      const Vec2 in_base = to_local(world.base_pose(), truth);
      CHECK((s.stimulus_base - in_base).norm() < 0.02);
      ++checked;
    }
  CHECK(checked == 25);
}

TEST_CASE("touch, joints and base pose are reported every tick", "[senses]") {
  World world;
  world.reset(open_world(false));
  DofVector e = DofVector::Zero();
  e[kLeftEye] = 0.5;
  world.command(e);
  run_for(world, 1.0);
  const Senses& s = world.senses();
  CHECK(s.time == Approx(world.time()));
  CHECK(s.q[kLeftEye] == Approx(0.5).margin(0.01));
  CHECK(s.base.x == Approx(world.base_pose().x));
  for (const Touch& t : s.touch) CHECK_FALSE(t.contact);
}

TEST_CASE("the eyes keep to one of two objects of the stimulus colour while it stays in view", "[senses]") {
  // Two red balls ahead, the nearer one larger in the image; Roger turns right so that the nearer
  // one slides out of the left edge of the view. Choosing the largest run each tick would jump to
  // the other ball while part of the first is still in view, and back and forth as they trade
  // sizes; the eyes keep to the one they had until none of it is left.
  WorldSpec spec = open_world(true, Vec2(1.0, 0.35));
  ObjectSpec far = spec.objects[0];
  far.name = "ball 2";
  far.pose = {2.0, -0.5, 0.0};
  spec.objects.push_back(far);
  World world;
  world.reset(spec);
  const Senses& s = world.senses();
  REQUIRE(s.stimulus[kLeft].index == 0);
  auto mass = [&](int index) {
    double m = 0.0;
    for (int u = 0; u < Camera{}.pixels; ++u)
      if (s.image[kLeft].index[size_t(u)] == index) m += s.image[kLeft].stimulus[size_t(u)];
    return m;
  };
  int switches = 0, last = s.stimulus[kLeft].index;
  bool other_larger_while_first_in_view = false;
  DofVector turn = DofVector::Zero();
  turn[kBaseHeading] = -0.15;
  for (int tick = 0; tick < 200 && last != 1; ++tick) {
    world.command(turn);
    world.tick();
    if (mass(0) > 0.0 && mass(1) > mass(0)) other_larger_while_first_in_view = true;
    const int now = s.stimulus[kLeft].index;
    if (now != last) ++switches, last = now;
    if (mass(0) > 0.0) CHECK(now == 0);
    // The right eye pairs the left eye's object whenever it has some of it in view.
    const auto& right = s.image[kRight].index;
    const auto right_end = right.begin() + s.image[kRight].pixels();
    if (std::find(right.begin(), right_end, now) != right_end) CHECK(s.stimulus[kRight].index == now);
  }
  CHECK(other_larger_while_first_in_view);  // the case the test is about did arise
  CHECK(last == 1);                          // and once the first was gone, the other was taken
  CHECK(switches == 1);
}

TEST_CASE("a polygon's extreme angles are those of every vertex's arc tangent, to the bit", "[senses]") {
  // The painter takes the arc tangents of only the vertices that can be a polygon's extremes
  // (senses_internal::extreme_angle). Against the min and max over every vertex's arc tangent,
  // from 0, as the painter took them before: vertices of random cones narrower than pi, vertices
  // whose angles differ by a few units in the last place (where the cross product's sign cannot
  // be trusted), vertices on one ray and a vertex at the eye. A vertex wrongly passed over would
  // differ in some bit.
  using senses_internal::extreme_angle;
  Rng rng(17);
  auto reference = [](const Vec2* v, int n, int side) {
    double lo = 0.0, hi = 0.0;
    for (int i = 0; i < n; ++i) {
      const double a = std::atan2(v[i].y(), v[i].x());
      lo = std::min(lo, a), hi = std::max(hi, a);
    }
    return side < 0 ? lo : hi;
  };
  for (int trial = 0; trial < 20000; ++trial) {
    const int n = 3 + trial % 6;
    const double middle = rng.uniform(-0.5, 0.5), width = rng.uniform(0.0, 3.1);
    Vec2 v[8];
    for (int i = 0; i < n; ++i) {
      double a = middle + rng.uniform(-0.5, 0.5) * width;
      if (trial % 3 == 1 && i > 0) a = std::nextafter(std::atan2(v[0].y(), v[0].x()), i % 2 ? 10.0 : -10.0);
      if (trial % 3 == 2 && i % 2) a = std::atan2(v[i - 1].y(), v[i - 1].x());  // the same ray
      const double r = rng.uniform(0.01, 5.0);
      v[i] = r * Vec2(std::cos(a), std::sin(a));
    }
    if (trial % 50 == 0) v[n - 1] = Vec2::Zero();
    for (int side : {-1, 1}) {
      const double want = reference(v, n, side), got = extreme_angle(v, n, side);
      if (std::memcmp(&want, &got, sizeof got) != 0)
        FAIL("trial " << trial << " side " << side << ": " << got << " instead of " << want);
    }
  }
  SUCCEED();
}
