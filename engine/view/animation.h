// animation.h: an episode as something to watch, for researchers debugging a controller. A folder
// holds episode.json (the world's shapes and, per frame, poses, arms, eyes, both images and touch;
// every watched controller's state per tick; the decisions of the action's skills), index.html, a
// self-contained viewer that draws the episode from those numbers on a canvas (no network, no
// server: open the file; docs/browser.md), and one PNG per recorded frame (the world picture of
// render.h over a timeline of the controllers' states) for whoever wants pictures. A single
// summary PNG (a strip of frames over the same timeline) fits in a report or an issue.
#pragma once

#include <string>

#include "learn/episode.h"
#include "view/render.h"
#include "core/spec.h"

namespace roger {

// How an episode is drawn and replayed.
struct AnimationOptions {
  RenderOptions frame;       // each frame's world picture; its title defaults to `title`
  double fps = 10.0;         // frames per simulated second, for episode.json (the viewer plays in simulated time)
  std::string title;         // the page's heading and the pictures' title
  bool show_timeline = true; // the controller-state timeline under each frame
  bool dim_future = true;    // in a frame's timeline, fade what has not happened yet
};

// Writes the episode into folder (created if missing): frame_0000.png, ... one per recorded frame,
// episode.json and index.html (the viewer, with episode.json's data inside), staged and moved in
// together once all are whole. Frames of an earlier, longer rendering beyond the new count are
// removed, so a folder never mixes episodes. Throws roger::Error for an episode without frames,
// frames that do not match spec, bad options, or a folder that cannot be written, and Interrupted
// when a stop was requested (catch_interrupts) before the files moved: the folder is as it was.
void render_episode(const WorldSpec& spec, const EpisodeResult& episode, const std::string& folder,
                    const AnimationOptions& options = {});

// Whether render_episode writes a file of this name into its folder: a frame (frame_0000.png, ...),
// episode.json or index.html. A folder holding others is not its own (roger render refuses it).
bool render_episode_writes(const std::string& file_name);

// Writes one PNG summarising the episode to path: `panels` evenly spaced frames side by side (the
// first and the last included; one panel shows the last frame) over the timeline, with numbered
// markers tying each panel to its moment. Same errors as render_episode, plus panels < 1 or a path
// that is not .png.
void render_episode_summary(const WorldSpec& spec, const EpisodeResult& episode,
                            const std::string& path, const AnimationOptions& options = {},
                            int panels = 4);

}  // namespace roger
