// episode_page.cpp: the episode folder's two text files: episode.json (the numbers behind the
// pictures) and index.html (the replay page of web/episode.html, filled with the episode's data).
#include "view/animation_internal.h"

#include <algorithm>
#include <cmath>

#include "episode_page_html.h"  // generated from web/episode.html by embed_text.cmake

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

// The replay page (web/episode.html, compiled in). Everything is inline so the folder can be
// zipped, mailed or opened from disk.
const char* const kPage = kEpisodePageHtml;


}  // namespace

json episode_json(const WorldSpec& spec, const EpisodeResult& ep, const Timeline& tl,
                  const AnimationOptions& o) {
  json j;
  j["format"] = "roger-episode";
  j["version"] = 1;
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
  json frames = json::array();
  for (size_t i = 0; i < ep.frames.size(); ++i) {
    const Frame& f = ep.frames[i];
    json objects = json::array();
    for (const Pose& p : f.objects) objects.push_back(pose_json(p));
    frames.push_back({{"file", frame_name(i)},
                      {"tick", tl.frame_ticks[i]},
                      {"time", f.time},
                      {"base", pose_json(f.base)},
                      {"objects", objects}});
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
  return j;
}

std::string page_html(const WorldSpec& spec, const EpisodeResult& ep, const Timeline& tl,
                      const AnimationOptions& o, const TimelineBox* box, double pic_w,
                      double pic_h) {
  json data;
  data["fps"] = o.fps;
  data["ticks"] = ep.ticks;
  data["sim_seconds"] = ep.sim_seconds;
  json frames = json::array();
  for (size_t i = 0; i < ep.frames.size(); ++i)
    frames.push_back({{"file", frame_name(i)},
                      {"time", std::isfinite(ep.frames[i].time) ? ep.frames[i].time : 0.0},
                      {"tick", tl.frame_ticks[i]}});
  data["frames"] = frames;
  // Each controller's state at each frame (-1 before the first tick), so the page needs no
  // knowledge of control ticks.
  json controllers = json::array();
  for (size_t r = 0; r < tl.rows.size(); ++r) {
    json states = json::array();
    for (long tick : tl.frame_ticks) {
      const Gamma* g = tl.state_at(r, tick);
      states.push_back(g ? int(*g) : -1);
    }
    controllers.push_back({{"name", tl.rows[r].name}, {"states", states}});
  }
  data["controllers"] = controllers;
  if (box)
    data["timeline"] = {{"x0", box->x0 / pic_w}, {"x1", box->x1 / pic_w},
                        {"y0", box->y0 / pic_h}, {"y1", box->y1 / pic_h},
                        {"t_end", tl.t_end}};
  else
    data["timeline"] = nullptr;

  const std::string title = valid_utf8(o.title);
  std::string meta = spec.scenario.empty() ? std::string("world")
                                           : "scenario " + valid_utf8(spec.scenario);
  meta += " \u00b7 world seed " + std::to_string(spec.seed) + " \u00b7 episode seed " +
          std::to_string(ep.seed) + " \u00b7 " + std::to_string(ep.frames.size()) + " frames";
  return fill(kPage, {{"TITLE", html_escape(title.empty() ? "roger episode"
                                                          : title + " \u2013 roger episode")},
                      {"HEADING", html_escape(title.empty() ? "Episode" : title)},
                      {"META", html_escape(meta)},
                      {"OUTCOME_CLASS", ep.success ? "success" : "timeout"},
                      {"OUTCOME", html_escape(outcome_text(tl))},
                      {"NOREF", kGammaCss[0]},
                      {"NOTCONV", kGammaCss[1]},
                      {"CONV", kGammaCss[2]},
                      {"DATA", script_json(data)}});
}

}  // namespace roger::anim
