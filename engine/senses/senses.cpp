#include "senses/senses.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "core/shape.h"
#include "senses/senses_internal.h"

namespace roger {
namespace {

constexpr double kUMin = -0.5;  // the image's right edge, in pixels (its left is pixels - 0.5)

// One surface's extent in the image, before occlusion.
struct Extent {
  double u0, u1;    // pixel coordinates, clipped to the image
  double distance;  // nearest point of the surface to the eye
  const SeenSurface* surface;
};

// The field of view widened by a margin, as the two half-planes through the eye whose
// intersection it is (a cone narrower than pi): a surface whose bounding disk lies wholly outside
// either is out of view. Two dot products per surface instead of extent_of's arc tangent and arc
// sine; the margin (1e-6 rad, far beyond their rounding) keeps it from dropping a surface that
// extent_of would keep, so the images are the same to the bit.
struct ViewCone {
  Vec2 eye, inward_left, inward_right;  // unit normals of the boundary lines, pointing inside
  ViewCone(const Vec2& at, double heading, double half_fov) : eye(at) {
    constexpr double kMargin = 1e-6;
    const double left = heading + half_fov + kMargin, right = heading - half_fov - kMargin;
    inward_left = Vec2(std::sin(left), -std::cos(left));
    inward_right = Vec2(-std::sin(right), std::cos(right));
  }
  bool misses(const SeenSurface& s) const {
    const Vec2 c = s.center - eye;
    return inward_left.dot(c) < -s.radius || inward_right.dot(c) < -s.radius;
  }
};

// An angular span in the eye frame, and the distance from the eye to the nearest point of what
// spans it.
struct Span {
  double lo, hi, distance;
};

// A disk's span, d from the eye to its centre, which lies at center_angle.
Span disk_span(const SeenSurface& s, double d, double center_angle, double half_fov) {
  if (d <= s.radius) return {-half_fov, half_fov, 0.0};  // the eye is inside: it sees nothing else
  const double half = std::asin(s.radius / d);
  return {center_angle - half, center_angle + half, d - s.radius};
}

// A convex polygon's span; false when even its bounding disk is out of the field of view.
bool polygon_span(const SeenSurface& s, const Vec2& eye, double eye_heading, double d, double center_angle,
                  double half_fov, Span& out) {
  // Outside the field of view even as its bounding disk: skip the per-vertex work (the disk's
  // extent contains the polygon's, so this never hides what the test below would show).
  if (d > s.radius) {
    const double half = std::asin(s.radius / d) + 1e-9;
    if (center_angle + half <= -half_fov || center_angle - half >= half_fov) return false;
  }
  // Vertex angles relative to the centre direction: a convex polygon seen from outside spans
  // less than pi, so min and max give its extent without wrap-around trouble.
  const double ref = center_angle + eye_heading;
  const double c = std::cos(ref), sn = std::sin(ref);
  bool inside = true;
  double nearest = INFINITY;  // the least squared distance to an edge
  Vec2 along[8];              // each vertex in the frame of the centre's direction
  for (int i = 0; i < s.vertex_count; ++i) {
    const Vec2 v = s.vertices[i] - eye;
    along[i] = Vec2(c * v.x() + sn * v.y(), -sn * v.x() + c * v.y());
    const Vec2& p = s.vertices[i];
    const Vec2& q = s.vertices[(i + 1) % s.vertex_count];
    const Vec2 e = q - p;
    if (e.x() * (eye.y() - p.y()) - e.y() * (eye.x() - p.x()) < 0) inside = false;
    const double t = std::clamp((eye - p).dot(e) / e.squaredNorm(), 0.0, 1.0);
    nearest = std::min(nearest, (p + t * e - eye).squaredNorm());
  }
  if (inside) {
    out = {-half_fov, half_fov, 0.0};
    return true;
  }
  // The least of the distances is the root of the least square: a rounded square root is monotonic.
  // The extremes of the vertices' angles: two or three arc tangents where each vertex took one.
  out = {center_angle + senses_internal::extreme_angle(along, s.vertex_count, -1),
         center_angle + senses_internal::extreme_angle(along, s.vertex_count, +1), std::sqrt(nearest)};
  return true;
}

// Computes a surface's angular extent in the eye frame; false when it is outside the field of view.
bool extent_of(const SeenSurface& s, const Vec2& eye, double eye_heading, const Camera& cam, Extent& out) {
  const double half_fov = cam.half_fov;
  const Vec2 to_center = s.center - eye;
  const double center_angle = wrap_angle(std::atan2(to_center.y(), to_center.x()) - eye_heading);
  const double d = to_center.norm();
  Span span;
  if (s.is_disk) {
    span = disk_span(s, d, center_angle, half_fov);
  } else if (!polygon_span(s, eye, eye_heading, d, center_angle, half_fov, span)) {
    return false;
  }
  if (span.hi <= -half_fov || span.lo >= half_fov) return false;
  const double lo = std::max(span.lo, -half_fov), hi = std::min(span.hi, half_fov);
  const double u_max = cam.pixels - 0.5;
  out.u0 = std::clamp(cam.pixel_of_angle(lo), kUMin, u_max);
  out.u1 = std::clamp(cam.pixel_of_angle(hi), kUMin, u_max);
  out.distance = span.distance;
  out.surface = &s;
  return out.u1 > out.u0;
}

// Sets n pixels from `first` to a surface. The values are copied first: bytes written through
// the image may alias any byte, so the compiler would otherwise read them again for every pixel.
// Inlined in both callers: a call per painted part cost more than the fill of a few pixels.
[[gnu::always_inline]] inline void fill_pixels(EyeImage& image, int first, int n, Colour colour, SurfaceKind kind,
                                               int16_t index) {
  // Eight colours per 24-byte copy (std::fill_n of a 3-byte colour is a loop of byte stores).
  Colour eight[8];
  std::fill_n(eight, 8, colour);
  Colour* colours = image.colour.data() + first;
  int c = 0;
  for (; c + 8 <= n; c += 8) std::memcpy(colours + c, eight, sizeof eight);
  for (; c < n; ++c) colours[c] = colour;
  std::fill_n(image.kind.begin() + first, n, kind);
  // Four indices per 8-byte store (a loop of 2-byte stores is what the compiler makes otherwise).
  const uint64_t four = uint64_t(uint16_t(index)) * 0x0001000100010001ull;
  int16_t* indices = image.index.data() + first;
  int i = 0;
  for (; i + 4 <= n; i += 4) std::memcpy(indices + i, &four, sizeof four);
  for (; i < n; ++i) indices[i] = index;
}

// Adds a whole pixel's coverage to n pixels, capped at 1: float(min(1.0, c + 1.0)) for each,
// which is 1 for every coverage a painted image can hold (paint_eye starts each pixel at +0 and
// only ever adds a positive overlap, so c >= 0, and c + 1 >= 1): the pixels become 1, the same
// bits without the sums.
void cover_whole_pixels(float* coverage, int n) { std::fill_n(coverage, n, 1.0f); }

// Paints the visible part [lo, hi) of a surface: pixels whose centre it covers take its colour,
// and stimulus-coloured parts add their exact coverage to the edge pixels.
void paint_part(double lo, double hi, const SeenSurface& s, bool is_stimulus, EyeImage& image) {
  const int first = std::max(0, int(std::ceil(lo)));         // centre u >= lo
  const int pixels = image.pixels();
  const int last = std::min(pixels - 1, int(std::ceil(hi)) - 1);  // centre u < hi
  if (last >= first) fill_pixels(image, first, last - first + 1, s.colour, s.kind, s.index);
  if (!is_stimulus) return;
  const int p0 = std::max(0, int(std::floor(lo + 0.5)));
  const int p1 = std::min(pixels - 1, int(std::floor(hi + 0.5)));
  if (p0 <= p1) {
    image.stimulus_first = int16_t(std::min<int>(image.stimulus_first, p0));
    image.stimulus_last = int16_t(std::max<int>(image.stimulus_last, p1));
  }
  float* coverage = image.stimulus.data();
  auto cover = [&](int i) {
    const double overlap = std::min(hi, i + 0.5) - std::max(lo, i - 0.5);
    if (overlap > 0) coverage[i] = float(std::min(1.0, coverage[i] + overlap));
  };
  // The edge pixels, then the run of pixels wholly inside [lo, hi], whose overlap is exactly 1
  // ((i + 0.5) - (i - 0.5)): those become 1 (cover_whole_pixels), the same bits as the sums.
  int i = p0;
  for (; i <= p1 && !(i - 0.5 >= lo && i + 0.5 <= hi); ++i) cover(i);
  int inner_end = i;  // one past the last pixel wholly inside
  if (i <= p1) {
    inner_end = std::min(p1, int(std::floor(hi - 0.5))) + 1;
    while (inner_end > i && (inner_end - 1) + 0.5 > hi) --inner_end;
    while (inner_end <= p1 && inner_end + 0.5 <= hi) ++inner_end;
  }
  cover_whole_pixels(coverage + i, inner_end - i);
  for (i = inner_end; i <= p1; ++i) cover(i);
}

// Whether the 8 floats from p are all +0 (every bit clear).
inline bool all_zero_bits(const float* p) {
  uint64_t w[4];
  std::memcpy(w, p, sizeof w);
  return (w[0] | w[1] | w[2] | w[3]) == 0;
}

}  // namespace

namespace senses_internal {

// The extreme direction is found by the sign of cross products, which orders two directions of a
// cone narrower than pi; a vertex whose cross product with it is too small to trust (their angles
// within about 1e-12 rad, where an arc tangent's last-bit error could order them the other way)
// has its arc tangent taken as well. Every vertex left out then lies surely short of one taken, so
// its arc tangent is smaller (greater): the min (max) is that of all n, to the bit.
double extreme_angle(const Vec2* v, int n, int side) {
  auto beyond = [side](const Vec2& a, const Vec2& b) {  // a lies further towards `side` than b
    return side * (b.x() * a.y() - b.y() * a.x()) > 0.0;
  };
  int best = 0;
  for (int i = 1; i < n; ++i)
    if (beyond(v[i], v[best])) best = i;
  double extreme = 0.0;
  auto take = [&](const Vec2& u) {
    const double a = std::atan2(u.y(), u.x());
    extreme = side < 0 ? std::min(extreme, a) : std::max(extreme, a);
  };
  take(v[best]);
  for (int i = 0; i < n; ++i) {
    if (i == best) continue;
    // Rounding of the cross product is below 3 units in the last place of the sum of the sizes
    // of its two products; far beyond that margin its sign is the angles' order.
    const double cross = v[best].x() * v[i].y() - v[best].y() * v[i].x();
    const double scale = (std::abs(v[best].x()) + std::abs(v[best].y())) * (std::abs(v[i].x()) + std::abs(v[i].y()));
    if (!(side * cross < -1e-12 * scale)) take(v[i]);  // not surely short of the extreme
  }
  return extreme;
}

}  // namespace senses_internal

void append_seen_surfaces(std::vector<SeenSurface>& out, const Shape& shape, const Pose& pose,
                          SurfaceKind kind, int index, const Colour& colour) {
  for (const auto& poly : shape.polygons) {
    SeenSurface s;
    s.kind = kind, s.index = int16_t(index), s.colour = colour, s.is_disk = false;
    s.vertex_count = int(poly.vertices.size());
    Vec2 sum = Vec2::Zero();
    for (int i = 0; i < s.vertex_count; ++i) sum += (s.vertices[i] = to_world(pose, poly.vertices[i]));
    s.center = sum / s.vertex_count;
    for (int i = 0; i < s.vertex_count; ++i) s.radius = std::max(s.radius, (s.vertices[i] - s.center).norm());
    out.push_back(s);
  }
  for (const auto& disk : shape.disks) {
    SeenSurface s;
    s.kind = kind, s.index = int16_t(index), s.colour = colour, s.is_disk = true;
    s.center = to_world(pose, disk.center);
    s.radius = disk.radius;
    out.push_back(s);
  }
}

EyeImage& EyeImage::operator=(const EyeImage& other) {
  if (this == &other) return *this;
  const size_t n = size_t(std::clamp(other.pixels(), 0, kMaxPixels));
  camera = other.camera;
  std::copy_n(other.colour.begin(), n, colour.begin());
  std::copy_n(other.kind.begin(), n, kind.begin());
  std::copy_n(other.index.begin(), n, index.begin());
  std::copy_n(other.stimulus.begin(), n, stimulus.begin());
  stimulus_colour = other.stimulus_colour;
  stimulus_first = other.stimulus_first, stimulus_last = other.stimulus_last;
  noisy = other.noisy;
  return *this;
}
// noisy is the last member: one added after it (and not copied above) would grow the image.
static_assert(sizeof(EyeImage) < offsetof(EyeImage, noisy) + sizeof(bool) + alignof(EyeImage),
              "EyeImage::operator= copies every member");

void paint_eye(const Camera& camera, const Vec2& eye, double eye_heading,
               const std::vector<SeenSurface>& surfaces, const Colour& wall_colour,
               const Colour& stimulus_colour, EyeImage& image) {
  // Scratch space reused across calls: no allocation in the control loop once warmed up.
  thread_local std::vector<Extent> extents;
  thread_local std::vector<std::pair<double, double>> covered, next;
  extents.clear();
  covered.clear();
  const ViewCone cone(eye, eye_heading, camera.half_fov);
  for (const auto& s : surfaces) {
    Extent e;
    if (!cone.misses(s) && extent_of(s, eye, eye_heading, camera, e)) extents.push_back(e);
  }
  // Nearest first; insertion sort is fastest for the handful of surfaces a world has.
  for (size_t i = 1; i < extents.size(); ++i)
    for (size_t j = i; j > 0 && extents[j].distance < extents[j - 1].distance; --j)
      std::swap(extents[j], extents[j - 1]);

  image.camera = camera;
  const int pixels = camera.pixels;
  const double u_max = pixels - 0.5;
  fill_pixels(image, 0, pixels, wall_colour, SurfaceKind::kWall, -1);
  std::fill_n(image.stimulus.begin(), pixels, 0.0f);
  image.stimulus_colour = stimulus_colour;
  image.noisy = false;
  image.stimulus_first = int16_t(pixels), image.stimulus_last = -1;  // nothing painted yet

  for (const Extent& e : extents) {
    const bool is_stimulus = !e.surface->ignored && e.surface->colour == stimulus_colour;
    // Visible parts: [u0, u1] minus the covered intervals (sorted, disjoint).
    double cursor = e.u0;
    for (const auto& c : covered) {
      if (c.second <= cursor) continue;
      if (c.first >= e.u1) break;
      if (c.first > cursor) paint_part(cursor, c.first, *e.surface, is_stimulus, image);
      cursor = std::max(cursor, c.second);
      if (cursor >= e.u1) break;
    }
    if (cursor < e.u1) paint_part(cursor, e.u1, *e.surface, is_stimulus, image);
    // Merge [u0, u1] into the covered set.
    next.clear();
    double lo = e.u0, hi = e.u1;
    bool placed = false;
    for (const auto& c : covered) {
      if (c.second < lo) {
        next.push_back(c);
      } else if (c.first > hi) {
        if (!placed) next.emplace_back(lo, hi), placed = true;
        next.push_back(c);
      } else {
        lo = std::min(lo, c.first), hi = std::max(hi, c.second);
      }
    }
    if (!placed) next.emplace_back(lo, hi);
    covered.swap(next);
    if (covered.size() == 1 && covered[0].first <= kUMin && covered[0].second >= u_max) break;
  }
}

namespace {

// The best run so far of a scan for the stimulus, and how to weigh another against it.
struct RunChoice {
  Sighting best;
  double best_mass = 0.0;
  bool best_preferred = false;
  int prefer_index = -1;

  // Weighs the run of pixels [start, end] of `image`, of object `index`. An edge pixel shared with
  // a neighbouring run of another object holds both runs' coverage, of which this run's is under
  // half (the pixel's centre is on neither): it counts for at most half a pixel.
  void consider(const EyeImage& image, int start, int end, int index, bool shared_lo, bool shared_hi,
                double mass) {
    // With several objects of the stimulus colour in view, stereo must pair the same one in both
    // eyes: a run of the preferred surface beats any other, whatever their sizes.
    const bool preferred = prefer_index >= 0 && index == prefer_index;
    if (best_preferred && !preferred) return;
    if (mass <= best_mass && preferred == best_preferred) return;
    best_mass = mass;
    best_preferred = preferred;
    best.index = index;
    // The edge pixels' coverage locates the edges inside them, as area-sampling cameras allow.
    const double c_lo = shared_lo ? std::min(0.5f, image.stimulus[size_t(start)]) : image.stimulus[size_t(start)];
    const double c_hi = shared_hi ? std::min(0.5f, image.stimulus[size_t(end)]) : image.stimulus[size_t(end)];
    double lo, hi;
    if (start == end) {
      lo = start - 0.5 * c_lo;
      hi = start + 0.5 * c_hi;
    } else {
      lo = start + 0.5 - c_lo;
      hi = end - 0.5 + c_hi;
    }
    best.seen = true;
    best.clipped = start == 0 || end == image.pixels() - 1;
    best.u_lo = lo;
    best.u_hi = hi;
    const Camera& cam = image.camera;
    const double angle_lo = cam.angle_of_pixel(lo), angle_hi = cam.angle_of_pixel(hi);
    best.bearing = 0.5 * (angle_lo + angle_hi);
    best.half_width = 0.5 * (angle_hi - angle_lo);
    best.u = cam.pixel_of_angle(best.bearing);
  }
};

constexpr int kNoObject = -2;  // no pixel centre of a run on an object of the stimulus colour yet

// Whether pixel k's centre lies on object `object` (two comparisons: most pixels of a run are one
// object's, and need not be tested for the stimulus colour).
inline bool on_object(const EyeImage& image, int k, int object) {
  return image.index[size_t(k)] == object && image.kind[size_t(k)] == SurfaceKind::kObject;
}

// Whether pixel k's centre lies on a surface of the stimulus colour (whose index it carries). In a
// noisy image no colour equals the stimulus's: a pixel reads as it when its coverage does.
inline bool on_stimulus(const EyeImage& image, int k) {
  if (image.noisy) return image.stimulus[size_t(k)] >= kStimulusStrong && image.kind[size_t(k)] == SurfaceKind::kObject;
  return image.colour[size_t(k)] == image.stimulus_colour && image.kind[size_t(k)] != SurfaceKind::kWall;
}

// The coverage of pixels [first, last], summed in order.
inline double coverage_sum(const EyeImage& image, int first, int last) {
  double mass = 0.0;
  for (int k = first; k <= last; ++k) mass += image.stimulus[size_t(k)];
  return mass;
}

// Weighs the covered pixels [start, end], split into one run per object of the stimulus colour
// whose surfaces the pixels' centres lie on. Two such objects side by side in the image, one
// partly behind the other or with a sliver of wall between them, made one run whose centre lay
// between them: stereo then paired it with the other eye's view of one of them and placed the
// object metres off (8-object sorting, seed 180006), every other tick as the base rocked.
void consider_runs(const EyeImage& image, int start, int end, RunChoice& choice) {
  int first = start, object = kNoObject, last_own = -1;  // the run being built: from, of, last centre on it
  bool shared_lo = false;
  for (int k = start; k <= end; ++k) {
    if (on_object(image, k, object)) {
      last_own = k;
      continue;
    }
    if (!on_stimulus(image, k)) continue;
    const int index = image.index[size_t(k)];
    if (object == kNoObject) {
      object = index, last_own = k;
      continue;
    }
    // Another object from k on. Between the two objects' last and first centres lie their edge
    // pixels: none where one hides the other, one pixel of wall that holds both edges (shared by
    // both runs), or two, the first the one's and the second the other's.
    const int between = k - last_own - 1;
    const bool shared = between == 1;
    const int last = between > 0 ? last_own + 1 : last_own;
    choice.consider(image, first, last, object, shared_lo, shared, coverage_sum(image, first, last));
    first = between > 0 ? k - 1 : k;
    shared_lo = shared;
    object = index, last_own = k;
  }
  choice.consider(image, first, end, object, shared_lo, false, coverage_sum(image, first, end));
}

}  // namespace

Sighting detect_stimulus(const EyeImage& image, int prefer_index) {
  RunChoice choice;
  choice.prefer_index = prefer_index;
  // Outside [stimulus_first, stimulus_last] no pixel has coverage: no run starts or ends there.
  const int pixels = image.pixels();
  int i = std::max(0, int(image.stimulus_first));
  const int end_scan = std::min(pixels, int(image.stimulus_last) + 1);
  while (i < end_scan) {
    // Most of an image has no stimulus: skip 8 pixels at a time whose coverage is +0 by its bits
    // (what fill() and an unpainted pixel hold), which the test below would pass over one by one.
    if (i + 8 <= pixels && all_zero_bits(&image.stimulus[size_t(i)])) {
      i += 8;
      continue;
    }
    if (image.stimulus[i] <= 0.0f) {
      ++i;
      continue;
    }
    // A run, and whether its pixels' centres lie on more than one object of the stimulus colour
    // (rare).
    const int start = i;
    double mass = 0.0;
    int object = kNoObject;
    bool several = false;
    for (; i < pixels && image.stimulus[i] > 0.0f; ++i) {
      mass += image.stimulus[i];
      if (on_object(image, i, object) || !on_stimulus(image, i)) continue;
      if (object == kNoObject) object = image.index[size_t(i)];
      else several = true;
    }
    if (several) {
      consider_runs(image, start, i - 1, choice);
    } else {
      // One object's run (every run of a world with one object of the stimulus colour): its index
      // is its middle pixel's.
      choice.consider(image, start, i - 1, image.index[size_t((start + i - 1) / 2)], false, false, mass);
    }
  }
  return choice.best;
}

bool triangulate(const Vec2& left_eye, double left_angle, const Vec2& right_eye, double right_angle,
                 Vec2& out) {
  const Vec2 dl(std::cos(left_angle), std::sin(left_angle));
  const Vec2 dr(std::cos(right_angle), std::sin(right_angle));
  const double denom = dl.x() * dr.y() - dl.y() * dr.x();
  if (std::abs(denom) < 1e-9) return false;  // parallel rays: the stimulus is at infinity
  const Vec2 b = right_eye - left_eye;
  const double tl = (b.x() * dr.y() - b.y() * dr.x()) / denom;
  const double tr = (b.x() * dl.y() - b.y() * dl.x()) / denom;
  if (tl <= 0.0 || tr <= 0.0 || tl > 50.0) return false;
  out = left_eye + tl * dl;
  return true;
}

}  // namespace roger
