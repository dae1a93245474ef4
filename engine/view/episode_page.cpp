// episode_page.cpp: the episode folder's two text files: episode.json (everything needed to draw
// and replay the episode: the world's shapes, every frame's poses, arms, eyes, images and touch,
// every tick's controller states and the decisions) and index.html (the vector viewer of
// web/episode.html, with that same data embedded, since a page opened from the file system cannot
// fetch() a file beside it).
#include "view/animation_internal.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "core/text.h"
#include "learn/decision_cycle.h"
#include "episode_page_html.h"  // generated from web/episode.html by engine/embed_text.cmake

namespace roger::anim {
namespace {

// A pose as {"x", "y", "theta"}.
json pose_json(const Pose& p) { return {{"x", p.x}, {"y", p.y}, {"theta", p.theta}}; }

// Text for an HTML element or attribute.
std::string html_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

// JSON safe to place inside a <script> element: '<' only occurs inside JSON strings, where \u003c
// means the same, so no name can close the element or open a comment.
std::string script_json(const json& j) {
  const std::string s = j.dump(-1, ' ', false, json::error_handler_t::replace);
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    if (c == '<')
      out += "\\u003c";
    else
      out += c;
  }
  return out;
}

// Replaces every {{key}} in the page template in one pass, so a title that happens to contain
// "{{DATA}}" stays text instead of being filled in itself.
std::string fill(const std::string& page,
                 const std::vector<std::pair<std::string, std::string>>& values) {
  std::string out;
  out.reserve(page.size());
  size_t at = 0;
  while (at < page.size()) {
    const size_t open = page.find("{{", at);
    const size_t close = open == std::string::npos ? open : page.find("}}", open + 2);
    if (close == std::string::npos) break;
    const std::string key = page.substr(open + 2, close - open - 2);
    const auto hit = std::find_if(values.begin(), values.end(),
                                  [&](const auto& kv) { return kv.first == key; });
    out.append(page, at, open - at);
    if (hit != values.end()) {
      out += hit->second;
      at = close + 2;
    } else {
      out += "{{";
      at = open + 2;
    }
  }
  out.append(page, std::min(at, page.size()), std::string::npos);
  return out;
}

// A point as [x, y], rounded to 0.1 mm: the page draws, it does not integrate.
json point_json(const Vec2& p) {
  return json::array({std::round(p.x() * 1e4) / 1e4, std::round(p.y() * 1e4) / 1e4});
}

// A shape in its own frame: convex polygons and disks.
json shape_json(const Shape& shape) {
  json polygons = json::array(), disks = json::array();
  for (const Polygon& poly : shape.polygons) {
    json vertices = json::array();
    for (const Vec2& v : poly.vertices) vertices.push_back(point_json(v));
    polygons.push_back(vertices);
  }
  for (const Disk& d : shape.disks) disks.push_back({{"center", point_json(d.center)}, {"radius", d.radius}});
  return {{"polygons", polygons}, {"disks", disks}};
}

// What does not change in an episode: the arena, the bodies' shapes and colours, the goals and the
// dimensions of Roger, so the page can draw every frame from poses alone.
json world_json(const WorldSpec& spec) {
  const RobotParams& robot = spec.body;
  json objects = json::array(), obstacles = json::array(), goals = json::array();
  for (const ObjectSpec& obj : spec.objects)
    objects.push_back({{"name", valid_utf8(obj.name)}, {"colour", obj.colour.hex()},
                       {"shape", shape_json(obj.shape)}});
  for (const ObstacleSpec& ob : spec.obstacles)
    obstacles.push_back({{"name", valid_utf8(ob.name)}, {"colour", ob.colour.hex()},
                         {"pose", pose_json(ob.pose)}, {"shape", shape_json(ob.shape)}});
  for (const GoalRegion& g : spec.goals)
    goals.push_back({{"name", valid_utf8(g.name)}, {"colour", g.colour.hex()},
                     {"center", point_json(g.center)}, {"radius", g.radius}});
  const ArenaSpec& a = spec.arena;
  return {{"arena", {{"xmin", a.xmin}, {"xmax", a.xmax}, {"ymin", a.ymin}, {"ymax", a.ymax},
                     {"wall_colour", a.wall_colour.hex()}}},
          {"robot", {{"base_radius", robot.base_radius}, {"hand_radius", robot.hand_radius},
                     {"link_width", robot.link_width}, {"axle_half_width", robot.axle_half_width},
                     {"upper_arm", robot.link_length[0]}, {"forearm", robot.link_length[1]},
                     {"shoulder_y", robot.shoulder_y}, {"eye_y", robot.eye_y},
                     {"pixels", spec.eyes.pixels}, {"field_of_view", 0.5 * spec.eyes.fov}}},
          {"objects", objects},
          {"obstacles", obstacles},
          {"goals", goals},
          {"stimulus_colour", spec.stimulus_colour.hex()}};
}

// One eye's image as its pixels' colours "rrggbb" in one string, pixel 0 (the right edge of the
// view) first.
std::string image_text(const EyeImage& image) {
  std::string out;
  out.reserve(size_t(image.pixels()) * 6);
  char buf[8];
  for (int u = 0; u < image.pixels(); ++u) {
    const Colour& c = image.colour[size_t(u)];
    std::snprintf(buf, sizeof buf, "%02x%02x%02x", c.r, c.g, c.b);
    out += buf;
  }
  return out;
}

// Everything moving in one frame: the base, arms, eyes and their images, touch and the stereo fix.
json frame_json(const Frame& f) {
  json objects = json::array();
  for (const Pose& p : f.objects) objects.push_back(pose_json(p));
  json arms = json::array(), eyes = json::array(), headings = json::array(), images = json::array(),
       sightings = json::array(), touch = json::array();
  for (const ArmPoints& a : f.arms)
    arms.push_back({point_json(a.shoulder), point_json(a.elbow), point_json(a.hand)});
  for (int e = 0; e < 2; ++e) {
    eyes.push_back(point_json(f.eyes[size_t(e)]));
    headings.push_back(f.eye_heading[size_t(e)]);
    images.push_back(image_text(f.senses.image[size_t(e)]));
    const Sighting& s = f.senses.stimulus[size_t(e)];
    sightings.push_back(s.seen ? json{{"u", s.u}, {"u_lo", s.u_lo}, {"u_hi", s.u_hi}} : json(nullptr));
  }
  static const char* const kSensor[kTactileCount] = {"body", "left hand", "right hand"};
  for (int k = 0; k < kTactileCount; ++k) {
    const Touch& t = f.senses.touch[size_t(k)];
    touch.push_back({{"sensor", kSensor[k]}, {"contact", t.contact}, {"force", t.force},
                     {"friction", t.friction}, {"normal", point_json(t.normal)},
                     {"point", point_json(t.point)}});
  }
  json j = {{"time", f.time}, {"base", pose_json(f.base)}, {"objects", objects}, {"arms", arms},
            {"eyes", eyes}, {"eye_heading", headings}, {"images", images},
            {"sightings", sightings}, {"touch", touch}};
  j["stereo"] = f.senses.stereo_valid ? point_json(f.senses.stimulus_world) : json(nullptr);
  return j;
}

// The viewer (web/episode.html, compiled in). Everything is inline so the folder can be zipped,
// mailed or opened from disk.
const char* const kPage = kEpisodePageHtml;


// The cycle a timed-out episode ended in (learn/decision_cycle.h), or null: each decision's path is
// its action and the states of every watched controller when it began are its state, so a greedy
// policy that repeats the same decisions in the same states until the time-out is found.
json cycle_json(const EpisodeResult& ep, const Timeline& tl) {
  if (ep.success || ep.decisions.size() < 2) return nullptr;
  std::map<std::vector<std::string>, int> path_ids;
  std::map<std::vector<Gamma>, int> state_ids;
  std::vector<int> states, actions;
  for (const Decision& d : ep.decisions) {
    // The states the decision was made on: those recorded at the end of the tick before it.
    const size_t seen = size_t(std::max(0, d.tick - 2));
    std::vector<Gamma> state;
    for (const GammaTrace& g : ep.gammas)
      if (!g.states.empty()) state.push_back(g.states[std::min(g.states.size() - 1, seen)]);
    actions.push_back(path_ids.emplace(d.path, int(path_ids.size())).first->second);
    states.push_back(state_ids.emplace(state, int(state_ids.size())).first->second);
  }
  const DecisionCycle c = find_decision_cycle(states, actions);
  if (c.turns == 0) return nullptr;
  const Decision& from = ep.decisions[size_t(c.first)];
  json turn = json::array();
  const size_t period = c.actions.size();
  for (size_t k = ep.decisions.size() - period; k < ep.decisions.size(); ++k)
    turn.push_back(ep.decisions[k].path.empty() ? std::string() : valid_utf8(ep.decisions[k].path.back()));
  return {{"from_tick", from.tick}, {"from_time", (from.tick - 1) * tl.dt}, {"first_decision", c.first},
          {"turns", c.turns}, {"period", period}, {"actions", turn}};
}

}  // namespace

json episode_json(const WorldSpec& spec, const EpisodeResult& ep, const Timeline& tl,
                  const AnimationOptions& o) {
  json j;
  j["format"] = "roger-episode";
  j["version"] = 2;
  j["title"] = valid_utf8(o.title);
  j["scenario"] = {{"name", valid_utf8(spec.scenario)}, {"seed", spec.seed}};
  j["seed"] = ep.seed;
  j["success"] = ep.success;
  j["reward"] = ep.reward;
  j["sim_seconds"] = ep.sim_seconds;
  j["ticks"] = ep.ticks;
  j["tick_seconds"] = tl.dt;
  j["fps"] = o.fps;
  json names = json::array();
  for (const ObjectSpec& obj : spec.objects) names.push_back(valid_utf8(obj.name));
  j["objects"] = names;
  j["world"] = world_json(spec);
  json frames = json::array();
  for (size_t i = 0; i < ep.frames.size(); ++i) {
    json f = frame_json(ep.frames[i]);
    f["file"] = frame_name(i);
    f["tick"] = tl.frame_ticks[i];
    frames.push_back(std::move(f));
  }
  j["frames"] = frames;
  // One state name per control tick, in the words of the paper's Equation 1.
  json gammas = json::array();
  for (const GammaTrace& g : ep.gammas) {
    json states = json::array();
    for (Gamma s : g.states) states.push_back(gamma_name(s));
    gammas.push_back({{"name", valid_utf8(g.name)}, {"states", states}});
  }
  j["gammas"] = gammas;
  json decisions = json::array();
  for (const Decision& d : ep.decisions) {
    json path = json::array();
    for (const std::string& name : d.path) path.push_back(valid_utf8(name));
    decisions.push_back({{"tick", d.tick}, {"time", (d.tick - 1) * tl.dt}, {"path", path}});
  }
  j["decisions"] = decisions;
  j["cycle"] = cycle_json(ep, tl);
  return j;
}

std::string page_html(const WorldSpec& spec, const EpisodeResult& ep, const Timeline& tl,
                      const AnimationOptions& o, const json& episode) {
  const std::string title = valid_utf8(o.title);
  std::string meta = spec.scenario.empty() ? std::string("world")
                                           : "scenario " + valid_utf8(spec.scenario);
  meta += " \u00b7 world seed " + std::to_string(spec.seed) + " \u00b7 episode seed " +
          std::to_string(ep.seed) + " \u00b7 " + counted(long(ep.frames.size()), "frame");
  return fill(kPage, {{"TITLE", html_escape(title.empty() ? "roger episode"
                                                          : title + " \u2013 roger episode")},
                      {"HEADING", html_escape(title.empty() ? "Episode" : title)},
                      {"META", html_escape(meta)},
                      {"OUTCOME_CLASS", ep.success ? "success" : "timeout"},
                      {"OUTCOME", html_escape(outcome_text(tl))},
                      {"NOREF", kGammaCss[0]},
                      {"NOTCONV", kGammaCss[1]},
                      {"CONV", kGammaCss[2]},
                      {"DATA", script_json(episode)}});
}

}  // namespace roger::anim
