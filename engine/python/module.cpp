// Module python: the extension `roger._roger` (pybind11) under the Python package `roger`
// (engine/python/roger/__init__.py, which gives it Gymnasium's shape). Binds the stage environment
// and its batched form (batch/environment.h) and saved policies (learn/learning.h); every call
// that runs the engine releases the GIL. The top layer: nothing in the engine includes it.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "batch/environment.h"
#include "core/error.h"
#include "core/rng.h"
#include "learn/learning.h"
#include "script/sandbox/lua_sandbox.h"

namespace py = pybind11;
using namespace roger;

namespace {

using Sets = std::vector<std::pair<std::string, std::string>>;

// A Python value as the text a scenario parameter is given as (--set key=value).
std::string param_text(const py::handle& v) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  return py::str(v).cast<std::string>();
}

EnvironmentOptions make_options(const std::string& curriculum, const std::string& stage, const std::string& context,
                                const std::string& scenario, const py::dict& params, const py::dict& skills,
                                bool per_tick) {
  EnvironmentOptions o;
  o.curriculum = curriculum;
  o.stage = stage;
  o.context = context;
  o.scenario = scenario;
  for (const auto& [k, v] : params) o.sets.push_back({py::str(k).cast<std::string>(), param_text(v)});
  for (const auto& [k, v] : skills) o.skill_files[py::str(k).cast<std::string>()] = py::str(v).cast<std::string>();
  o.per_tick = per_tick;
  return o;
}

py::array_t<uint8_t> state_array(const std::vector<Gamma>& g) {
  py::array_t<uint8_t> a(py::ssize_t(g.size()));
  for (size_t i = 0; i < g.size(); ++i) a.mutable_at(py::ssize_t(i)) = uint8_t(g[i]);
  return a;
}

py::dict info_dict(const EnvironmentInfo& i) {
  py::dict d;
  d["curriculum"] = i.curriculum;
  d["stage"] = i.stage;
  d["context"] = i.context;
  d["scenario"] = i.scenario;
  d["actions"] = i.actions;
  py::dict params;
  for (const auto& [k, v] : i.params) params[py::str(k)] = v;
  d["params"] = params;
  d["time_limit"] = i.time_limit;
  d["time_per_object"] = i.time_per_object;
  d["tick_seconds"] = i.tick_seconds;
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

// The raw senses of the tick that just ran: what a per-tick learner observes.
py::dict senses_dict(const Agent& agent) {
  const Senses& s = agent.world().senses();
  const int pixels = agent.world().camera().pixels;  // the body's eyes decide the shapes
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
  py::array_t<double> q(kDofCount), qdot(kDofCount);
  for (int j = 0; j < kDofCount; ++j) {
    q.mutable_at(j) = s.q[j];
    qdot.mutable_at(j) = s.qdot[j];
  }
  py::dict d;
  d["images"] = images;
  d["stimulus"] = stimulus;
  d["touch"] = touch;
  d["joints"] = q;
  d["joint_velocities"] = qdot;
  return d;
}

// A saved policy.json: the greedy action of a state, as `roger eval` takes it.
class Policy {
 public:
  explicit Policy(const std::string& path) : path_(path), q_(QTable::load(path, {}, &meta_)) {}
  int act(py::array_t<int64_t, py::array::c_style | py::array::forcecast> obs) const {
    if (obs.ndim() != 1 || obs.shape(0) != q_.actions())
      throw Error(path_ + ": the policy has " + std::to_string(q_.actions()) +
                  " actions but the observation has " + std::to_string(obs.size()) + " values");
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
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  PolicyMetadata meta_;
  QTable q_;
};

void bind_environment(py::module_& m) {
  py::class_<StageEnvironment>(m, "Environment")
      .def(py::init([](const std::string& curriculum, const std::string& stage, const std::string& context,
                       const std::string& scenario, const py::dict& params, const py::dict& skills, bool per_tick) {
             const EnvironmentOptions o = make_options(curriculum, stage, context, scenario, params, skills, per_tick);
             py::gil_scoped_release nogil;
             return std::make_unique<StageEnvironment>(o);
           }),
           py::arg("curriculum"), py::arg("stage"), py::arg("context"), py::arg("scenario") = "",
           py::arg("params") = py::dict(), py::arg("skills") = py::dict(), py::arg("per_tick") = false)
      .def_property_readonly("info", [](const StageEnvironment& e) { return info_dict(e.info()); })
      .def("reset",
           [](StageEnvironment& e, uint64_t seed) {
             std::vector<Gamma> g;
             {
               py::gil_scoped_release nogil;
               g = e.reset(seed);
             }
             return py::make_tuple(state_array(g), e.running());
           },
           py::arg("seed"))
      .def("step",
           [](StageEnvironment& e, int action) {
             EnvironmentStep r;
             {
               py::gil_scoped_release nogil;
               r = e.step(action);
             }
             return py::make_tuple(state_array(e.state()), r.reward, r.terminated, r.truncated);
           },
           py::arg("action"))
      .def_property_readonly("running", &StageEnvironment::running)
      .def_property_readonly("seed", &StageEnvironment::seed)
      .def_property_readonly("sim_seconds", &StageEnvironment::sim_seconds)
      .def_property_readonly("ticks", &StageEnvironment::ticks)
      .def_property_readonly("decisions", [](const StageEnvironment& e) { return e.episode().decisions; })
      .def_property_readonly("episode_reward", [](const StageEnvironment& e) { return e.episode().reward; })
      .def_property_readonly("success", [](const StageEnvironment& e) { return e.episode().success; })
      .def("senses", [](const StageEnvironment& e) { return senses_dict(e.agent()); });
}

void bind_vec(py::module_& m) {
  py::class_<VecEnvironment>(m, "VecEnvironment")
      .def(py::init([](const std::string& curriculum, const std::string& stage, const std::string& context,
                       const std::string& scenario, const py::dict& params, const py::dict& skills, int num_envs,
                       int threads) {
             const EnvironmentOptions o = make_options(curriculum, stage, context, scenario, params, skills, false);
             py::gil_scoped_release nogil;
             return std::make_unique<VecEnvironment>(o, num_envs, threads);
           }),
           py::arg("curriculum"), py::arg("stage"), py::arg("context"), py::arg("scenario") = "",
           py::arg("params") = py::dict(), py::arg("skills") = py::dict(), py::arg("num_envs") = 1,
           py::arg("threads") = 1)
      .def_property_readonly("info", [](const VecEnvironment& v) { return info_dict(v.info()); })
      .def_property_readonly("num_envs", &VecEnvironment::size)
      .def_property_readonly("threads", &VecEnvironment::threads)
      .def("reset",
           [](VecEnvironment& v, uint64_t seed) {
             const py::ssize_t n = v.size(), k = py::ssize_t(v.info().actions.size());
             py::array_t<uint8_t> states({n, k});
             py::array_t<uint64_t> seeds(n);
             uint8_t* s = states.mutable_data();
             uint64_t* d = seeds.mutable_data();
             {
               py::gil_scoped_release nogil;
               v.reset(seed, s, d);
             }
             return py::make_tuple(states, seeds);
           },
           py::arg("seed"))
      .def("step",
           [](VecEnvironment& v, py::array_t<int64_t, py::array::c_style | py::array::forcecast> actions) {
             const py::ssize_t n = v.size(), k = py::ssize_t(v.info().actions.size());
             if (actions.ndim() != 1 || actions.shape(0) != n)
               throw Error("step: expected " + std::to_string(n) + " actions, one per environment, got an array of " +
                           std::to_string(actions.size()));
             py::array_t<uint8_t> states({n, k}), finals({n, k}), term(n), trunc(n);
             py::array_t<double> rewards(n), sim_s(n), ep_rewards(n);
             py::array_t<uint64_t> seeds(n), ep_seeds(n);
             py::array_t<int32_t> ticks(n);
             const VecEnvironment::StepOutput out{states.mutable_data(), rewards.mutable_data(), term.mutable_data(),
                                                  trunc.mutable_data(),  finals.mutable_data(),  seeds.mutable_data(),
                                                  ep_seeds.mutable_data(), sim_s.mutable_data(), ticks.mutable_data(),
                                                  ep_rewards.mutable_data()};
             const int64_t* a = actions.data();
             {
               py::gil_scoped_release nogil;
               v.step(a, out);
             }
             py::dict d;
             d["states"] = states;
             d["rewards"] = rewards;
             d["terminated"] = term.attr("astype")("bool");
             d["truncated"] = trunc.attr("astype")("bool");
             d["final_states"] = finals;
             d["seeds"] = seeds;
             d["episode_seeds"] = ep_seeds;
             d["episode_sim_s"] = sim_s;
             d["episode_ticks"] = ticks;
             d["episode_rewards"] = ep_rewards;
             return d;
           },
           py::arg("actions"));
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
  // ScriptError(RogerError) with .file and .line. Registered most derived first.
  static py::exception<Error> error(m, "RogerError", PyExc_ValueError);
  // A reference kept for the life of the process (never released: a static py::object would be
  // released after the interpreter is gone).
  static PyObject* script_error = PyErr_NewException("roger._roger.ScriptError", error.ptr(), nullptr);
  m.attr("ScriptError") = py::handle(script_error);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ScriptError& e) {
      py::object exc = py::handle(script_error)(e.what());
      exc.attr("file") = e.file;
      exc.attr("line") = e.line;
      PyErr_SetObject(script_error, exc.ptr());
    } catch (const Error& e) {
      PyErr_SetString(error.ptr(), e.what());
    }
  });
  m.def("mix", &Rng::mix, py::arg("seed"), py::arg("i"),
        "The seed mixer of the engine: roger train's training episode e runs in world mix(seed, e + 1).");
  m.def(
      "state_index",
      [](const std::vector<int>& obs) {
        std::vector<Gamma> g;
        for (int v : obs) {
          if (v < 0 || v > 2) throw Error("state_index: a controller state is 0, 1 or 2, got " + std::to_string(v));
          g.push_back(Gamma(v));
        }
        return gamma_state_index(g);
      },
      py::arg("obs"), "The row of a policy's Q table for a state vector (first action most significant).");
  bind_environment(m);
  bind_vec(m);
  bind_policy(m);
}
