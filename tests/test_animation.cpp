// Tests of animation.h: a real recorded episode becomes a folder of frames that load back at one
// size, a replay page that needs no network, and episode.json with every tick's states; re-rendering
// never mixes episodes, and bad folders or episodes are clear errors.
#include <cairo.h>
#include <stdlib.h>

#include <csignal>
#include <map>

#include <catch2/catch.hpp>

#include "test_files.h"
#include "temp_dir.h"
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "control/agent.h"
#include "view/animation.h"
#include "learn/episode.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "control/predicate.h"
#include "control/primitives.h"
#include "world_fixtures.h"

namespace fs = std::filesystem;
using namespace roger;
using roger::test::slurp;

namespace {

// A scratch folder named after this test file.
struct TempDir : roger::test::TempDir {
  TempDir() : roger::test::TempDir("test_animation") {}
};

// Sorted names of the frame files in a folder, and whether anything else unexpected is there.
std::vector<std::string> frame_files(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (std::regex_match(name, std::regex(R"(frame_\d+\.png)"))) out.push_back(name);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Loads a PNG with cairo and returns its size (0 x 0 when it does not load).
std::pair<int, int> png_size(const fs::path& p) {
  cairo_surface_t* s = cairo_image_surface_create_from_png(p.string().c_str());
  std::pair<int, int> size{0, 0};
  if (cairo_surface_status(s) == CAIRO_STATUS_SUCCESS)
    size = {cairo_image_surface_get_width(s), cairo_image_surface_get_height(s)};
  cairo_surface_destroy(s);
  return size;
}

// Whether a PNG has a pixel close to colour (r, g, b) in rows [y0, y1).
bool has_colour(const fs::path& p, int y0, int y1, int r, int g, int b) {
  cairo_surface_t* s = cairo_image_surface_create_from_png(p.string().c_str());
  REQUIRE(cairo_surface_status(s) == CAIRO_STATUS_SUCCESS);
  const int w = cairo_image_surface_get_width(s), h = cairo_image_surface_get_height(s);
  const int stride = cairo_image_surface_get_stride(s);
  const unsigned char* data = cairo_image_surface_get_data(s);
  bool found = false;
  for (int y = std::max(0, y0); y < std::min(h, y1) && !found; ++y)
    for (int x = 0; x < w && !found; ++x) {
      const uint32_t px = *reinterpret_cast<const uint32_t*>(data + y * stride + 4 * x);
      const int pr = (px >> 16) & 255, pg = (px >> 8) & 255, pb = px & 255;
      found = std::abs(pr - r) <= 6 && std::abs(pg - g) <= 6 && std::abs(pb - b) <= 6;
    }
  cairo_surface_destroy(s);
  return found;
}

// Phi6 for real: search until both eyes see the ball behind Roger, then track it with phi0; the
// two primitives are watched. Frames every 0.2 s.
struct Phi6Episode {
  WorldSpec spec = test::open_world(true, Vec2(-1.4, 0.6));
  PrimitivePtr search = make_primitive("search");
  PrimitivePtr track = make_primitive("phi0");
  EpisodeResult run(double time_limit) {
    search->set_name("search");
    track->set_name("phi0");
    spec.seed = 3;
    Sequence phi6({search, track});
    phi6.set_name("Phi6");
    PredicatePtr goal = held(converged(track), 0.2);
    EpisodeOptions eo;
    eo.time_limit = time_limit;
    eo.record_every = 0.2;
    Agent agent;
    return run_episode(agent, spec, 11, phi6, *goal, eo, {search, track});
  }
};

AnimationOptions small_options() {
  AnimationOptions o;
  o.frame.width_px = 320;  // small pictures keep the test fast
  o.title = "Phi6 <search & track>";
  return o;
}

}  // namespace

// Found by a probe: a timed-out episode's viewer showed, at its end, the world of its last frame,
// seconds before the time-out. The last moment is a frame whatever the outcome, once.
TEST_CASE("an episode's last moment is a frame, a success's or a time-out's") {
  Phi6Episode timed_out;
  const EpisodeResult short_one = timed_out.run(0.5);  // too short to track: a time-out at tick 25
  REQUIRE_FALSE(short_one.success);
  CHECK(short_one.frame_ticks.back() == short_one.ticks);
  CHECK(short_one.frame_ticks == std::vector<double>{0, 10, 20, 25});
  Phi6Episode succeeded;
  const EpisodeResult whole = succeeded.run(4.0);
  REQUIRE(whole.success);
  CHECK(whole.frame_ticks.back() == whole.ticks);
  CHECK(std::adjacent_find(whole.frame_ticks.begin(), whole.frame_ticks.end()) == whole.frame_ticks.end());
}

TEST_CASE("an episode becomes frames, a replay page and episode.json") {
  Phi6Episode e;
  const EpisodeResult ep = e.run(4.0);
  REQUIRE(ep.frames.size() >= 3);
  REQUIRE(ep.gammas.size() == 2);
  TempDir dir;
  const fs::path out = dir.path / "nested" / "anim";  // missing folders are created
  const AnimationOptions o = small_options();
  render_episode(e.spec, ep, out.string(), o);

  SECTION("one PNG per frame, all the same size: the world picture and the timeline under it") {
    const std::vector<std::string> files = frame_files(out);
    REQUIRE(files.size() == ep.frames.size());
    CHECK(files.front() == "frame_0000.png");
    RenderOptions ro = o.frame;
    const PictureSize world = picture_size(e.spec, ro);
    for (const std::string& f : files) {
      const auto [w, h] = png_size(out / f);
      CHECK(w == 320);
      // Two controller rows: about an eighth of a 320-pixel width below the world picture.
      CHECK(h > world.height + 30);
      CHECK(h < world.height + 60);
    }
    // The last frame's timeline shows states in their colours: !CONV amber (searching) and CONV
    // green (found, tracking), below the world picture.
    const fs::path last = out / files.back();
    const int h_total = png_size(last).second;
    CHECK(has_colour(last, world.height, h_total, 240, 166, 0));
    CHECK(has_colour(last, world.height, h_total, 44, 160, 84));
    // No temporaries left behind by the atomic writes.
    for (const auto& entry : fs::directory_iterator(out))
      CHECK(entry.path().filename().string()[0] != '.');
  }

  SECTION("index.html draws the episode on a canvas from its embedded data, without the network") {
    const std::string html = slurp(out / "index.html");
    REQUIRE(!html.empty());
    CHECK(html.find("<canvas id=\"world\"") != std::string::npos);
    CHECK(html.find("<img") == std::string::npos);  // no pre-drawn frames are replayed
    // The data embedded is episode.json's, so the page needs no file beside it.
    const size_t open = html.find("<script type=\"application/json\" id=\"episode\">");
    REQUIRE(open != std::string::npos);
    const size_t from = html.find('>', open) + 1;
    const nlohmann::json embedded = nlohmann::json::parse(html.substr(from, html.find("</script>", from) - from));
    CHECK(embedded == nlohmann::json::parse(slurp(out / "episode.json")));
    CHECK(!std::regex_search(html, std::regex("https?:", std::regex::icase)));
    CHECK(html.find("<script src") == std::string::npos);
    CHECK(html.find("<link") == std::string::npos);
    // The title is escaped in the markup and controller names are in the page's data.
    CHECK(html.find("Phi6 &lt;search &amp; track&gt;") != std::string::npos);
    CHECK(html.find("\"search\"") != std::string::npos);
    CHECK(html.find("\"phi0\"") != std::string::npos);
    CHECK(html.find(ep.success ? "success after" : "timeout after") != std::string::npos);
  }

  SECTION("names from scripts cannot break the page") {
    EpisodeResult odd = ep;
    odd.gammas[0].name = "</script><b>{{DATA}}";
    AnimationOptions titled = o;
    titled.title = "{{DATA}} \xff";  // invalid UTF-8 too
    render_episode(e.spec, odd, out.string(), titled);
    const std::string html = slurp(out / "index.html");
    CHECK(html.find("</script><b>") == std::string::npos);
    CHECK(html.find("\\u003c/script>\\u003cb>{{DATA}}") != std::string::npos);
    CHECK(html.find("<h1>{{DATA}} ?</h1>") != std::string::npos);
    const nlohmann::json j = nlohmann::json::parse(slurp(out / "episode.json"));
    CHECK(j.at("gammas")[0].at("name") == "</script><b>{{DATA}}");
  }

  SECTION("episode.json has the outcome, every frame and one state per tick per controller") {
    const nlohmann::json j = nlohmann::json::parse(slurp(out / "episode.json"));
    CHECK(j.at("seed").get<uint64_t>() == 11);
    CHECK(j.at("success").get<bool>() == ep.success);
    CHECK(j.at("reward").get<double>() == ep.reward);
    CHECK(j.at("ticks").get<int>() == ep.ticks);
    CHECK(j.at("sim_seconds").get<double>() == Approx(ep.sim_seconds));
    REQUIRE(j.at("frames").size() == ep.frames.size());
    for (size_t i = 0; i < ep.frames.size(); ++i) {
      const auto& f = j.at("frames")[i];
      CHECK(f.at("time").get<double>() == Approx(ep.frames[i].time));
      CHECK(f.at("base").at("x").get<double>() == Approx(ep.frames[i].base.x));
      CHECK(f.at("base").at("theta").get<double>() == Approx(ep.frames[i].base.theta));
    }
    REQUIRE(j.at("gammas").size() == 2);
    CHECK(j.at("gammas")[0].at("name") == "search");
    CHECK(j.at("gammas")[1].at("name") == "phi0");
    const std::set<std::string> names = {"NOREF", "!CONV", "CONV"};
    for (size_t c = 0; c < 2; ++c) {
      const auto& states = j.at("gammas")[c].at("states");
      REQUIRE(states.size() == size_t(ep.ticks));
      for (size_t t = 0; t < states.size(); ++t) {
        CHECK(names.count(states[t].get<std::string>()) == 1);
        CHECK(states[t].get<std::string>() == gamma_name(ep.gammas[c].states[t]));
      }
    }
  }

  SECTION("episode.json has what the viewer draws: shapes, arms, eyes, images, touch, decisions") {
    const nlohmann::json j = nlohmann::json::parse(slurp(out / "episode.json"));
    const auto& world = j.at("world");
    CHECK(world.at("arena").at("xmax").get<double>() == e.spec.arena.xmax);
    REQUIRE(world.at("objects").size() == e.spec.objects.size());
    CHECK(world.at("objects")[0].at("shape").at("disks").size() +
              world.at("objects")[0].at("shape").at("polygons").size() > 0);
    CHECK(world.at("robot").at("base_radius").get<double>() == Approx(e.spec.body.base_radius));
    for (size_t i = 0; i < ep.frames.size(); ++i) {
      const auto& f = j.at("frames")[i];
      const Frame& fr = ep.frames[i];
      CHECK(f.at("arms")[1][2][0].get<double>() == Approx(fr.arms[1].hand.x()).margin(1e-4));
      CHECK(f.at("eyes")[0][1].get<double>() == Approx(fr.eyes[0].y()).margin(1e-4));
      CHECK(f.at("eye_heading")[1].get<double>() == Approx(fr.eye_heading[1]));
      REQUIRE(f.at("images").size() == 2);
      const std::string left = f.at("images")[0];
      REQUIRE(left.size() == 6 * size_t(e.spec.eyes.pixels));
      const Colour c = fr.senses.image[0].colour[5];
      char hex[8];
      std::snprintf(hex, sizeof hex, "%02x%02x%02x", c.r, c.g, c.b);
      CHECK(left.substr(5 * 6, 6) == hex);
      REQUIRE(f.at("touch").size() == size_t(kTactileCount));
      CHECK(f.at("touch")[0].at("force").get<double>() == Approx(fr.senses.touch[0].force));
    }
    // Phi6 searches first, then tracks: two decisions, the second when search has converged.
    const auto& d = j.at("decisions");
    REQUIRE(ep.decisions.size() == d.size());
    REQUIRE(d.size() >= 2);
    CHECK(d[0].at("tick") == 1);
    CHECK(d[0].at("path") == nlohmann::json({"Phi6", "search"}));
    CHECK(d[1].at("path") == nlohmann::json({"Phi6", "phi0"}));
    const int switched = d[1].at("tick");
    REQUIRE(switched >= 2);
    CHECK(ep.gammas[0].states[size_t(switched - 2)] == Gamma::kConv);  // search converged just before
    CHECK(d[1].at("time").get<double>() == Approx((switched - 1) * j.at("tick_seconds").get<double>()));
  }

  // Found by a probe: Ctrl-C during a rendering left the first frames of the new episode among the
  // old one's files, and a half-written frame's temporary file. The files are staged and moved in
  // once all are whole; a stop before that leaves the folder as it was, and what a killed rendering
  // left (its staging folder, a temporary file) goes at the next.
  SECTION("a rendering stopped part-way leaves the folder as it was") {
    auto contents = [&] {
      std::map<std::string, std::string> files;
      for (const auto& e : fs::directory_iterator(out)) files[e.path().filename().string()] = slurp(e.path());
      return files;
    };
    const auto before = contents();
    Phi6Episode shorter;
    const EpisodeResult ep2 = shorter.run(0.5);
    catch_interrupts("");
    std::raise(SIGINT);
    CHECK_THROWS_AS(render_episode(shorter.spec, ep2, out.string(), o), Interrupted);
    clear_interrupt();
    CHECK(contents() == before);
    fs::create_directory(out / ".staged99999-0-1.tmp");
    std::ofstream(out / ".staged99999-0-1.tmp" / "frame_0000.png") << "half";
    std::ofstream(out / ".frame_0003.png.tmp99999-3-7") << "half";
    std::ofstream(out / ".notes") << "the user's";
    render_episode(shorter.spec, ep2, out.string(), o);
    CHECK(!fs::exists(out / ".staged99999-0-1.tmp"));
    CHECK(!fs::exists(out / ".frame_0003.png.tmp99999-3-7"));
    CHECK(fs::exists(out / ".notes"));
    CHECK(frame_files(out).size() == ep2.frames.size());
  }

  SECTION("re-rendering a shorter episode removes the old frames beyond it") {
    Phi6Episode shorter;
    const EpisodeResult ep2 = shorter.run(0.5);
    REQUIRE(ep2.frames.size() < ep.frames.size());
    render_episode(shorter.spec, ep2, out.string(), o);
    const std::vector<std::string> files = frame_files(out);
    CHECK(files.size() == ep2.frames.size());
    CHECK(files.back() == "frame_" + std::string(4 - std::to_string(ep2.frames.size() - 1).size(), '0') +
                              std::to_string(ep2.frames.size() - 1) + ".png");
    const nlohmann::json j = nlohmann::json::parse(slurp(out / "episode.json"));
    CHECK(j.at("frames").size() == ep2.frames.size());
  }
}

TEST_CASE("episode.json marks the cycle a timed-out episode ended in") {
  Phi6Episode e;
  EpisodeResult ep = e.run(4.0);
  REQUIRE(ep.ticks > 40);
  TempDir dir;
  // Rewritten as a livelock: from tick 11 on, "a" runs in states (CONV, !CONV) and "b" in
  // (!CONV, CONV), every 5 ticks, until the time-out.
  ep.success = false;
  ep.decisions = {{1, {"start"}}};
  for (auto& g : ep.gammas) g.states.assign(size_t(ep.ticks), Gamma::kNoRef);
  for (int tick = 11, k = 0; tick + 5 <= ep.ticks; tick += 5, ++k) {
    ep.decisions.push_back({tick, {"skill", k % 2 ? "b" : "a"}});
    for (int t = tick - 2; t < tick + 3; ++t) {  // the states seen at the decision, and after it
      ep.gammas[0].states[size_t(t)] = k % 2 ? Gamma::kNotConv : Gamma::kConv;
      ep.gammas[1].states[size_t(t)] = k % 2 ? Gamma::kConv : Gamma::kNotConv;
    }
  }
  if (ep.decisions.size() % 2 == 0) ep.decisions.pop_back();  // whole turns: a, b, ..., a, b
  render_episode(e.spec, ep, dir.path.string(), small_options());
  const nlohmann::json cycle = nlohmann::json::parse(slurp(dir.path / "episode.json"))["cycle"];
  REQUIRE(cycle.is_object());
  CHECK(cycle["from_tick"] == 11);
  CHECK(cycle["first_decision"] == 1);
  CHECK(cycle["period"] == 2);
  CHECK(cycle["turns"].get<int>() == int(ep.decisions.size() - 1) / 2);
  CHECK(cycle["actions"].size() == 2);
  CHECK(slurp(dir.path / "index.html").find("E.cycle") != std::string::npos);  // the page draws it

  // An episode that reached its goal, or never repeats itself, has none.
  ep.success = true;
  render_episode(e.spec, ep, dir.path.string(), small_options());
  CHECK(nlohmann::json::parse(slurp(dir.path / "episode.json"))["cycle"].is_null());
}

TEST_CASE("a summary is one PNG: evenly spaced frames over the timeline") {
  Phi6Episode e;
  const EpisodeResult ep = e.run(2.0);
  TempDir dir;
  const AnimationOptions o = small_options();
  const fs::path path = dir.path / "summary.png";
  render_episode_summary(e.spec, ep, path.string(), o, 3);
  const auto [w, h] = png_size(path);
  CHECK(w == 3 * 320);
  CHECK(h > picture_size(e.spec, o.frame).height);

  // More panels than frames: one panel per frame.
  EpisodeResult two = ep;
  two.frames.resize(2);
  two.frame_ticks.resize(2);
  render_episode_summary(e.spec, two, path.string(), o, 6);
  CHECK(png_size(path).first == 2 * 320);

  CHECK_THROWS_AS(render_episode_summary(e.spec, ep, (dir.path / "s.svg").string(), o), Error);
  CHECK_THROWS_AS(render_episode_summary(e.spec, ep, path.string(), o, 0), Error);
}

TEST_CASE("bad folders and episodes are clear errors") {
  Phi6Episode e;
  const EpisodeResult ep = e.run(0.5);
  TempDir dir;
  const AnimationOptions o = small_options();

  SECTION("a folder that cannot be made") {
    const fs::path file = dir.path / "plain_file";
    std::ofstream(file) << "not a folder";
    // Below a regular file nothing can be created, whoever runs the test (root included).
    CHECK_THROWS_WITH(render_episode(e.spec, ep, (file / "anim").string(), o),
                      Catch::Contains("cannot create folder"));
    CHECK_THROWS_WITH(render_episode(e.spec, ep, file.string(), o),
                      Catch::Contains("not a folder"));
    CHECK_THROWS_AS(render_episode_summary(e.spec, ep, (file / "s.png").string(), o), Error);
  }

  SECTION("an episode without frames, or from another world, touches nothing") {
    EpisodeResult empty = ep;
    empty.frames.clear();
    empty.frame_ticks.clear();
    const fs::path out = dir.path / "never";
    CHECK_THROWS_WITH(render_episode(e.spec, empty, out.string(), o),
                      Catch::Contains("no frames"));
    const WorldSpec no_ball = test::open_world(false);
    CHECK_THROWS_WITH(render_episode(no_ball, ep, out.string(), o),
                      Catch::Contains("object poses"));
    CHECK(!fs::exists(out));
  }

  SECTION("playback speed must be positive") {
    AnimationOptions bad = o;
    bad.fps = 0;
    CHECK_THROWS_AS(render_episode(e.spec, ep, (dir.path / "a").string(), bad), Error);
  }
}

TEST_CASE("the timeline shows each watched controller's row once") {
  using G = Gamma;
  const std::vector<Gamma> a{G::kNotConv, G::kConv}, b{G::kNoRef, G::kConv};
  // Psi's actions, then what is inside them: two copies of "phi4 <| phi5" in two skills that ran
  // alike, a learned skill and the binding running it, and a composite whose copies differed.
  const std::vector<GammaTrace> watched{{"Phi_STG", a}, {"transport", b},     {"Phi_SG", a},
                                        {"phi4 <| phi5", b}, {"phi4 <| phi5", b}, {"Phi_SG", a},
                                        {"phi1 <| phi2", a}, {"phi1 <| phi2", b}, {"phi4", a}};
  std::vector<std::string> names;
  for (const GammaTrace& t : distinct_traces(watched, 12)) names.push_back(t.name);
  CHECK(names == std::vector<std::string>{"Phi_STG", "transport", "Phi_SG", "phi4 <| phi5", "phi1 <| phi2",
                                          "phi1 <| phi2 (2)", "phi4"});
  // The limit counts the rows kept: the repeats left room for the rows after them.
  names.clear();
  for (const GammaTrace& t : distinct_traces(watched, 5)) names.push_back(t.name);
  CHECK(names == std::vector<std::string>{"Phi_STG", "transport", "Phi_SG", "phi4 <| phi5", "phi1 <| phi2"});
  CHECK(distinct_traces(watched, 0).empty());
}
