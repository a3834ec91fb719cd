// What a run does besides the mechanics: heat, the integrator and its steps, the run's checks
// and its early stop.
#include "src/scene/scene_parts.h"
#include "src/base/text_format.h"

#include <algorithm>
#include "integrators/integrator.h"

namespace kiln::scene_parts {

namespace {

// The integrators a scene names exist and suit their stages: made once here (an unknown name is
// reported at its key; rtol and contact events are checked where the run makes it, since studies
// override the integrator after loading), and IMEX Euler only where no contact is integrated (its
// forward Euler grows every undamped contact oscillation).
void check_integrators(const SceneNode& root, const Scene& scene) {
  auto check = [&](const SceneNode* node, const std::string& name, bool mechanics) {
    const IntegratorInfo* info = nullptr;
    try {
      info = &integrator_info(name);
    } catch (const InputError& e) {
      if (node) node->fail(e.what());
      throw;
    }
    if (mechanics && !info->integrates_contacts) {
      const std::string why =
          name + " integrates heat on frozen networks only: its explicit Euler part is unstable on undamped contacts. Use "
          "it with 'mechanics: frozen' or as 'freeze.integrator'; for moving grains pick imex3, imex4 or imex5";
      if (node) node->fail(why);
      throw InputError(why);
    }
  };
  const auto integrator_node = root.optional("integrator");
  check(integrator_node ? &*integrator_node : nullptr, scene.integrator, !scene.frozen);
  if (const auto freeze = root.optional("freeze"))
    if (const auto i = freeze->optional("integrator")) check(&*i, scene.freeze.integrator, false);
}

}  // namespace

void read_heat(const SceneNode& root, Scene& scene) {
  if (auto h = root.optional("heat_from_dissipation")) {
    const std::string mode = h->choice({"none", "friction", "all"});
    scene.heat_from_dissipation = mode == "all"        ? HeatFromDissipation::all
                                  : mode == "friction" ? HeatFromDissipation::friction
                                                       : HeatFromDissipation::none;
  }
  if (auto m = root.optional("mechanics")) scene.frozen = m->choice({"dynamic", "frozen"}) == "frozen";
  if (auto f = root.optional("freeze")) {
    f->allow();
    scene.freeze.enabled = true;
    scene.freeze.kinetic_energy_below = (*f)["kinetic_energy_below"].positive();
    if (auto n = f->optional("not_before")) scene.freeze.not_before = n->non_negative();
    if (auto l = f->optional("latest")) scene.freeze.latest = l->positive();
    scene.freeze.dt = (*f)["dt"].positive();
    scene.freeze.dt_at = (*f)["dt"].location();
    if (auto o = f->optional("output_interval")) scene.freeze.output_interval = o->positive();
    if (auto i = f->optional("integrator")) scene.freeze.integrator = i->text();
  }
  if (scene.thermal) {
    for (int i = 0; i < scene.n_particles(); ++i) {
      const Material& m = scene.materials[scene.material[i]];
      if (!(m.specific_heat > 0 && m.conductivity > 0))
        root["materials"][m.name].fail("particles of a thermal scene need specific_heat and conductivity");
    }
    return;
  }
  const char* needs_heat = root.has("heat_from_dissipation") ? "heat_from_dissipation"
                           : root.has("freeze")              ? "freeze"
                                                             : nullptr;
  if (needs_heat) root[needs_heat].fail("this scene carries no temperatures (give particle sets a 'temperature')");
  if (scene.frozen) root["mechanics"].fail("mechanics: frozen leaves nothing to integrate without temperatures");
  for (size_t w = 0; w < scene.walls.size(); ++w)
    if (scene.walls[w].temperature.isothermal())
      root["walls"].items()[w]["temperature"].fail("this scene carries no temperatures (give particle sets a 'temperature')");
}

// The steps: integrator, tolerances, dt, t_end and frames.
void read_stepping(const SceneNode& root, Scene& scene) {
  if (auto i = root.optional("integrator")) scene.integrator = i->text();
  // Below 1e-14 no integrator can meet the tolerance in double precision: ARKODE fails its steps.
  if (auto r = root.optional("rtol")) scene.control.rtol = r->in_range(1e-14, 1, false, true);
  // atol: a number for every component, or per field {position, velocity, angle, temperature, other}.
  // At least 1e-20 (SI units): a component at rest (a velocity or an angle of 0) is held to atol
  // alone, and below what double precision resolves no step passes (atol 1e-100 failed at t = 0
  // blaming dt; 1e-300 with rtol 1e-14 took steps of 5e-14 s for ever: issue 28's review).
  const auto absolute = [](const SceneNode& n) { return n.in_range(1e-20, HUGE_VAL, false, true); };
  if (auto a = root.optional("atol")) {
    if (a->is_map()) {
      a->allow();
      auto field = [&](const char* key, double fallback) { return a->has(key) ? absolute((*a)[key]) : fallback; };
      scene.control.atol = field("other", 0);
      scene.control.atol_position = field("position", NAN);
      scene.control.atol_velocity = field("velocity", NAN);
      scene.control.atol_angle = field("angle", NAN);
      scene.control.atol_temperature = field("temperature", NAN);
    } else {
      scene.control.atol = absolute(*a);
    }
  }
  // Whether the integrator can adapt or locate events is checked where it is made (make_integrator).
  if (auto e = root.optional("contact_events")) scene.control.contact_events = e->boolean();
  if (auto l = root.optional("linear_solver")) {
    scene.control.linear_solver =
        l->choice({"cholesky", "cg"}) == "cg" ? LinearSolverKind::cg : LinearSolverKind::cholesky;
  }
  check_integrators(root, scene);
  // How many steps that makes is judged with the other limits of dt (judge_dt), which --force overrides.
  scene.dt = root["dt"].positive();
  scene.t_end = root["t_end"].positive();
  scene.t_end_at = root["t_end"].location();
  scene.dt_at = root["dt"].location();
  if (scene.dt > scene.t_end) root["dt"].fail("dt is longer than t_end");
  scene.output_interval = root.has("output_interval") ? root["output_interval"].positive() : scene.t_end / 100;
  // 1e-300 s was accepted: a frame at every step, 196 MB for 0.02 s of T3. The count is blamed on
  // t_end when the command line gave it: `--t-end 1e300` over a scene's interval (or a resumed
  // run's) was blamed on the interval.
  const auto frame_count = [&](const char* key, double interval) {
    return format("t_end / %s = %g s / %g s = %.3g frames, more than the limit of %.0e", key, scene.t_end, interval,
                  scene.t_end / interval, max_frames);
  };
  if (scene.t_end / scene.output_interval > max_frames) {
    const SceneNode interval = root["output_interval"];  // given: t_end / 100 frames cannot exceed the limit
    const std::string count = frame_count("output_interval", scene.output_interval);
    // A resumed run's interval is the checkpoint's, given as --set too: there only t_end can change.
    if (scene.t_end_at.file == "--set")
      root["t_end"].fail(count + format("; give at most %g s", scene.output_interval * max_frames) +
                         (interval.location().file == "--set"
                              ? std::string()
                              : ", or a longer output_interval (" + describe(interval.location()) + ")"));
    interval.fail(count + format("; give at least %g s", scene.t_end / max_frames));
  }
  // The heating's frames likewise (freeze.output_interval: 1e-300 wrote a frame every step, 150 MB
  // a minute: issue 28's review).
  if (scene.freeze.enabled && scene.freeze.output_interval > 0 && scene.t_end / scene.freeze.output_interval > max_frames)
    root["freeze"]["output_interval"].fail(frame_count("freeze.output_interval", scene.freeze.output_interval) +
                                           format("; give at least %g s", scene.t_end / max_frames));
}

// The run's own checks and its early stop.
void read_checks(const SceneNode& root, Scene& scene) {
  if (auto s = root.optional("skin")) scene.skin = length(*s);
  if (auto checks = root.optional("checks")) {
    checks->allow();
    if (auto f = checks->optional("max_overlap_fraction")) scene.max_overlap_fraction = f->in_range(0, 1, true, false);
  }
  if (auto stop = root.optional("stop")) {
    stop->allow();
    scene.stop_kinetic_energy = (*stop)["kinetic_energy_below"].positive();
    if (auto n = stop->optional("not_before")) scene.stop_not_before = n->non_negative();
  }

}

}  // namespace kiln::scene_parts
