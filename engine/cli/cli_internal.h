// cli_internal.h: helpers the commands share.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "cli/commands.h"
#include "core/error.h"
#include "script/sandbox/lua_sandbox.h"
#include "script/scenario/scenario.h"
#include "script/skills/skill_script.h"

namespace roger {

struct BatchScript;

// For roger run: of `sets` (its --set, added to every run's parameters), those a run's scenario
// never reads in any world roger check builds of it, a message each ("--set clutter changes no
// world of runs R1 and R2: ..."), so a sweep over an unwired parameter is seen before it trains.
std::vector<std::string> unread_sets_in_batch(const BatchScript& b,
                                              const std::vector<std::pair<std::string, std::string>>& sets);

// One line for a file the machine could not write or read (core/error.h): the message, what went
// wrong in plain words (a full disk, no permission, a script removed) and what to do. `resumes`:
// the command resumes where it stopped when run again (roger run, roger report).
std::string file_error_line(const FileError& e, bool resumes = true);

// A required option left out that the parser could not require, since what it takes is read from
// the script (--stage, --context of roger train): exit status 2, as the parser's refusals.
struct CommandLineError : Error {
  using Error::Error;
};

// "roger: error: MESSAGE", or, when the message names its command ("roger propose: --budget ..."),
// "roger propose: error: --budget ...": not "roger: error: roger propose: ...".
std::string error_line(const std::string& message);

// "eye_pixels = 32, overridden by --set eye_pixels=128": `params`, each one a --set of `sets`
// replaced with another value marked so, and each one of a saved policy's trial sets otherwise
// (`trial`, set here too) marked as that (learn_commands.cpp).
std::string params_marking_sets(const std::vector<std::pair<std::string, std::string>>& params,
                                const std::vector<std::string>& sets,
                                const std::vector<std::pair<std::string, std::string>>& trial = {});

// file_error_line for roger report: it writes only into its folder (a folder it may not write
// into needs another place, or a copy), and it resumes nothing.
std::string report_file_error_line(const FileError& e);

// stimulus_unseen_note of `worlds` worlds of `scenario` from `first_seed`, with `params` set, and
// those of `where_declared` the scenario declares (a --set for other stages): "" when the worlds
// have the colour their eyes look for, or cannot be made here (their own error is said elsewhere).
std::string stimulus_unseen_in(const std::string& scenario, const std::vector<std::pair<std::string, std::string>>& params,
                               const SandboxLimits& limits, uint64_t first_seed, int worlds,
                               const std::vector<std::pair<std::string, std::string>>& where_declared = {});

// The first goal region of `model`'s world the navigator (phi1 {goal = "region"}) cannot reach, said,
// or "": none of its static grid's free cells lies within the region's radius less phi1's margin
// of its centre (check.cpp).
struct WorldModel;
std::string goal_out_of_reach(const WorldModel& model);

// For a command given a module (a script of no kind's keys that another requires, or one in a lib/
// folder) where it takes a script of kind `wanted`: why it cannot run it, naming the script that
// requires it ("scripts/noise_kinds_levels.lua is a module, required as ... by scripts/noise_kinds.lua:
// run that batch script"); "" for any other script. `path` is resolved, `given` as typed.
std::string module_given(const std::string& given, const std::string& path, const std::string& wanted);

// The sandbox limits --lua-instructions and --lua-memory set over the defaults.
SandboxLimits sandbox_limits(const LuaLimitArgs& lua);

// Applies `--set key=value` options to a scenario.
void apply_sets(Scenario& scenario, const std::vector<std::string>& sets);

// Items as a sentence lists them: "a", "a and b", "a, b and c".
std::string listed_with_and(const std::vector<std::string>& items);

// Says that the --set of `unread` changed no world: generate never read them in `scenario` (a path
// or name). Empty when `unread` is.
std::string unread_sets_note(const std::vector<std::string>& unread, const std::string& scenario);

// The same as a note line of roger train's and roger eval's summary, and after it noise_sets_note's
// for `params` (the parameters as used) and `sets` (the command's --set). Nothing when neither says
// anything.
void print_unread_sets(const std::vector<std::string>& unread, const std::string& scenario,
                       const std::vector<std::pair<std::string, std::string>>& params,
                       const std::vector<std::string>& sets);

// lib/body's noise parameters that `sets` (--set key=value options) gave and that changed nothing
// with the others in `params` (the parameters as used): a drift's tau without a drift, a
// noise_scale with every level 0 (found by a probe: both ran as if unset, without a word); and a
// dropout that noise_scale carries past 1, held at 1 (every reading lost). "" when none.
std::string noise_sets_note(const std::vector<std::pair<std::string, std::string>>& params,
                             const std::vector<std::string>& sets);

// A scenario's parameters and their values, as text.
std::vector<std::pair<std::string, std::string>> scenario_param_values(const Scenario& scenario);

// Splits key=value options into pairs, each key once (a key repeated with another value is an
// error; with the same value, kept once); `option` names the option in the errors.
std::vector<std::pair<std::string, std::string>> split_sets(const std::vector<std::string>& sets, const char* option);

// A saved policy's first world seed from --seed: a seed of 2^63 or more would read as none given
// (its signed form is negative, the held-out seeds') and is refused, naming `command`.
int64_t saved_policy_first_seed(const char* command, uint64_t seed);

// Whether `script` is a curriculum, so that --policy names a policy.json written by roger train;
// throws roger::Error when it is and `policy` is not such a file name.
bool policy_is_saved_file(const std::string& script, const std::string& policy);

// Refuses an existing --out folder holding files `command` does not write (`own` says which it
// does): its output would go among them, and files of the same names would be replaced (a
// results folder's index.html by roger render's). Subfolders and hidden files are left alone.
void refuse_foreign_files(const std::string& out, const std::string& command,
                          const std::function<bool(const std::string&)>& own);

// The note on a saved policy's trial parameters that another scenario (--scenario) left at its
// own values: "the trial trained with forearm = 0.6; scenario cluttered plays its own value of
// forearm here (--set forearm=0.6 plays the trial's)". The first `declared` of `left` are the
// scenario's parameters; of the others it says the scenario has none of that name.
std::string trial_params_left_note(const std::vector<std::pair<std::string, std::string>>& left, size_t declared,
                                   const std::string& scenario);

}  // namespace roger
