// Module python: the extension `roger._roger` (pybind11) under the Python package `roger`
// (engine/python/roger/__init__.py, which gives it Gymnasium's shape). Binds the stage environment
// and its batched form (batch/environment.h) and saved policies (learn/learning.h); every call
// that runs the engine releases the GIL. The top layer: nothing in the engine includes it.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <optional>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

#include <unistd.h>

#include "batch/environment.h"
#include "batch/trainer.h"
#include "core/error.h"
#include "core/json_input.h"
#include "core/rng.h"
#include "core/text.h"
#include "learn/learning.h"
#include "script/sandbox/lua_sandbox.h"
#include "script/scenario/scenario.h"
#include "view/render.h"

namespace py = pybind11;
using namespace roger;

namespace {

using Sets = std::vector<std::pair<std::string, std::string>>;

// Whether the interpreter has begun to finalize (it reads an atomic: no GIL needed).
bool interpreter_finalizing() {
#if PY_VERSION_HEX >= 0x030D0000
  return Py_IsFinalizing();
#else
  return _Py_IsFinalizing();
#endif
}

// Runs f() with the GIL released; returns what it returns, or rethrows what it threw once the GIL
// is held again. The GIL is taken back by a plain call, not by a guard's destructor. Found by a
// probe: a daemon thread inside step() when the interpreter exits asks for the GIL back, and
// CPython (3.11) ends it with pthread_exit there; from pybind11's gil_scoped_release destructor,
// which is noexcept, that unwinding called std::terminate and the whole process aborted (exit code
// 134, also after Ctrl-C). A thread that finds the interpreter finalizing sleeps until the process
// ends instead, as CPython 3.14 makes such threads do itself; one that it catches a moment later
// unwinds from here, which is allowed.
template <class F>
auto without_gil(F&& f) -> decltype(f()) {
  using Result = decltype(f());
  std::optional<std::conditional_t<std::is_void_v<Result>, bool, Result>> result;
  std::exception_ptr error;
  PyThreadState* const saved = PyEval_SaveThread();
  try {
    if constexpr (std::is_void_v<Result>) {
      f();
      result.emplace(true);
    } else {
      result.emplace(f());
    }
  } catch (...) {
    error = std::current_exception();
  }
  while (interpreter_finalizing()) std::this_thread::sleep_for(std::chrono::hours(1));
  PyEval_RestoreThread(saved);
  if (error) std::rethrow_exception(error);
  if constexpr (!std::is_void_v<Result>) return std::move(*result);
}

// Text from Python for the engine: bytes as they are; a str as UTF-8, with the bytes of a file name
// that are not (os.fsdecode's surrogates) given back as they were, as the command line passes
// them (found by a probe: such a name or value raised a binding's RuntimeError).
std::string native_text(const py::handle& v) {
  if (py::isinstance<py::bytes>(v)) return v.cast<std::string>();
  const py::str text(v);
  PyObject* bytes = PyUnicode_AsEncodedString(text.ptr(), "utf-8", "surrogateescape");
  if (!bytes) throw py::error_already_set();
  std::string out(PyBytes_AS_STRING(bytes), size_t(PyBytes_GET_SIZE(bytes)));
  Py_DECREF(bytes);
  return out;
}

// Engine text for Python: UTF-8, with bytes that are not (a file name's) as os.fsdecode gives
// them, so that the name goes back to the engine (native_text) as it came.
py::str python_text(const std::string& s) {
  PyObject* text = PyUnicode_DecodeUTF8(s.data(), py::ssize_t(s.size()), "surrogateescape");
  if (!text) throw py::error_already_set();
  return py::reinterpret_steal<py::str>(text);
}

// A Python value as the text a scenario parameter is given as (--set key=value).
std::string param_text(const py::handle& v) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  return native_text(v);
}

EnvironmentOptions make_options(const std::string& curriculum, const std::string& stage, const std::string& context,
                                const std::string& scenario, const py::dict& params, const py::dict& skills,
                                bool per_tick, const std::string& tasks = "", const std::string& teacher = "",
                                const std::string& teacher_file = "", const std::string& embedded_skills = "",
                                bool teaching = true) {
  EnvironmentOptions o;
  o.teaching = teaching;
  // A policy file's extra.skills (make(..., policy=...)): the learned skills `roger eval` binds.
  if (!embedded_skills.empty()) o.embedded_skills = parse_json(embedded_skills);
  // The package writes a tasks dict as Lua text; a teacher comes as Lua text or a file.
  if (!tasks.empty()) o.tasks = {tasks, "make(tasks=...)", false};
  if (!teacher.empty()) o.teacher = {teacher, "make(teacher=...)", false};
  if (!teacher_file.empty()) o.teacher = {"", teacher_file, true};
  o.curriculum = curriculum;
  o.stage = stage;
  o.context = context;
  o.scenario = scenario;
  for (const auto& [k, v] : params) o.sets.push_back({native_text(k), param_text(v)});
  for (const auto& [k, v] : skills) o.skill_files[native_text(k)] = native_text(v);
  o.per_tick = per_tick;
  return o;
}

// A skill the context does not use would be ignored, a misspelt name with it: refused, naming
// what the context uses, as `roger train` refuses such a --skill (docs/cli.md).
void check_skill_names(const EnvironmentOptions& o, const std::string& where) {
  if (o.skill_files.empty()) return;
  const Curriculum cur = Curriculum::load(o.curriculum, o.limits);
  const CurriculumStage& stage = cur.stage(o.stage);
  for (const auto& [name, file] : o.skill_files)
    if (const std::string problem = cur.unused_skill_problem(stage, o.context, name); !problem.empty())
      throw Error(where + ": skills={'" + name + "': '" + file + "'}: " + cur.path() + ": " + problem);
}

// Makes an environment (or a batch) of `o` with `make`, after checking its skills' names. The
// engine words a mistake of a stage's ("stage 'SG' has no context 'DC9'; its contexts: ...")
// without the curriculum's file, which the curriculum's own mistakes name: such a message is
// given the file in front.
template <class Make>
auto make_environment(const EnvironmentOptions& o, const std::string& where, Make make) {
  try {
    check_skill_names(o, where);
    return make();
  } catch (const PlacementError& e) {
    throw with_text(e, where + ": " + e.what());  // which call could not build the world
  } catch (const ScriptError&) {
    throw;  // file:line already
  } catch (const Error& e) {
    const std::string message = e.what();
    if (message.rfind("stage '", 0) != 0) throw;
    const std::exception_ptr original = std::current_exception();
    std::string path;
    try {
      path = Curriculum::load(o.curriculum, o.limits).path();
    } catch (const std::exception&) {
      std::rethrow_exception(original);  // as it was, not a copy cut down to Error
    }
    throw Error(path + ": " + message);
  }
}

// A given scenario (make(..., scenario=...)) that cannot play the stage's own task space (less
// what params fix) refused at make, where the space is offered, naming the parameter, the scenario
// and what it has: else the environment is made and its first reset fails. make's own tasks were
// checked against the scenario given when they were read. make_vec offers no task space (its
// worlds have the stage's own parameters), so it plays any scenario.
void check_scenario_takes_tasks(const EnvironmentOptions& o, const StageEnvironment& e) {
  if (o.scenario.empty() || !o.tasks.empty() || e.task_space().empty()) return;
  try {
    e.check_played_in(o.scenario);
  } catch (const ScriptError& x) {
    throw ScriptError("make: scenario='" + o.scenario + "' cannot play the task space of stage '" + e.info().stage +
                          "': " + x.message +
                          "; give make(..., tasks={...}) over parameters it has, or leave out scenario= to play the "
                          "stage's own",
                      x.file, x.line, x.traceback);
  }
}

py::array_t<uint8_t> state_array(const std::vector<Gamma>& g) {
  py::array_t<uint8_t> a(py::ssize_t(g.size()));
  for (size_t i = 0; i < g.size(); ++i) a.mutable_at(py::ssize_t(i)) = uint8_t(g[i]);
  return a;
}

// A scenario parameter as its declared type: a number as a float, an integer as an int, a
// boolean as a bool, text (a choice, a list) as str. The engine keeps the text --set takes; as a
// str in Python, "0.25" * 2 is "0.250.25", without a word.
py::object param_object(const std::string& text, const std::map<std::string, ParamType>& types,
                        const std::string& key) {
  const auto t = types.find(key);
  if (t == types.end()) return py::str(text);
  switch (t->second) {
    case ParamType::kNumber: return py::float_(std::stod(text));
    case ParamType::kInteger: return py::int_(std::stoll(text));
    case ParamType::kBoolean: return py::bool_(text == "true");
    case ParamType::kString: break;
  }
  return py::str(text);
}

py::dict info_dict(const EnvironmentInfo& i) {
  py::dict d;
  d["curriculum"] = python_text(i.curriculum);
  d["stage"] = python_text(i.stage);
  d["context"] = python_text(i.context);
  d["scenario"] = python_text(i.scenario);
  d["actions"] = i.actions;
  py::dict params;
  for (const auto& [k, v] : i.params) params[py::str(k)] = param_object(v, i.param_types, k);
  d["params"] = params;
  d["time_limit"] = i.time_limit;
  d["time_per_object"] = i.time_per_object;
  d["tick_seconds"] = i.tick_seconds;
  d["eye_pixels"] = i.eye_pixels;
  d["joint_low"] = std::vector<double>(i.joint_low.begin(), i.joint_low.end());
  d["joint_high"] = std::vector<double>(i.joint_high.begin(), i.joint_high.end());
  d["budget_episodes"] = i.budget_episodes;
  d["learner"] = py::dict(py::arg("alpha") = i.learner.alpha, py::arg("discount") = i.learner.discount,
                          py::arg("epsilon_start") = i.learner.epsilon_start,
                          py::arg("epsilon_end") = i.learner.epsilon_end, py::arg("initial_q") = i.learner.initial_q,
                          py::arg("referenced_only") = i.learner.referenced_only,
                          py::arg("unconverged_first") = i.learner.unconverged_first,
                          py::arg("discount_seconds") = i.discount_seconds);
  d["checkpoints"] = py::dict(py::arg("every") = i.checkpoint_every, py::arg("episodes") = i.checkpoint_episodes,
                              py::arg("threshold") = i.threshold, py::arg("seeds") = i.checkpoint_seeds,
                              py::arg("stop_after") = i.stop_after, py::arg("settle") = i.settle,
                              py::arg("final") = i.final_episodes);
  return d;
}

// The world of the environment's episode. Before its first reset an environment has none (the
// agent's world holds no model until an episode builds one): `what` is refused with a RogerError
// rather than read through a null model.
const World& world_of(const StageEnvironment& e, const std::string& what) {
  if (!e.begun()) throw Error(what + ": no world yet (call reset first)");
  return e.agent().world();
}

// The raw senses of the tick that just ran: what a per-tick learner observes.
py::dict senses_dict(const StageEnvironment& e) {
  const World& world = world_of(e, "senses");
  const Senses& s = world.senses();
  const int pixels = world.camera().pixels;  // the body's eyes decide the shapes
  py::array_t<uint8_t> images({2, pixels, 3});
  py::array_t<float> stimulus({2, pixels});
  for (int e = 0; e < 2; ++e)
    for (int u = 0; u < pixels; ++u) {
      const Colour& c = s.image[size_t(e)].colour[size_t(u)];
      images.mutable_at(e, u, 0) = c.r;
      images.mutable_at(e, u, 1) = c.g;
      images.mutable_at(e, u, 2) = c.b;
      stimulus.mutable_at(e, u) = s.image[size_t(e)].stimulus[size_t(u)];
    }
  py::array_t<float> touch({int(kTactileCount), 5});
  for (int t = 0; t < kTactileCount; ++t) {
    const Touch& k = s.touch[size_t(t)];
    const float row[5] = {k.contact ? 1.0f : 0.0f, float(k.force), float(k.friction), float(k.normal.x()),
                          float(k.normal.y())};
    for (int j = 0; j < 5; ++j) touch.mutable_at(t, j) = row[j];
  }
  // float32 as every other float of the observation; joints within the body's ranges (an encoder
  // reads within its joint's range), so that the observation is always in its space.
  std::array<double, kDofCount> low, high;
  observed_joint_ranges(world.spec().body, low, high);
  py::array_t<float> q(kDofCount), qdot(kDofCount);
  for (int j = 0; j < kDofCount; ++j) {
    q.mutable_at(j) = float(std::clamp(s.q[j], low[size_t(j)], high[size_t(j)]));
    qdot.mutable_at(j) = float(s.qdot[j]);
  }
  py::dict d;
  d["images"] = images;
  d["stimulus"] = stimulus;
  d["touch"] = touch;
  d["joints"] = q;
  d["joint_velocities"] = qdot;
  return d;
}

// The picture `roger render --width width` draws of the environment's world now, H x W x 3 uint8.
py::array_t<uint8_t> render_array(const StageEnvironment& e, int width, const std::string& what = "render") {
  const World& world = world_of(e, what);
  RenderOptions options;
  options.width_px = width;
  const RgbPicture p = without_gil([&] {
    const EngineFloatMode mode;  // as `roger render` draws, on an engine thread
    return render_rgb(world.spec(), world.frame(), options);
  });
  py::array_t<uint8_t> a({py::ssize_t(p.height), py::ssize_t(p.width), py::ssize_t(3)});
  std::copy(p.pixels.begin(), p.pixels.end(), a.mutable_data());
  return a;
}

// "1 value", "2 values": a count in words that agree with it (found by a probe: "the observation
// has 1 values").
std::string counted(py::ssize_t n, const std::string& what) {
  return std::to_string(n) + " " + what + (n == 1 ? "" : "s");
}

// A saved policy.json: the greedy action of a state, as `roger eval` takes it.
class Policy {
 public:
  explicit Policy(const std::string& path) : path_(path), q_(QTable::load(path, {}, &meta_)) {}
  int act(py::array_t<int64_t, py::array::c_style | py::array::forcecast> obs) const {
    if (obs.ndim() != 1) {
      std::string shape;
      for (py::ssize_t d = 0; d < obs.ndim(); ++d) shape += (d ? ", " : "") + std::to_string(obs.shape(d));
      const std::string expected =
          "act: takes one observation, a vector of " + counted(q_.actions(), "value") + " (one per action)";
      if (obs.ndim() == 0) throw Error(expected + ", got a single number");
      throw Error(expected + ", not a batch: got a " + std::to_string(obs.ndim()) + "-D array of shape (" + shape +
                  "); for a batch of observations, act on each row: [policy.act(o) for o in obs]");
    }
    if (obs.shape(0) != q_.actions())
      throw Error(path_ + ": the policy has " + counted(q_.actions(), "action") + " but the observation has " +
                  counted(obs.size(), "value"));
    std::vector<Gamma> g(size_t(q_.actions()));
    for (int a = 0; a < q_.actions(); ++a) {
      const int64_t v = obs.at(a);
      if (v < 0 || v > 2)
        throw Error("observation[" + std::to_string(a) + "] (" + q_.action_names()[size_t(a)] + ") is " +
                    std::to_string(v) + ": a controller state is 0 (NOREF), 1 (!CONV) or 2 (CONV)");
      g[size_t(a)] = Gamma(v);
    }
    return q_.policy_action(gamma_state_index(g));
  }
  const QTable& table() const { return q_; }
  const PolicyMetadata& meta() const { return meta_; }
  // extra's field `key` (an object, or a string), or an empty one.
  nlohmann::json extra(const std::string& key, nlohmann::json empty) const {
    const nlohmann::json& e = meta_.extra;
    return e.is_object() && e.contains(key) && e[key].type() == empty.type() ? e[key] : empty;
  }
  // The trial's own scenario parameters, as `roger eval --policy` sets them (batch/trainer.h).
  std::vector<std::pair<std::string, std::string>> trial_params(const std::string& curriculum,
                                                                const std::string& scenario) const {
    return policy_trial_params(meta_, path_, curriculum, scenario, {}, SandboxLimits{});
  }
  // What `roger eval --policy` notes of a curriculum that is not the one the policy trained with.
  std::string curriculum_note(const std::string& curriculum) const {
    return policy_curriculum_note(meta_, curriculum, SandboxLimits{});
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  PolicyMetadata meta_;
  QTable q_;
};


// ---- tasks (docs/python.md, Tasks and teachers)

// The task space's axes in its order, for the package to build its Gymnasium Dict space.
py::list task_dims(const TaskSpace& space) {
  py::list out;
  for (const TaskDim& d : space.dims()) {
    const char* kind = d.kind == TaskDim::Kind::kInt ? "int" : d.kind == TaskDim::Kind::kReal ? "real" : "choice";
    out.append(py::dict(py::arg("name") = d.name, py::arg("kind") = kind, py::arg("low") = d.lo,
                        py::arg("high") = d.hi, py::arg("choices") = d.choices, py::arg("text") = d.text()));
  }
  return out;
}

// A task as a member of the package's space: an int axis's integer, a real one's number, a
// choice's index.
py::dict task_point_dict(const TaskSpace& space, const TaskPoint& t) {
  py::dict d;
  for (size_t i = 0; i < space.size(); ++i) {
    const TaskDim& dim = space.dims()[i];
    if (dim.kind == TaskDim::Kind::kReal) d[py::str(dim.name)] = t[i];
    else d[py::str(dim.name)] = int64_t(std::llround(t[i]));
  }
  return d;
}

// A task's scenario parameters with numbers as numbers: an int axis's as an int, a real axis's as
// a float, any other value (a choice's, a parameter a teacher sets beside the space) as the engine
// writes it in JSON (param_value_json: an integer, a number, else the text).
py::dict typed_params(const TaskSpace& space, const ParamList& params) {
  py::dict d;
  for (const auto& [key, text] : params) {
    const nlohmann::json v = param_value_json(text);
    const int i = space.index(key);
    const bool real = i >= 0 && space.dims()[size_t(i)].kind == TaskDim::Kind::kReal;
    if (v.is_number_integer() && !real) d[py::str(key)] = v.get<int64_t>();
    else if (v.is_number()) d[py::str(key)] = v.get<double>();
    else d[py::str(key)] = text;
  }
  return d;
}

bool is_index(const py::handle& v) {
  const std::string type = py::str(py::type::handle_of(v).attr("__name__"));
  return PyIndex_Check(v.ptr()) && type.find("bool") == std::string::npos;
}

// A task given from Python (reset's options["task"], set_task): every axis once, each value in
// the space (a choice by its index or its value), nothing else. Returns the task as the space
// holds it and as scenario parameters. Throws roger::Error naming the parameter and the space.
py::tuple task_of(const TaskSpace& space, const py::handle& task, const std::string& where) {
  if (space.empty())
    throw Error(where + ": the stage has no task space (give the stage `tasks`, or make(..., tasks={...}))");
  if (!py::isinstance<py::dict>(task))
    throw Error(where + ": a task is a dict {parameter: value} over the task space (" + space.describe() + "), got " +
                py::str(py::type::handle_of(task).attr("__name__")).cast<std::string>());
  ParamList params;
  for (const auto& [k, v] : task.cast<py::dict>()) {
    const std::string key = py::str(k);
    const int i = space.index(key);
    if (i < 0) throw Error(where + ": '" + key + "' is not a parameter of the task space (" + space.describe() + ")");
    const TaskDim& d = space.dims()[size_t(i)];
    if (d.kind == TaskDim::Kind::kChoice && is_index(v)) {
      const int64_t n = int64_t(d.choices.size()), index = v.cast<int64_t>();
      if (index < 0 || index >= n)
        throw Error(where + ": " + key + " = " + std::to_string(index) + " is outside the task space: " + key +
                    " takes an index in [0, " + std::to_string(n) + ") of " + d.text() + ", or one of its values");
      params.push_back({key, d.choices[size_t(index)]});
    } else {
      params.push_back({key, param_text(v)});
    }
  }
  std::string why;
  const std::optional<TaskPoint> t = space.task_of(params, &why);
  if (!t) throw Error(where + ": " + why);
  return py::make_tuple(task_point_dict(space, *t), space.params(*t));
}

// A teacher of the environment's stage, asked and told from the package's Env: the pick waiting
// for its outcome is kept here.
class PyTeacher {
 public:
  PyTeacher(std::unique_ptr<Teacher> teacher, TaskSpace space) : teacher_(std::move(teacher)), space_(std::move(space)) {}
  // The next task: (as the space holds it, as scenario parameters, the world seed of a level it
  // replays or None).
  py::tuple next() {
    pick_ = teacher_->next();
    ParamList params = space_.params(pick_.task);
    params.insert(params.end(), pick_.extra.begin(), pick_.extra.end());
    py::object seed = pick_.world_seed ? py::object(py::int_(*pick_.world_seed)) : py::object(py::none());
    return py::make_tuple(task_point_dict(space_, pick_.task), params, seed);
  }
  void record(uint64_t world_seed, bool success, double reward, double sim_s) {
    TaskOutcome o;
    o.task = pick_.task;
    o.world_seed = world_seed;
    o.success = success;
    o.reward = reward;
    o.sim_s = sim_s;
    teacher_->record(o);
  }
  std::string kind() const { return teacher_->kind(); }
  std::string state() const { return teacher_->state().dump(); }

 private:
  std::unique_ptr<Teacher> teacher_;
  TaskSpace space_;
  TaskPick pick_;
};

void bind_tasks(py::module_& m) {
  py::class_<PyTeacher>(m, "Teacher")
      .def("next", &PyTeacher::next)
      .def("record", &PyTeacher::record, py::arg("world_seed"), py::arg("success"), py::arg("reward"),
           py::arg("sim_seconds"))
      .def_property_readonly("kind", &PyTeacher::kind)
      .def("state", &PyTeacher::state, "The teacher's own state as JSON text (its step, level, mixture...).");
}

using PyEnvironment = py::class_<StageEnvironment>;

// What an Environment knows of tasks: the stage's task space, its teacher, a reset to a given task.
void def_environment_tasks(PyEnvironment& env) {
  env.def_property_readonly("task_dims", [](const StageEnvironment& e) { return task_dims(e.task_space()); })
      .def_property_readonly("teaches", &StageEnvironment::teaches)
      .def(
          "typed_params",
          [](const StageEnvironment& e, const ParamList& params) { return typed_params(e.task_space(), params); },
          py::arg("params"))
      .def(
          "task_of",
          [](const StageEnvironment& e, const py::handle& task, const std::string& where) {
            return task_of(e.task_space(), task, where);
          },
          py::arg("task"), py::arg("where"))
      .def(
          "make_teacher",
          [](StageEnvironment& e, uint64_t seed) {
            return without_gil([&] { return std::make_unique<PyTeacher>(e.make_teacher(seed), e.task_space()); });
          },
          py::arg("seed"), py::keep_alive<0, 1>())
      .def("reset_task",
           [](StageEnvironment& e, uint64_t seed, const ParamList& task) {
             std::vector<Gamma> g;
             try {
               g = without_gil([&] { return e.reset(seed, task); });
             } catch (const PlacementError& error) {
               throw with_text(error, std::string("reset: ") + error.what());
             }
             return py::make_tuple(state_array(g), e.running());
           },
           py::arg("seed"), py::arg("task"))
      .def("teacher_body_change",
           [](StageEnvironment& e) -> py::object {
             const std::optional<TeacherBodyChange> c = without_gil([&] { return e.teacher_body_change(); });
             if (!c) return py::none();
             return py::dict(py::arg("teacher") = c->teacher, py::arg("lift") = c->lift,
                             py::arg("levels") = c->levels, py::arg("level") = c->level,
                             py::arg("misfit") = c->misfit);
           });
}

// An episode: reset, step, render, replay.
void def_environment_episode(PyEnvironment& env) {
  env.def_property_readonly("info", [](const StageEnvironment& e) { return info_dict(e.info()); })
      .def("reset",
           [](StageEnvironment& e, uint64_t seed) {
             const std::vector<Gamma> g = without_gil([&] { return e.reset(seed); });
             return py::make_tuple(state_array(g), e.running());
           },
           py::arg("seed"))
      .def("step",
           [](StageEnvironment& e, int action) {
             const EnvironmentStep r = without_gil([&] { return e.step(action); });
             return py::make_tuple(state_array(e.state()), r.reward, r.terminated, r.time_out);
           },
           py::arg("action"))
      .def(
          "render", [](const StageEnvironment& e, int width) { return render_array(e, width); }, py::arg("width"))
      .def(
          "replay",
          [](StageEnvironment& e, uint64_t seed, const std::vector<int>& actions, const ParamList& task) {
            without_gil([&] { e.replay(seed, actions, task); });
          },
          py::arg("seed"), py::arg("actions"), py::arg("task") = ParamList());
}

// What an Environment reports of its episode and world.
void def_environment_state(PyEnvironment& env) {
  env.def_property_readonly("actions_taken",
                             [](const StageEnvironment& e) { return e.begun() ? e.episode().actions_taken : std::vector<int>(); })
      .def_property_readonly("begun", &StageEnvironment::begun)
      .def_property_readonly("running", &StageEnvironment::running)
      .def_property_readonly("seed", &StageEnvironment::seed)
      .def_property_readonly("sim_seconds", &StageEnvironment::sim_seconds)
      .def_property_readonly("ticks", &StageEnvironment::ticks)
      .def_property_readonly("decisions", [](const StageEnvironment& e) { return e.episode().decisions; })
      .def_property_readonly("episode_reward", [](const StageEnvironment& e) { return e.episode().reward; })
      .def_property_readonly("success", [](const StageEnvironment& e) { return e.episode().success; })
      .def("senses", [](const StageEnvironment& e) { return senses_dict(e); })
      // The body of the episode's world, which a task or teacher may set apart from the stage's
      // (eye_pixels): what the tick mode's observations are shaped and bounded by.
      .def_property_readonly("body", [](const StageEnvironment& e) {
        const World& world = world_of(e, "body");
        std::array<double, kDofCount> low, high;
        observed_joint_ranges(world.spec().body, low, high);
        return py::dict(py::arg("eye_pixels") = world.camera().pixels,
                        py::arg("joint_low") = std::vector<double>(low.begin(), low.end()),
                        py::arg("joint_high") = std::vector<double>(high.begin(), high.end()));
      });
}

void bind_environment(py::module_& m) {
  PyEnvironment environment(m, "Environment");
  environment.def(py::init([](const std::string& curriculum, const std::string& stage, const std::string& context,
                            const std::string& scenario, const py::dict& params, const py::dict& skills, bool per_tick,
                            const std::string& tasks, const std::string& teacher, const std::string& teacher_file,
                            const std::string& embedded_skills, bool teaching) {
                  const EnvironmentOptions o = make_options(curriculum, stage, context, scenario, params, skills, per_tick,
                                                            tasks, teacher, teacher_file, embedded_skills, teaching);
                  return without_gil([&] {
                    auto env = make_environment(o, "make", [&] { return std::make_unique<StageEnvironment>(o); });
                    check_scenario_takes_tasks(o, *env);
                    return env;
                  });
                }),
                py::arg("curriculum"), py::arg("stage"), py::arg("context"), py::arg("scenario") = "",
                py::arg("params") = py::dict(), py::arg("skills") = py::dict(), py::arg("per_tick") = false,
                py::arg("tasks") = "", py::arg("teacher") = "", py::arg("teacher_file") = "",
                py::arg("embedded_skills") = "", py::arg("teaching") = true);
  def_environment_tasks(environment);
  def_environment_episode(environment);
  def_environment_state(environment);
}

using IntArray = py::array_t<int64_t, py::array::c_style | py::array::forcecast>;
using ByteArray = py::array_t<uint8_t, py::array::c_style | py::array::forcecast>;
using SeedArray = py::array_t<uint64_t, py::array::c_style | py::array::forcecast>;

// The exception types of the module (set once by PYBIND11_MODULE; never released).
PyObject* roger_error_type = nullptr;
PyObject* script_error_type = nullptr;
PyObject* placement_error_type = nullptr;

// Numpy arrays for one VecEnvironment::Episodes block, under names with a common prefix.
struct EpisodeArrays {
  py::array_t<uint8_t> states;
  py::array_t<uint64_t> seeds;
  py::array_t<double> sim_seconds;
  py::array_t<int32_t> ticks, decisions;
  EpisodeArrays(py::ssize_t n, py::ssize_t k) : states({n, k}), seeds(n), sim_seconds(n), ticks(n), decisions(n) {}
  VecEnvironment::Episodes out() {
    return {states.mutable_data(), seeds.mutable_data(), sim_seconds.mutable_data(), ticks.mutable_data(),
            decisions.mutable_data()};
  }
  void put(py::dict& d, const std::string& prefix) const {
    d[py::str(prefix + "states")] = states;
    d[py::str(prefix + "seed")] = seeds;
    d[py::str(prefix + "sim_seconds")] = sim_seconds;
    // As int64, the dtype Gymnasium's sync and async vector environments gather a single Env's
    // Python ints in (found by a probe: make_vec's int32 and SyncVectorEnv's int64 did not concatenate
    // alike). The engine counts in int32; the copy is of one number per environment.
    d[py::str(prefix + "ticks")] = as_int64(ticks);
    d[py::str(prefix + "decisions")] = as_int64(decisions);
  }

 private:
  // Copied in C++, not by numpy's astype: a call of a Python method may let the GIL go, and a daemon
  // thread that meets the interpreter's end as it takes it back is ended there by CPython (3.11),
  // unwinding these frames without the GIL (found under load: 5 segmentation faults in about 930 exits).
  static py::array_t<int64_t> as_int64(const py::array_t<int32_t>& a) {
    py::array_t<int64_t> out(a.size());
    std::copy(a.data(), a.data() + a.size(), out.mutable_data());
    return out;
  }
};

// n flags, zero, written as bytes and handed to Python as booleans.
py::array_t<uint8_t> flags(py::ssize_t n) {
  py::array_t<uint8_t> a(n);
  std::fill(a.mutable_data(), a.mutable_data() + n, uint8_t(0));
  return a;
}
// The flags as booleans, copied in C++ rather than viewed by numpy's view (EpisodeArrays::as_int64).
py::array_t<bool> as_bool(const py::array_t<uint8_t>& a) {
  py::array_t<bool> out(a.size());
  std::transform(a.data(), a.data() + a.size(), out.mutable_data(), [](uint8_t v) { return v != 0; });
  return out;
}

Autoreset autoreset_of(const std::string& mode) {
  if (mode == "NextStep") return Autoreset::kNextStep;
  if (mode == "SameStep") return Autoreset::kSameStep;
  if (mode == "Disabled") return Autoreset::kDisabled;
  throw Error("make_vec: autoreset_mode must be NextStep, SameStep or Disabled, got '" + mode + "'");
}

// Raises `error` of environment `first` as RogerError or ScriptError (PlacementError) with
// `where` in front of its message and .env = first (and .file, .line of a Lua fault).
[[noreturn]] void raise_vec_error(std::exception_ptr error, int first, const std::string& where,
                                  const std::function<void(py::object&)>& more = {}) {
  py::object exc;
  PyObject* type = roger_error_type;
  try {
    std::rethrow_exception(error);
  } catch (const ScriptError& e) {
    type = dynamic_cast<const PlacementError*>(&e) ? placement_error_type : script_error_type;
    exc = py::handle(type)(where + e.what());
    exc.attr("file") = e.file;
    exc.attr("line") = e.line;
  } catch (const Error& e) {
    exc = py::handle(type)(where + e.what());
  }
  exc.attr("env") = first;
  if (more) more(exc);
  PyErr_SetObject(type, exc.ptr());
  throw py::error_already_set();
}

// Raises the fault of environment `first` as RogerError or ScriptError naming it, with the step's
// outcomes of every environment as .results, the failed ones as .failed and the first as .env.
[[noreturn]] void raise_vec_fault(std::exception_ptr error, int first, uint64_t seed, int n, const py::dict& results,
                                  py::object failed) {
  const std::string where = "environment " + std::to_string(first) + " of " + std::to_string(n) + " (seed " +
                            std::to_string(seed) + ", its episode is over): ";
  raise_vec_error(error, first, where, [&](py::object& exc) {
    exc.attr("failed") = failed;
    exc.attr("results") = results;
  });
}

// "environment 1 of 3" for messages.
std::string env_name(py::ssize_t i, py::ssize_t n) {
  return "environment " + std::to_string(i) + " of " + std::to_string(n);
}

py::dict vec_reset(VecEnvironment& v, const ByteArray& mask, const ByteArray& seeded, const SeedArray& seeds) {
  const py::ssize_t n = v.size(), k = py::ssize_t(v.info().actions.size());
  if (mask.size() != n || seeded.size() != n || seeds.size() != n)
    throw Error("reset: expected one mask entry and one seed per environment (" + std::to_string(n) + ")");
  EpisodeArrays now(n, k);
  const VecEnvironment::ResetRequest request{mask.data(), seeded.data(), seeds.data()};
  std::exception_ptr error;
  without_gil([&] {
    try {
      v.reset(request, now.out());
    } catch (...) {
      error = std::current_exception();
    }
  });
  if (error) {
    // The environment that failed is the first reset one left without a running episode: a
    // reset that succeeds runs to its first decision.
    const uint8_t* m = mask.data();
    py::ssize_t first = 0;
    while (first < n && !(m[first] && !v.env(int(first)).running())) ++first;
    if (first == n) std::rethrow_exception(error);
    raise_vec_error(error, int(first), "reset: " + env_name(first, n) + " (seed " +
                                           std::to_string(v.env(int(first)).seed()) + "): ");
  }
  py::dict d;
  now.put(d, "");
  return d;
}

// step's refusals before anything runs: one action per environment, every environment begun by a
// reset, every action in range.
void check_step(VecEnvironment& v, const IntArray& actions) {
  const py::ssize_t n = v.size(), k = py::ssize_t(v.info().actions.size());
  if (actions.ndim() != 1 || actions.shape(0) != n)
    throw Error("step: expected " + std::to_string(n) + " actions, one per environment, got an array of " +
                std::to_string(actions.size()));
  // An environment that no reset has begun (its reset_mask entry False at every reset) has no
  // episode to step: refused before anything runs, rather than stepped into a fault.
  // None begun: no reset yet at all (found by a probe: the reset_mask advice misled there).
  bool any_begun = false;
  for (py::ssize_t i = 0; i < n; ++i) any_begun = any_begun || v.env(int(i)).begun();
  if (!any_begun)
    throw Error("step: no episode is running in the " + std::to_string(n) + " environments " +
                "(call reset first)");
  for (py::ssize_t i = 0; i < n; ++i)
    if (!v.env(int(i)).begun())
      throw Error("step: " + env_name(i, n) + " has not been reset yet (its reset_mask entry was False at every "
                  "reset): reset it first (reset(options={'reset_mask': ...}))");
  // Every action is checked, also one an environment ignores because this step begins its next
  // episode (NEXT_STEP): the engine checks only those it runs, and whether a bad action is refused
  // should not depend on which episodes happened to end.
  const int64_t* a = actions.data();
  for (py::ssize_t i = 0; i < n; ++i)
    if (a[i] < 0 || a[i] >= int64_t(k))
      throw Error("step: action " + std::to_string(a[i]) + " of environment " + std::to_string(i) + " is not in [0, " +
                  std::to_string(k) + ")");
}

// The arrays one step of n environments fills (VecEnvironment::StepOutput), and the dict they
// become.
struct StepArrays {
  EpisodeArrays now, last;
  py::array_t<double> rewards, episode_rewards;
  py::array_t<uint8_t> term, time_out, restarted, ended, failed, truncated, success;
  StepArrays(py::ssize_t n, py::ssize_t k)
      : now(n, k), last(n, k), rewards(n), episode_rewards(n), term(flags(n)), time_out(flags(n)),
        restarted(flags(n)), ended(flags(n)), failed(flags(n)), truncated(flags(n)), success(flags(n)) {}
  VecEnvironment::StepOutput out() {
    return {now.out(),         rewards.mutable_data(),   term.mutable_data(),
            time_out.mutable_data(), restarted.mutable_data(), ended.mutable_data(),
            failed.mutable_data(), truncated.mutable_data(), last.out(),
            episode_rewards.mutable_data(), success.mutable_data()};
  }
  py::dict dict() const {
    py::dict d;
    now.put(d, "");
    last.put(d, "last_");
    d["rewards"] = rewards;
    d["terminated"] = as_bool(term);
    d["time_out"] = as_bool(time_out);
    d["restarted"] = as_bool(restarted);
    d["ended"] = as_bool(ended);
    d["failed"] = as_bool(failed);
    d["truncated"] = as_bool(truncated);
    d["episode_reward"] = episode_rewards;
    d["success"] = as_bool(success);
    return d;
  }
};

py::dict vec_step(VecEnvironment& v, const IntArray& actions) {
  check_step(v, actions);
  const py::ssize_t n = v.size();
  StepArrays arrays(n, py::ssize_t(v.info().actions.size()));
  const VecEnvironment::StepOutput out = arrays.out();
  std::exception_ptr error;
  without_gil([&] {
    try {
      v.step(actions.data(), out);
    } catch (...) {
      error = std::current_exception();
    }
  });
  const uint8_t* f = arrays.failed.data();
  const int first = int(std::find(f, f + n, uint8_t(1)) - f);
  if (error && first == n) std::rethrow_exception(error);  // refused before anything ran
  py::dict d = arrays.dict();
  if (error) {
    const uint64_t seed = arrays.ended.data()[first] ? arrays.last.seeds.at(first) : arrays.now.seeds.at(first);
    raise_vec_fault(error, first, seed, int(n), d, d["failed"]);
  }
  return d;
}

// A VecEnvironment's snapshot as plain Python values (pickled with the Python object), and back.
py::list vec_snapshot(const VecEnvironment& v) {
  py::list out;
  for (const auto& s : v.snapshot())
    out.append(py::make_tuple(s.base_seed, s.started, s.needs_reset, s.begun, s.seed, s.actions));
  return out;
}

void vec_restore(VecEnvironment& v, const py::list& state) {
  std::vector<VecEnvironment::Snapshot> snapshots;
  for (const auto& item : state) {
    const auto t = item.cast<py::tuple>();
    if (t.size() != 6) throw Error("restore: an environment's state is 6 values, got " + std::to_string(t.size()));
    VecEnvironment::Snapshot s;
    s.base_seed = t[0].cast<uint64_t>();
    s.started = t[1].cast<uint64_t>();
    s.needs_reset = t[2].cast<bool>();
    s.begun = t[3].cast<bool>();
    s.seed = t[4].cast<uint64_t>();
    s.actions = t[5].cast<std::vector<int>>();
    snapshots.push_back(std::move(s));
  }
  without_gil([&] { v.restore(snapshots); });
}

// A batch's deleter: in a process other than the one that made it (a fork()ed child) a batch with
// worker threads is left to the process's end, not deleted. Its workers exist only in the process
// that made it, and ~VecEnvironment joins them: found by a probe, a child that closed such a batch,
// or only exited with it alive, aborted (std::system_error from join; roger/__init__.py refuses
// every other use there). Its memory is the child's copy, freed when the child ends.
struct ForkSafeDelete {
  pid_t maker = getpid();
  void operator()(VecEnvironment* v) const {
    if (v->threads() > 1 && getpid() != maker) return;
    delete v;
  }
};
using VecHolder = std::unique_ptr<VecEnvironment, ForkSafeDelete>;

void bind_vec(py::module_& m) {
  py::class_<VecEnvironment, VecHolder>(m, "VecEnvironment")
      .def(py::init([](const std::string& curriculum, const std::string& stage, const std::string& context,
                       const std::string& scenario, const py::dict& params, const py::dict& skills, int num_envs,
                       int threads, const std::string& autoreset, const std::string& embedded_skills) {
             const EnvironmentOptions o =
                 make_options(curriculum, stage, context, scenario, params, skills, false, "", "", "", embedded_skills,
                              /*teaching=*/false);  // a batch runs no teacher (the package refuses a stage's)
             const Autoreset mode = autoreset_of(autoreset);
             return without_gil([&] {
               return VecHolder(make_environment(o, "make_vec", [&] {
                                  return std::make_unique<VecEnvironment>(o, num_envs, threads, mode);
                                }).release());
             });
           }),
           py::arg("curriculum"), py::arg("stage"), py::arg("context"), py::arg("scenario") = "",
           py::arg("params") = py::dict(), py::arg("skills") = py::dict(), py::arg("num_envs") = 1,
           py::arg("threads") = 1, py::arg("autoreset") = "NextStep", py::arg("embedded_skills") = "")
      .def_property_readonly("info", [](const VecEnvironment& v) { return info_dict(v.info()); })
      .def_property_readonly("num_envs", &VecEnvironment::size)
      .def_property_readonly("teaches", [](const VecEnvironment& v) { return v.env(0).teaches(); })
      .def_property_readonly("threads", &VecEnvironment::threads)
      .def("reset", &vec_reset, py::arg("mask"), py::arg("seeded"), py::arg("seeds"))
      .def("step", &vec_step, py::arg("actions"))
      .def("snapshot", &vec_snapshot)
      .def("restore", &vec_restore, py::arg("state"))
      .def("continue_at", &VecEnvironment::continue_at, py::arg("i"), py::arg("next"))
      .def_property("decision_cap", &VecEnvironment::decision_cap, &VecEnvironment::cap_decisions)
      .def_property_readonly("begun",
                             [](const VecEnvironment& v) {
                               std::vector<bool> out;
                               for (int i = 0; i < v.size(); ++i) out.push_back(v.env(i).begun());
                               return out;
                             })
      .def(
          "render",
          [](const VecEnvironment& v, int i, int width) {
            if (i < 0 || i >= v.size()) throw Error("render: no environment " + std::to_string(i));
            return render_array(v.env(i), width, "render: " + env_name(i, v.size()));
          },
          py::arg("i"), py::arg("width"));
}

void bind_policy(py::module_& m) {
  py::class_<Policy>(m, "Policy")
      .def(py::init<const std::string&>(), py::arg("path"))
      .def("act", &Policy::act, py::arg("obs"), "The greedy action of a state, as roger eval chooses it.")
      .def_property_readonly("actions", [](const Policy& p) { return p.table().action_names(); })
      .def_property_readonly("stage", [](const Policy& p) { return p.meta().stage; })
      .def_property_readonly("context", [](const Policy& p) { return p.meta().context; })
      .def_property_readonly("seed", [](const Policy& p) { return p.meta().seed; })
      .def_property_readonly("path", &Policy::path)
      .def_property_readonly("extra", [](const Policy& p) { return p.meta().extra.dump(); })
      .def_property_readonly("curriculum",
                             [](const Policy& p) { return python_text(p.extra("curriculum", std::string()).get<std::string>()); })
      .def_property_readonly("skills_json",
                             [](const Policy& p) { return p.extra("skills", nlohmann::json::object()).dump(); })
      .def(
          "trial_params",
          [](const Policy& p, const std::string& curriculum, const std::string& scenario) {
            return without_gil([&] { return p.trial_params(curriculum, scenario); });
          },
          py::arg("curriculum"), py::arg("scenario") = "")
      .def(
          "curriculum_note",
          [](const Policy& p, const std::string& curriculum) {
            return python_text(without_gil([&] { return p.curriculum_note(curriculum); }));
          },
          py::arg("curriculum"))
      .def_property_readonly("q", [](const Policy& p) {
        const QTable& q = p.table();
        py::array_t<double> a({q.states(), q.actions()});
        for (int s = 0; s < q.states(); ++s)
          for (int k = 0; k < q.actions(); ++k) a.mutable_at(s, k) = q.value(s, k);
        return a;
      });
}

}  // namespace

PYBIND11_MODULE(_roger, m) {
  m.doc() = "roger's stages as environments (the engine's extension; use the package `roger`)";
  // Errors: roger::Error (bad arguments, files, fields) as RogerError(ValueError); a Lua fault as
  // ScriptError(RogerError) with .file and .line, and a world that could not be placed as
  // PlacementError(ScriptError).
  static py::exception<Error> error(m, "RogerError", PyExc_ValueError);
  // A reference kept for the life of the process (never released: a static py::object would be
  // released after the interpreter is gone).
  static PyObject* script_error = PyErr_NewException("roger._roger.ScriptError", error.ptr(), nullptr);
  m.attr("ScriptError") = py::handle(script_error);
  // A world the scenario could not place (world:sample_position found no room): a ScriptError at
  // the scenario's line that a teacher's reset tells apart, to draw another task.
  static PyObject* placement_error = PyErr_NewException("roger._roger.PlacementError", script_error, nullptr);
  m.attr("PlacementError") = py::handle(placement_error);
  roger_error_type = error.ptr();
  script_error_type = script_error;
  placement_error_type = placement_error;
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ScriptError& e) {
      // Messages as printable text: one holding bytes that are not UTF-8 (a file's, a name's) was
      // raised with no message at all (found by a probe: a policy.json that is not UTF-8).
      PyObject* type = dynamic_cast<const PlacementError*>(&e) ? placement_error : script_error;
      py::object exc = py::handle(type)(printable_text(e.what()));
      exc.attr("file") = printable_text(e.file);
      exc.attr("line") = e.line;
      PyErr_SetObject(type, exc.ptr());
    } catch (const Error& e) {
      PyErr_SetString(error.ptr(), printable_text(e.what()).c_str());
    }
  });
  // As `roger --version` says them (found by a probe: the package named neither).
  m.attr("__version__") = ROGER_VERSION;
  m.def("project_folder", &project_in_use,
        "The project folder the module reads bare names from, and why: ROGER_HOME, installed beside the "
        "module, or the source tree it was built from");
  m.def("mix", &Rng::mix, py::arg("seed"), py::arg("i"),
        "The seed mixer of the engine: roger train's training episode e runs in world mix(seed, e + 1).");
  m.def(
      "state_index",
      [](const std::vector<int>& obs) {
        if (obs.size() > 19)
          throw Error("state_index: a state of " + std::to_string(obs.size()) + " actions has 3^" +
                      std::to_string(obs.size()) + " rows, more than a Q table's index holds (at most 19 actions)");
        std::vector<Gamma> g;
        for (int v : obs) {
          if (v < 0 || v > 2) throw Error("state_index: a controller state is 0, 1 or 2, got " + std::to_string(v));
          g.push_back(Gamma(v));
        }
        return gamma_state_index(g);
      },
      py::arg("obs"), "The row of a policy's Q table for a state vector (first action most significant).");
  bind_tasks(m);
  bind_environment(m);
  bind_vec(m);
  bind_policy(m);
}
