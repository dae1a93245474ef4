// Tests of render.h: pictures load back at the promised size with things where and in the colours
// they should be, files are written atomically, and bad paths are clear errors.
#include <cairo.h>
#include <stdlib.h>

#include <catch2/catch.hpp>

#include "temp_dir.h"
#include "test_files.h"
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/error.h"
#include "view/render.h"
#include "view/render_internal.h"
#include "senses/senses.h"

namespace fs = std::filesystem;
using namespace roger;
using roger::test::slurp;

namespace {

const Vec2 kBall(1.0, 0.8);
const double kBallRadius = 0.2;
const Vec2 kObstacle(-1.2, 1.0);
const Vec2 kGoal(1.0, -1.2);
const Colour kWallColour{200, 200, 200};
const Colour kRed{220, 30, 30};

// A scratch folder named after this test file.
struct TempDir : roger::test::TempDir {
  TempDir() : roger::test::TempDir("test_render") {}
};

WorldSpec make_spec() {
  WorldSpec spec;
  spec.scenario = "render_test";
  spec.seed = 7;
  ObjectSpec ball;
  ball.name = "ball";
  ball.shape.disks.push_back({Vec2::Zero(), kBallRadius});
  ball.colour = kRed;
  ball.pose = {kBall.x(), kBall.y(), 0.0};
  spec.objects.push_back(ball);
  ObjectSpec tri;
  tri.name = "triangle";
  tri.shape.polygons.push_back({{Vec2(0.18, 0), Vec2(-0.12, 0.15), Vec2(-0.12, -0.15)}});
  tri.colour = {240, 190, 40};
  tri.pose = {-0.8, -1.1, 0.6};
  spec.objects.push_back(tri);
  ObstacleSpec wall;
  wall.name = "block";
  wall.shape.polygons.push_back(
      {{Vec2(-0.3, -0.2), Vec2(0.3, -0.2), Vec2(0.3, 0.2), Vec2(-0.3, 0.2)}});
  wall.pose = {kObstacle.x(), kObstacle.y(), 0.3};
  spec.obstacles.push_back(wall);
  GoalRegion goal;
  goal.name = "goal";
  goal.center = kGoal;
  goal.radius = 0.3;
  spec.goals.push_back(goal);
  spec.arena.wall_colour = kWallColour;
  return spec;
}

// Roger at the origin facing +x, arms posed by plain trigonometry, both eyes verged on the ball,
// images painted by casting one ray per pixel at the ball, the left hand pressing the ball.
Frame make_frame() {
  const RobotParams rp;
  Frame f;
  f.time = 3.25;
  f.base = {0.0, 0.0, 0.0};
  // The left hand touches the ball (two-link inverse kinematics); the right arm is folded.
  const Vec2 left_shoulder(0.0, rp.shoulder_y);
  const Vec2 target = kBall - (kBallRadius + rp.hand_radius) * (kBall - left_shoulder).normalized();
  const Vec2 d = target - left_shoulder;
  const double l1 = rp.link_length[0], l2 = rp.link_length[1];
  const double left_elbow = -std::acos((d.squaredNorm() - l1 * l1 - l2 * l2) / (2 * l1 * l2));
  const double left_shoulder_angle =
      std::atan2(d.y(), d.x()) -
      std::atan2(l2 * std::sin(left_elbow), l1 + l2 * std::cos(left_elbow));
  const double shoulder[2] = {left_shoulder_angle, -0.5}, elbow[2] = {left_elbow, 0.9};
  for (int side = 0; side < 2; ++side) {
    const double sign = side == kLeft ? 1.0 : -1.0;
    ArmPoints& a = f.arms[side];
    a.shoulder = Vec2(0.0, sign * rp.shoulder_y);
    const double t1 = shoulder[side], t2 = t1 + elbow[side];
    a.elbow = a.shoulder + l1 * Vec2(std::cos(t1), std::sin(t1));
    a.hand = a.elbow + l2 * Vec2(std::cos(t2), std::sin(t2));
    f.eyes[side] = Vec2(0.0, sign * rp.eye_y);
    const Vec2 to_ball = kBall - f.eyes[side];
    // Verged near the ball but not on it, so the ball sits off the images' centres.
    f.eye_heading[side] = std::atan2(to_ball.y(), to_ball.x()) + (side == kLeft ? -0.15 : 0.06);
  }
  f.objects = {Pose{kBall.x(), kBall.y(), 0.4}, Pose{-0.8, -1.1, 0.6}};

  Senses& s = f.senses;
  s.time = f.time;
  s.base = f.base;
  for (int side = 0; side < 2; ++side) {
    EyeImage& img = s.image[side];
    int lo = Camera{}.pixels, hi = -1;
    for (int u = 0; u < Camera{}.pixels; ++u) {
      const double a = f.eye_heading[side] + Camera{}.angle_of_pixel(u);
      const Vec2 d(std::cos(a), std::sin(a));
      const Vec2 m = kBall - f.eyes[side];
      const double along = m.dot(d), miss = (m - along * d).norm();
      const bool hit = along > 0 && miss < kBallRadius;
      img.colour[u] = hit ? kRed : (u % 32 < 16 ? kWallColour : Colour{180, 180, 185});
      img.kind[u] = hit ? SurfaceKind::kObject : SurfaceKind::kWall;
      img.index[u] = hit ? 0 : -1;
      img.stimulus[u] = hit ? 1.0f : 0.0f;
      if (hit) lo = std::min(lo, u), hi = std::max(hi, u);
    }
    REQUIRE(hi >= lo);
    Sighting& seen = s.stimulus[side];
    seen.seen = true;
    seen.u_lo = lo - 0.5;
    seen.u_hi = hi + 0.5;
    seen.bearing = 0.5 * (Camera{}.angle_of_pixel(seen.u_lo) + Camera{}.angle_of_pixel(seen.u_hi));
    seen.u = Camera{}.pixel_of_angle(seen.bearing);
  }
  s.stereo_valid = true;
  s.stimulus_world = kBall;  // the cross-hair's open centre leaves the ball's centre pixel red
  s.stimulus_base = s.stimulus_world;
  Touch& t = s.touch[kLeftHand];
  t.contact = true;
  t.kind = SurfaceKind::kObject;
  t.index = 0;
  t.force = 6.5;
  const Vec2 n = (f.arms[kLeft].hand - kBall).normalized();
  t.normal = n;
  t.point = kBall + kBallRadius * n;
  return f;
}

struct Pixel {
  int r, g, b;
};

// Reads one pixel of an opaque ARGB32 PNG.
Pixel pixel_at(cairo_surface_t* png, const Vec2& at) {
  const int x = int(std::lround(at.x())), y = int(std::lround(at.y()));
  REQUIRE(x >= 0);
  REQUIRE(y >= 0);
  REQUIRE(x < cairo_image_surface_get_width(png));
  REQUIRE(y < cairo_image_surface_get_height(png));
  const unsigned char* row =
      cairo_image_surface_get_data(png) + y * cairo_image_surface_get_stride(png);
  const uint32_t v = reinterpret_cast<const uint32_t*>(row)[x];
  return {int((v >> 16) & 0xff), int((v >> 8) & 0xff), int(v & 0xff)};
}

}  // namespace

TEST_CASE("a PNG shows the ball red, the obstacle grey and the goal green where they are") {
  TempDir dir;
  const WorldSpec spec = make_spec();
  const Frame frame = make_frame();
  RenderOptions options;
  options.width_px = 800;
  options.title = "test picture";
  const fs::path file = dir.path / "frame.png";
  render_frame(spec, frame, file.string(), options);

  cairo_surface_t* png = cairo_image_surface_create_from_png(file.c_str());
  REQUIRE(cairo_surface_status(png) == CAIRO_STATUS_SUCCESS);
  CHECK(cairo_image_surface_get_width(png) == 800);
  const PictureSize size = picture_size(spec, options);
  CHECK(size.width == 800);
  CHECK(cairo_image_surface_get_height(png) == size.height);
  CHECK(size.height > size.width);  // a square arena plus the eye strips below it

  auto at = [&](const Vec2& w) {
    return pixel_at(png, picture_point(spec, options, size.width, size.height, w));
  };
  const Pixel ball = at(kBall);
  CHECK(ball.r > 170);
  CHECK(ball.g < 80);
  CHECK(ball.b < 80);
  const Pixel obstacle = at(kObstacle);
  CHECK(std::abs(obstacle.r - obstacle.g) < 30);
  CHECK(std::abs(obstacle.g - obstacle.b) < 40);
  CHECK(obstacle.r > 50);
  CHECK(obstacle.r < 160);
  const Pixel goal = at(kGoal);
  CHECK(goal.g > goal.r + 20);
  CHECK(goal.g > goal.b + 20);
  // The floor far from everything is light and the walls have the wall colour.
  const Pixel floor = at(Vec2(-1.7, -1.7));
  CHECK(floor.r > 230);
  CHECK(floor.g > 230);
  CHECK(floor.b > 220);
  const Vec2 corner = picture_point(spec, options, size.width, size.height, Vec2(2.0, 0.0));
  const Pixel wall = pixel_at(png, corner + Vec2(3.0, 0.0));
  CHECK(std::abs(wall.r - kWallColour.r) < 12);
  // Roger's base is drawn in light steel, not in any object's colour.
  const Pixel base = at(Vec2(-0.1, 0.0));
  CHECK(base.b > 200);
  CHECK(base.r > 180);
  cairo_surface_destroy(png);

  CHECK(dir.names() == std::vector<std::string>{"frame.png"});  // no temporary left behind
}

TEST_CASE("an SVG is written and is an SVG document") {
  TempDir dir;
  const fs::path file = dir.path / "frame.SVG";  // extensions are case-insensitive
  render_frame(make_spec(), make_frame(), file.string());
  const std::string text = slurp(file);
  REQUIRE(!text.empty());
  CHECK((text.rfind("<?xml", 0) == 0 || text.find("<svg") != std::string::npos));
  CHECK(text.find("width=\"1000") != std::string::npos);
  CHECK(dir.names() == std::vector<std::string>{"frame.SVG"});
}

TEST_CASE("a file with another extension is refused with the accepted ones named") {
  TempDir dir;
  const fs::path file = dir.path / "frame.jpg";
  try {
    render_frame(make_spec(), make_frame(), file.string());
    FAIL("no error for .jpg");
  } catch (const Error& e) {
    const std::string what = e.what();
    CHECK(what.find(".jpg") != std::string::npos);
    CHECK(what.find(".png") != std::string::npos);
    CHECK(what.find(".svg") != std::string::npos);
  }
  CHECK_THROWS_AS(render_frame(make_spec(), make_frame(), (dir.path / "frame").string()), Error);
  CHECK(dir.names().empty());
}

TEST_CASE("an unwritable path is an error naming it, and leaves no file") {
  // A folder cannot be made under a file (a missing folder is made, as for every output).
  TempDir dir;
  { std::ofstream(dir.path / "a_file") << "x"; }
  const std::string path = (dir.path / "a_file" / "x.png").string();
  try {
    render_frame(make_spec(), make_frame(), path);
    FAIL("no error for an unwritable path");
  } catch (const Error& e) {
    const std::string what = e.what();
    CHECK(what.find(path) != std::string::npos);
    CHECK(what.find("Not a directory") != std::string::npos);
  }
  CHECK(dir.names() == std::vector<std::string>{"a_file"});
  // A missing folder is made.
  render_frame(make_spec(), make_frame(), (dir.path / "new" / "deeper" / "x.png").string());
  CHECK(fs::file_size(dir.path / "new" / "deeper" / "x.png") > 1000);
}

TEST_CASE("a picture replaces an existing file whole, and a failed drawing keeps the old one") {
  TempDir dir;
  const fs::path file = dir.path / "frame.png";
  { std::ofstream(file) << "old"; }
  render_frame(make_spec(), make_frame(), file.string());
  const std::string png = slurp(file);
  CHECK(png.substr(1, 3) == "PNG");

  // A frame whose object poses do not match the spec is refused; the old picture stays.
  Frame bad = make_frame();
  bad.objects.pop_back();
  CHECK_THROWS_WITH(render_frame(make_spec(), bad, file.string()),
                    Catch::Contains("1 object poses") && Catch::Contains("2 objects"));
  CHECK(slurp(file) == png);
  CHECK(dir.names() == std::vector<std::string>{"frame.png"});
}

TEST_CASE("a frame without object poses shows the objects at their starting poses") {
  TempDir dir;
  WorldSpec spec = make_spec();
  Frame frame = make_frame();
  frame.objects.clear();
  spec.objects[0].pose = {-1.0, -0.3, 0.0};
  RenderOptions options;
  options.width_px = 500;
  options.show_images = false;
  options.show_status = false;
  const fs::path file = dir.path / "preview.png";
  render_frame(spec, frame, file.string(), options);
  cairo_surface_t* png = cairo_image_surface_create_from_png(file.c_str());
  REQUIRE(cairo_surface_status(png) == CAIRO_STATUS_SUCCESS);
  const PictureSize size = picture_size(spec, options);
  CHECK(cairo_image_surface_get_height(png) == size.height);
  CHECK(size.height < size.width + 100);  // without strips, the picture is nearly square
  const Pixel ball =
      pixel_at(png, picture_point(spec, options, size.width, size.height, Vec2(-1.0, -0.3)));
  CHECK(ball.r > 170);
  CHECK(ball.g < 80);
  cairo_surface_destroy(png);
}

TEST_CASE("several frames make a mosaic of equal panels") {
  TempDir dir;
  const WorldSpec spec = make_spec();
  std::vector<Frame> frames(3, make_frame());
  frames[1].time = 3.5;
  frames[2].time = 3.75;
  RenderOptions options;
  options.width_px = 400;
  const PictureSize panel = picture_size(spec, options);
  const fs::path file = dir.path / "mosaic.png";
  render_frames(spec, frames, file.string(), options, 2);
  cairo_surface_t* png = cairo_image_surface_create_from_png(file.c_str());
  REQUIRE(cairo_surface_status(png) == CAIRO_STATUS_SUCCESS);
  CHECK(cairo_image_surface_get_width(png) == 2 * panel.width);
  CHECK(cairo_image_surface_get_height(png) == 2 * panel.height);
  // The third panel (second row, first column) has the ball where a single picture has it.
  const Vec2 p = picture_point(spec, options, panel.width, panel.height, kBall);
  const Pixel ball = pixel_at(png, p + Vec2(0, panel.height));
  CHECK(ball.r > 170);
  CHECK(ball.g < 80);
  cairo_surface_destroy(png);
  CHECK_THROWS_AS(render_frames(spec, {}, file.string(), options), Error);
  CHECK(dir.names() == std::vector<std::string>{"mosaic.png"});
}

TEST_CASE("draw_frame draws onto a caller's surface and leaves its state alone") {
  const WorldSpec spec = make_spec();
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, 640, 480);
  cairo_t* cr = cairo_create(surface);
  cairo_set_line_width(cr, 7.0);
  draw_frame(cr, spec, make_frame(), RenderOptions{}, 640, 480);
  CHECK(cairo_status(cr) == CAIRO_STATUS_SUCCESS);
  CHECK(cairo_get_line_width(cr) == 7.0);
  cairo_surface_flush(surface);
  // Off the centre: at this size the stereo cross-hair covers the middle of the ball.
  const Vec2 inside = kBall + Vec2(-0.1, 0.08);
  const Pixel ball = pixel_at(surface, picture_point(spec, RenderOptions{}, 640, 480, inside));
  CHECK(ball.r > 170);
  CHECK(ball.g < 80);
  cairo_destroy(cr);
  cairo_surface_destroy(surface);
}

TEST_CASE("impossible sizes and arenas are errors, not crashes") {
  TempDir dir;
  const std::string file = (dir.path / "frame.png").string();
  RenderOptions tiny;
  tiny.width_px = 10;
  CHECK_THROWS_WITH(render_frame(make_spec(), make_frame(), file, tiny),
                    Catch::Contains("width_px"));
  WorldSpec flat = make_spec();
  flat.arena.ymax = flat.arena.ymin;
  CHECK_THROWS_WITH(render_frame(flat, make_frame(), file), Catch::Contains("arena"));
  CHECK_THROWS_WITH(render_frames(make_spec(), std::vector<Frame>(40, make_frame()), file),
                    Catch::Contains("32767"));
  CHECK(dir.names().empty());
  // A simulation that blew up still draws: non-finite poses are left out, not passed to cairo.
  Frame broken = make_frame();
  broken.base.x = std::nan("");
  broken.arms[kLeft].hand = Vec2(std::nan(""), 0.0);
  broken.objects[0].theta = std::nan("");
  CHECK_NOTHROW(render_frame(make_spec(), broken, file));
  CHECK(fs::file_size(file) > 1000);
}

TEST_CASE("a titled picture draws as PNG and SVG, inside its own folder") {
  roger::test::TempDir dir("roger_render_sample");
  RenderOptions options;
  options.title = "reach for the ball";
  render_frame(make_spec(), make_frame(), dir.file("sample.png"), options);
  render_frame(make_spec(), make_frame(), dir.file("sample.svg"), options);
  CHECK(fs::file_size(dir.file("sample.png")) > 1000);
  CHECK(fs::file_size(dir.file("sample.svg")) > 1000);
}

TEST_CASE("render_rgb is the PNG's picture, in memory, as rows of RGB bytes") {
  TempDir dir;
  const WorldSpec spec = make_spec();
  const Frame frame = make_frame();
  RenderOptions options;
  options.width_px = 400;
  const fs::path file = dir.path / "frame.png";
  render_frame(spec, frame, file.string(), options);
  const RgbPicture rgb = render_rgb(spec, frame, options);
  const PictureSize size = picture_size(spec, options);
  REQUIRE(rgb.width == size.width);
  REQUIRE(rgb.height == size.height);
  REQUIRE(rgb.pixels.size() == size_t(rgb.width) * size_t(rgb.height) * 3);

  cairo_surface_t* png = cairo_image_surface_create_from_png(file.c_str());
  REQUIRE(cairo_surface_status(png) == CAIRO_STATUS_SUCCESS);
  REQUIRE(cairo_image_surface_get_width(png) == rgb.width);
  REQUIRE(cairo_image_surface_get_height(png) == rgb.height);
  int differing = 0;
  for (int y = 0; y < rgb.height; ++y) {
    const unsigned char* row = cairo_image_surface_get_data(png) + y * cairo_image_surface_get_stride(png);
    for (int x = 0; x < rgb.width; ++x) {
      const uint32_t v = reinterpret_cast<const uint32_t*>(row)[x];
      const uint8_t* q = &rgb.pixels[(size_t(y) * size_t(rgb.width) + size_t(x)) * 3];
      differing += q[0] != ((v >> 16) & 0xff) || q[1] != ((v >> 8) & 0xff) || q[2] != (v & 0xff);
    }
  }
  cairo_surface_destroy(png);
  CHECK(differing == 0);
  // The ball is red where the picture puts it.
  const Vec2 at = picture_point(spec, options, rgb.width, rgb.height, kBall);
  const uint8_t* ball = &rgb.pixels[(size_t(std::lround(at.y())) * size_t(rgb.width) + size_t(std::lround(at.x()))) * 3];
  CHECK(int(ball[0]) > 170);
  CHECK(int(ball[1]) < 80);

  RenderOptions tiny = options;
  tiny.width_px = 10;
  CHECK_THROWS_AS(render_rgb(spec, frame, tiny), Error);
}

// Found by a probe: a goal of radius 1e300 m (its centre in the arena, as a scenario may write it)
// hung roger render, cairo drawing its arc in segments by its length.
TEST_CASE("a goal larger than the picture draws at once and as a disk just covering the picture does") {
  RenderOptions options;
  options.width_px = 400;
  WorldSpec spec = make_spec();
  const PictureSize size = picture_size(spec, options);
  const double w = size.width, h = size.height;
  const Vec2 centre = picture_point(spec, options, w, h, kGoal);
  const double px_per_m = (picture_point(spec, options, w, h, kGoal + Vec2(1, 0)) - centre).norm();
  const double reach = std::hypot(std::max(centre.x(), w - centre.x()), std::max(centre.y(), h - centre.y()));
  spec.goals[0].radius = (reach + 4) / px_per_m;  // its rim 4 pixels past the farthest corner
  const RgbPicture covering = render_rgb(spec, make_frame(), options);
  spec.goals[0].radius = 1e300;
  const RgbPicture huge = render_rgb(spec, make_frame(), options);
  CHECK(huge.pixels == covering.pixels);
  spec.goals[0].radius = 0.3;
  CHECK(render_rgb(spec, make_frame(), options).pixels != covering.pixels);  // the goal does cover it
  // On the floor only: the header's corner and the wall's keep their colours.
  spec.goals.clear();
  const RgbPicture none = render_rgb(spec, make_frame(), options);
  const Vec2 wall = picture_point(spec, options, w, h, Vec2(spec.arena.xmin - 0.02, spec.arena.ymin - 0.02));
  for (const Vec2& at : {Vec2(1, 1), wall}) {
    const size_t i = (size_t(std::lround(at.y())) * size_t(w) + size_t(std::lround(at.x()))) * 3;
    INFO("pixel (" << at.x() << ", " << at.y() << ")");
    CHECK(std::equal(huge.pixels.begin() + long(i), huge.pixels.begin() + long(i) + 3, none.pixels.begin() + long(i)));
  }
  spec.goals = make_spec().goals;
  TempDir dir;
  spec.goals[0].radius = 1e300;
  render_frame(spec, make_frame(), dir.file("huge.svg"), options);
  CHECK(fs::file_size(dir.file("huge.svg")) > 0);
}

// Seen in a rendered frame: the force labels of a three-contact grasp around a small object sat on each
// other and read as one number ("53.13 N 43.5").
TEST_CASE("force labels that would overlap are moved apart, and a label alone stays where it was") {
  using picture::LabelBox;
  const auto overlap = [](const LabelBox& a, const LabelBox& b) {
    return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1;
  };
  std::vector<LabelBox> boxes = {{100, 100, 140, 112}, {110, 104, 150, 116}, {95, 98, 135, 110}, {300, 100, 340, 112}};
  const std::vector<LabelBox> before = boxes;
  picture::separate_labels(boxes);
  for (size_t i = 0; i < boxes.size(); ++i)
    for (size_t j = i + 1; j < boxes.size(); ++j) CHECK_FALSE(overlap(boxes[i], boxes[j]));
  // Only moved down, by whole heights, and not at all when nothing was in the way.
  for (size_t i = 0; i < boxes.size(); ++i) {
    CHECK(boxes[i].x0 == before[i].x0);
    const double moves = (boxes[i].y0 - before[i].y0) / 12.0;
    CHECK(moves == std::floor(moves));
    CHECK(moves >= 0);
  }
  CHECK(boxes[0].y0 == before[0].y0);
  CHECK(boxes[3].y0 == before[3].y0);
  CHECK(boxes[1].y0 == 116);  // one height down: clear of the first box
  CHECK(boxes[2].y0 == 134);  // three heights down: clear of both
}
