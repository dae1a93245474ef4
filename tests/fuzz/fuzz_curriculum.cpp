// fuzz_curriculum: arbitrary Lua source loaded as a curriculum or skill script (Curriculum::load),
// then called as a trainer calls it between and within episodes: each stage's teacher (built in or
// a Lua function) draws tasks and hears what came of them, and its Lua absorbing and reward
// functions see states of each context. The sandbox, the control-basis bindings
// (engine/script/lua_control*.cpp), the curriculum's stages and callbacks
// (engine/script/curriculum*.cpp), the teachers (engine/teach) and the converters must turn every
// mistake, at load or at a call, into a roger::Error.
#include "fuzz_lua_script.h"
#include "script/curriculum/curriculum.h"

namespace {

// A teacher's round of a trial, as batch/trainer.cpp's TrialTeacher makes it: the test sets, then
// tasks drawn and outcomes told, alternately successes and failures.
void teach(roger::Curriculum& curriculum, const roger::CurriculumStage& stage) {
  const roger::TaskSpace& space = stage.tasks;
  std::unique_ptr<roger::Teacher> teacher = curriculum.make_teacher(stage, space, 7);
  if (!teacher) return;
  stage.test_tasks(space, 4);
  teacher->test_params();
  for (int episode = 0; episode < 8; ++episode) {
    const roger::TaskPick pick = teacher->next();
    space.params(pick.task);
    space.to_json(pick.task);
    roger::TaskOutcome outcome;
    outcome.task = pick.task;
    outcome.world_seed = uint64_t(episode);
    outcome.success = episode % 2 == 1;
    outcome.reward = outcome.success ? 100.0 : -100.0;
    outcome.sim_s = 1.0 + episode;
    outcome.td_error = 0.25 * episode;
    teacher->record(outcome);
    teacher->state();
  }
}

// A context's Lua callbacks at three states: every action NOREF, every one !CONV, and the last
// CONV with the others NOREF; the reward for each event.
void call_back(roger::Curriculum& curriculum, const roger::CurriculumStage& stage,
               const roger::CurriculumContext& context) {
  using roger::Gamma;
  const size_t n = context.actions.size();
  if (n == 0) return;  // a context without actions is refused at load
  std::vector<std::vector<Gamma>> states = {std::vector<Gamma>(n, Gamma::kNoRef),
                                            std::vector<Gamma>(n, Gamma::kNotConv)};
  states.push_back(states.front());
  states.back().back() = Gamma::kConv;
  for (const std::vector<Gamma>& state : states) {
    curriculum.begin_episode();
    if (stage.absorbing_lua) curriculum.call_absorbing(stage, context, state, 1.0);
    if (stage.reward_lua)
      for (const char* event : {"decision", "absorbing", "timeout"})
        curriculum.call_reward(stage, context, state, int(n) - 1, event, 2.0);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = roger::fuzz::lua_file("curriculum.lua", data, size);
  roger::fuzz::expect_success_or_roger_error([&] {
    roger::Curriculum curriculum = roger::Curriculum::load(path, roger::fuzz::fuzz_limits());
    for (const auto& stage : curriculum.stages()) curriculum.producer(stage.name);
    // Each stage apart: a fault in one should not hide what the next would do.
    for (const auto& stage : curriculum.stages()) {
      roger::fuzz::expect_success_or_roger_error([&] { teach(curriculum, stage); });
      for (const auto& context : stage.contexts)
        roger::fuzz::expect_success_or_roger_error([&] { call_back(curriculum, stage, context); });
    }
  });
  return 0;
}
