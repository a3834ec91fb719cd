// The granular system as an ODE: state layout, neighbour rebuilds, and the force evaluation.
//
// State y = [q | v | z], structure of arrays:
//   q = x (N), y (N) and, only when some contact has friction or rolling resistance, angle (N);
//   v = vx, vy, omega (same layout); z = the energy ledger: energy dissipated by the normal
//   dashpots, work done by the tangential forces and rolling torques on the relative motion of
//   the contacts (what they dissipated plus what their springs hold), work done by moving walls.
// Only non-conservative power is integrated; elastic and kinetic energy come from the state.
// Integrating the ledger as part of the state makes it as accurate as the trajectory, whichever
// integrator runs, and closes the energy balance (see energy.h).
//
// Friction heat (heat_from_dissipation) is booked as the work of friction and rolling resistance
// on the relative motion, shared by beta: while a friction spring holds energy, its particles'
// temperatures include their shares of it (at most 1/2 k_t xi^2 per contact, ~1e-9 J in the
// shipped cases), and energy() subtracts it from `thermal` and `heat_from_dissipation`. So the
// heat made equals the friction dissipation of the ledger, whatever the springs did, to round-off:
// under ARKODE both integrate the same power; the Verlet schemes book each contact's heat by their
// works' trapezoid (contact_works.cpp). A heat rate from stick and slip phases could not be: the
// Coulomb cap shortens the spring (contact/capped_spring.h), which moves stored energy by a jump.
//
// One derivative evaluation: positions and velocities in, accelerations and ledger rates out.
// Contact history (springs measured from the contact frame of the last accepted step) is written
// to trial arrays and kept only when the step is accepted.
#pragma once
#include <vector>

#include "contact/normal_force.h"
#include "contact/rolling_resistance.h"
#include "contact/stick_slip.h"
#include "contact/tangential_force.h"
#include "integrators/integrator.h"
#include "src/geometry/broadphase.h"
#include "src/dem/contact_coefficients.h"
#include "src/dem/contact_list.h"
#include "src/dem/energy.h"
#include "src/geometry/periodic_cell.h"
#include "src/scene/scene.h"
#include "src/dem/stage_profile.h"
#include "src/scene/wall_geometry.h"

namespace kiln {

// The first-order part z: the ledger integrals, then (thermal scenes) one temperature per particle.
enum Ledger {
  ledger_damping = 0,
  ledger_friction = 1,  // work of friction and rolling resistance; dissipated = this - spring energy
  ledger_walls = 2,
  ledger_heat_walls = 3,
  ledger_heat_generated = 4,
  ledger_mechanical = 3,  // entries in a scene without heat
  ledger_thermal = 5      // entries in a thermal scene
};

// A conduction path of a frozen contact network: particle i to particle j, or to wall -1 - j.
struct ConductanceLink {
  int i = 0, j = 0;
  double h = 0;  // W/K
};

// One touching contact linearised at a state (src/dem/contact_springs.cpp): where it acts and
// the slopes of its laws there, for the stability limit (src/run/linearised_dynamics.h).
struct ContactSprings {
  int i = 0, j = 0;             // particles (j < 0: wall -1 - j)
  Vec2 normal;                  // unit, from i towards the other body
  double arm_i = 0, arm_j = 0;  // lever arms to the contact point (m; a wall's: 0)
  double kn = 0, cn = 0;        // normal: dF/d(overlap) (N/m) and dashpot (N s/m)
  double kt = 0, ct = 0;        // tangential spring and dashpot; 0 without friction or while sliding
  double kr = 0, cr = 0;        // rolling spring (N m/rad) and dashpot; 0 without, or while rolling
};

class DemSystem final : public OdeSystem {
 public:
  explicit DemSystem(const Scene& scene);

  StateLayout layout() const override { return layout_; }
  void prepare(double t, const double* y, double lookahead) override;
  bool neighbours_cover(double t, const double* y) const override;
  void rebuild_neighbours(double t, const double* y, double t_reached, const double* reached) override;
  double neighbour_step_bound(const double* y) const override;
  std::string describe_travel(const double* from, const double* to, double h) const override;
  bool diffusion_jacobian(double t, const double* y, DiffusionJacobian& out) const override;
  void derivative(double t, const double* y, double* ydot) override { evaluate(t, y, ydot, Part::all, nullptr); }
  void accept(double t) override;
  bool has_history() const override { return pp_.history; }
  // Particle contacts in batches where the scene allows (the default), or one by one through the
  // kernel (off): the same bits either way.
  void contact_batches(bool on) { friction_batches_ = on && friction_everywhere_; }
  bool contact_batches() const { return friction_batches_; }
  // IMEX: conduction (linear in the temperatures) is the implicit part; all else is explicit.
  bool has_implicit_part() const override { return thermal_; }
  bool implicit_part_is_linear() const override { return false; }  // conductances follow the positions
  void explicit_part(double t, const double* y, double* ydot) override {
    evaluate(t, y, ydot, Part::explicit_only, nullptr);
  }
  void implicit_part(double t, const double* y, double* ydot) override {
    evaluate(t, y, ydot, Part::implicit_only, nullptr);
  }
  void implicit_jacobian_times(double t, const double* y, const double* v, double* jv) override {
    evaluate(t, y, jv, Part::jacobian, v + temperature_at());
  }
  bool latest_implicit_jacobian_times(const double* v, double* jv) override;
  std::vector<double> absolute_tolerances(const StepControl& c) const override;
  // The damping and friction ledgers are works: their velocity-linear parts are minus the
  // dashpot forces, and minus the friction forces and rolling and friction torques, on the
  // particles, times their velocities. So is the walls' ledger where walls move with the state
  // (wall bodies, attached particles): minus the forces on those, times their velocities.
  int work_components(const double** g) const override {
    *g = work_force_.data();
    return works_;  // ledger_damping, ledger_friction[, ledger_walls]
  }
  // Heat made by dissipation booked per contact by the step (contact_works.cpp): under the Verlet
  // schemes, with the trapezoid of their works, so heat equals beta times the ledger's
  // dissipation to round-off.
  void book_contact_works_by_step() override { heat_by_step_ = thermal_ && heat_power_factor_friction_ > 0; }
  void book_contact_works(const double* dir, double scale, double rest_weight_old, double rest_weight_new,
                          double* z) override;
  // Springs in the state (multi-stage integrators): one slip path per candidate contact of the
  // lists with history, pairs then walls (ContactList::path), so each tangential elongation is
  // integrated at the table's order; their rates are the slip speeds. Rolling springs need none:
  // a rolling spring's trial angle is the committed one plus the particles' turned angles, which
  // are state components already. The paths restart from 0 at each rebuild.
  bool integrate_history(bool on) override;
  int history_size() const override { return pp_.integrated ? pp_.size() + pw_.size() : 0; }
  long history_generation() const override { return rebuilds_; }
  void initial_history(double* s) const override;
  // Contact events (contact_events.cpp): per candidate contact its overlap, positive while the
  // contact is as locked (touching or apart); with friction or rolling resistance, then two per
  // candidate, its tangential and rolling springs' stick or slip (contact/stick_slip.h); with
  // load events, then one per candidate, its pressing or pulling (ContactList::active).
  int event_count() const override {
    return events_ ? (pp_.size() + pw_.size()) * (1 + (pp_.located ? 2 : 0) + (pp_.load_events ? 1 : 0)) : 0;
  }
  void event_functions(double t, const double* y, double* g) override;
  void lock_contacts(double t, const double* y, const int* flips) override;

  std::vector<double> initial_state() const;
  // Checkpoints: what evaluations and steps change (neighbour lists and where they were built,
  // contact history, committed angles, the latest work forces). A system restored into one built
  // from the same scene evaluates as the saved one would have.
  void state(SnapshotFields& f);
  int particles() const { return n_; }
  bool rotates() const { return rotates_; }
  // Offsets of each field in y (angle and omega are -1 when the scene does not rotate).
  int x_at() const { return 0; }
  int y_at() const { return n_; }
  int angle_at() const { return rotates_ ? 2 * n_ : -1; }
  int vx_at() const { return layout_.nq; }
  int vy_at() const { return layout_.nq + n_; }
  int omega_at() const { return rotates_ ? layout_.nq + 2 * n_ : -1; }
  // Load-controlled walls: each one's position along its load (m) and its speed (m/s), after the
  // particles' fields, in the order of the walls.
  int bodies() const { return static_cast<int>(body_wall_.size()); }
  int body_at() const { return (rotates_ ? 3 : 2) * n_; }
  int body_speed_at() const { return layout_.nq + body_at(); }
  // Whether particle i moves with a wall (or is fixed) instead of under its forces.
  [[gnu::always_inline]] bool attached(int i) const { return has_attached_ && scene_.attached[i] != Scene::free_particle; }
  int ledger_at() const { return 2 * layout_.nq; }
  int ledger_count() const { return thermal_ ? ledger_thermal : ledger_mechanical; }
  int temperature_at() const { return thermal_ ? ledger_at() + ledger_thermal : -1; }
  bool thermal() const { return thermal_; }
  double heat_capacity(int i) const { return capacity_[i]; }
  // Conductances of the contacts active in state y at time t (with elastic normal forces): the
  // network that a frozen stage integrates.
  std::vector<ConductanceLink> conduction_links(double t, const double* y) const;
  // The contacts touching in state y at time t (lists prepared for it), linearised: a contact
  // whose committed spring sits at its Coulomb (or rolling) cap slides (rolls) and holds no
  // spring there. Attached particles appear as particles (attached() says which).
  std::vector<ContactSprings> contact_springs(double t, const double* y) const;
  // Index of wall w's load-controlled body (its coordinate at body_at() + index), or -1.
  int body_of_wall(int w) const { return body_of_wall_[w]; }

  double mass(int i) const { return mass_[i]; }
  double inertia(int i) const { return inertia_[i]; }
  double radius(int i) const { return radius_[i]; }
  // The one separation of two particles: p_j - p_i, the nearest images in a periodic cell.
  Vec2 separation(const double* px, const double* py, int i, int j) const {
    return cell_.minimum_image(px[j] - px[i], py[j] - py[i]);
  }
  const PeriodicCell& cell() const { return scene_.periodic; }

  // The ledger at (t, y); potential and thermal energy from the scene's initial state (energy.h).
  EnergyLedger energy(double t, const double* y) const;
  struct ContactCount {
    long particle_particle = 0, particle_wall = 0;
  };
  ContactCount count_contacts(double t, const double* y) const;
  // Largest overlap / smaller radius seen at the latest evaluation.
  double max_overlap_fraction() const { return max_overlap_fraction_; }
  long rebuilds() const { return rebuilds_; }
  // How often the particles were ranked along the curve (see slot_).
  long reorders() const { return reorders_; }
  double skin() const { return broadphase_.skin(); }
  const ContactList& particle_contacts() const { return pp_; }
  const ContactList& wall_contacts() const { return pw_; }
  // Wall segment endpoints at time t in state y (a load-controlled wall's position is part of y).
  void wall_geometry(double t, const double* y, std::vector<Vec2>& a, std::vector<Vec2>& b) const;
  // What the particles do to each wall (indexed as scene().walls), at the latest force
  // evaluation: the force on the wall (N), its torque about the wall's centre (N m,
  // counter-clockwise positive) and the power the wall delivers to the particles (W).
  struct WallLoad {
    Vec2 force;
    double torque = 0, power = 0;
  };
  const std::vector<WallLoad>& wall_loads() const { return wall_loads_; }
  // The velocity of wall w's point `p` at time t in state y: its driven motion plus, for a
  // load-controlled wall, the speed of its free coordinate.
  Vec2 wall_point_velocity(int w, Vec2 p, double t, const double* y) const {
    return scene_.walls[w].motion.velocity_at(p, t) + body_velocity(w, y);
  }
  Vec2 body_velocity(int w, const double* y) const;  // the free coordinate's part alone
  const Scene& scene() const { return scene_; }
  // The wall time of the stages this system runs (neighbour update, contacts, conduction).
  const StageProfile& profile() const { return profile_; }

 private:
  // What one evaluation computes: everything, the explicit or the implicit part of an IMEX split,
  // or the implicit part's Jacobian times the temperatures `temps` (walls held at 0).
  enum class Part { all, explicit_only, implicit_only, jacobian };
  // One force evaluation's inputs, outputs and running sums, shared by its stages.
  struct Evaluation {
    double t = 0;
    const double* state;
    const double *x, *y, *angle, *vx, *vy, *w;  // state fields (angle, w null without rotation)
    double *fx, *fy, *torque;                    // accelerations (torque null likewise); sums_ has the forces
    double* heat = nullptr;                      // thermal scenes: dT/dt
    double *gd = nullptr, *g = nullptr;          // work forces of the damping and friction ledgers
    double* gw = nullptr;                        // ... and of the walls' (wall bodies, attached particles)
    double damping = 0, friction_work = 0, walls_work = 0, heat_generated = 0, heat_walls = 0;
    double worst = 0;     // largest overlap / radius
    bool conduct = false;  // a thermal scene's full evaluation: conduction goes with the contacts
    // The particle contacts run on several threads: each contact writes its row and
    // rows_to_particles() sums them. Otherwise each row is added to its particles as it is made.
    bool threaded = false;
  };
  // What a block of particle contacts adds to the evaluation's sums (parallel.h).
  struct BlockSums {
    double damping = 0, friction_work = 0, heat_generated = 0, worst = 0;
  };
  void add_block_sums(Evaluation& e) const {
    for (const BlockSums& b : block_sums_) {
      e.damping += b.damping;
      e.friction_work += b.friction_work;
      e.heat_generated += b.heat_generated;
      e.worst = std::max(e.worst, b.worst);
    }
  }
  void evaluate(double t, const double* y, double* ydot, Part part, const double* temps);
  // The stages of an evaluation (each in a file of its own).
  Evaluation begin_evaluation(double t, const double* y, double* ydot);
  void particle_contact_forces(Evaluation& e);  // stage_particle_contacts.cpp
  // What a scene adds to the pair loop's contacts: nothing, heat alone, or also contact events
  // and particles of walls.
  enum class PairExtras { none, heat, any };
  template <bool Threaded, bool History, PairExtras X, class M>
  void contact_loop(Evaluation& e);  // the loop compiled for its case, in one version or two
  template <bool History, class M>
  void plain_contact_loop(Evaluation& e);
  template <bool Threaded, bool History, PairExtras X, class M>
  void pair_contact_loop(Evaluation& e);
  // What a particle contact reads of its two particles, packed per particle (one cache line) at
  // the start of the stage: the contact loop then holds one pointer for them instead of eight,
  // and its working values stay in registers instead of going through the stack. Without
  // rotation w and spun are 0. prepare_particles() packs them, each particle at its slot (see
  // slot_), and, on one thread, zeroes the sums the contact stages add to (threaded,
  // rows_to_particles() sets them). alignas: malloc aligns a vector's storage to 16 bytes only,
  // and each particle then straddled two lines.
  struct alignas(64) ParticleKinematics {
    double x, y, vx, vy;
    double w, spun;  // spin (rad/s), angle turned since the committed state (rad)
    double r, inv_r;
  };
  void prepare_particles(const Evaluation& e);
  // What the contacts add to a particle, at its slot, one cache line: force, torque, the dashpots'
  // and friction's work forces, heat. Particles without rotation or heat add zeros there.
  // accelerations() takes them to the evaluation's arrays.
  struct alignas(64) ParticleSum {
    double fx, fy, torque, dx, dy, gx, gy, heat;
  };
  // A contact's row added to one particle's sum: the pair's i takes it as it is, its j with the
  // opposite sign and torque_j (a sign of -1 is exact: the bits of subtracting).
  [[gnu::always_inline]] static void add_row_to(ParticleSum& s, const ContactRow& r, bool is_i) {
    const double sign = is_i ? 1.0 : -1.0;
    s.fx += sign * r.fx;
    s.fy += sign * r.fy;
    s.dx += sign * r.dx;
    s.dy += sign * r.dy;
    s.gx += sign * r.gx;
    s.gy += sign * r.gy;
    s.torque += is_i ? r.torque_i : r.torque_j;
  }
  // ... to the sums of the particles at slots a and b (b < 0: a wall), heat rows likewise: on one
  // thread, in the order of the lists, the additions rows_to_particles() makes.
  [[gnu::always_inline]] static void add_row(ParticleSum* s, int a, int b, const ContactRow& r) {
    add_row_to(s[a], r, true);
    if (b >= 0) add_row_to(s[b], r, false);
  }
  [[gnu::always_inline]] static void add_heat_row(ParticleSum* s, int a, int b, const HeatRow& h) {
    s[a].heat += h.to_i;
    if (b >= 0) s[b].heat += h.to_j;
  }
  // A batch of acting particle contacts (stage_particle_contacts.cpp): their inputs and results,
  // one array each, so that the loop of their laws is vectorised.
  struct FrictionBatch {
    static constexpr int size = 64;
    double nx[size], ny[size], dist[size], r_i[size], r_j[size], vx[size], vy[size], w_i[size], w_j[size];
    double spun_i[size], spun_j[size], inv_r[size], k[size], c[size], tension[size], stiffness_ratio[size];
    double damping_ratio[size], friction[size], from_nx[size], from_ny[size], from_rho_t[size], from_rho_n[size];
    double spring[size], damping[size], work[size], fx[size], fy[size], torque_i[size], torque_j[size];
    double gx[size], gy[size], dx[size], dy[size], worst[size];
    double redo[size];  // 1: the normal turned beyond the series (a double: one vector type in the loop)
  };
  template <bool Threaded, class M, class Act>
  void friction_batch(const ContactArrays& list, const ParticleKinematics* kin, ParticleSum* to, const int* acting,
                      int count, int begin, const double* sep_x, const double* sep_y, const double* dist_of,
                      const double* inv_dist, FrictionBatch& q, BlockSums& sums, Act& act, int first);
  void wall_contact_forces(Evaluation& e);  // stage_wall_contacts.cpp
  void rows_to_particles(Evaluation& e);    // stage_contact_sums.cpp (threaded evaluations)
  void attached_particles(Evaluation& e);       // what pushes them pushes their walls
  void wall_bodies(Evaluation& e, double* ydot);  // load-controlled walls under their loads
  void accelerations(Evaluation& e);            // the sums to accelerations (gravity) and work forces
  void close_ledger(const Evaluation& e, double* ydot);
  void implicit_conduction(double t, const double* y, double* ydot, const double* temps, bool wall_sources);

  // Neighbour update (neighbour_update.cpp): new candidate lists at (t, y) with a skin of at
  // least `skin` (the base skin otherwise).
  void rebuild(double t, const double* y, double skin = 0);
  // The places the tree sees (wrapped into the cell) and the radii, in slot order.
  void places_by_slot(const double* px, const double* py);
  // Ranks the particles along a Hilbert curve of their places when the candidate pairs' slots
  // have drifted apart (curve_order.h); true when the slots changed.
  bool reorder_slots();
  bool covers(double t, const double* y, double lookahead) const;
  double fastest_speed(const double* y) const;
  void set_coefficients(ContactList& list, bool walls);
  // The contact frames of the touching contacts that have none, at the committed state (t, y).
  void frame_new_contacts(double t, const double* y);
  void update_walls(double t, const double* y);
  // Where the free coordinate of wall w's body puts it, in state y.
  Vec2 body_offset(int w, const double* y) const;
  // A particle's place in the cell (its wrapped image): where walls and the tree see it.
  Vec2 place(const double* px, const double* py, int i) const { return cell_.wrap({px[i], py[i]}); }

  // Overlap of candidate contact p of the pp list (walls: of pw), negative when apart.
  double pair_overlap(const double* px, const double* py, int p) const;
  double wall_overlap(const double* px, const double* py, const std::vector<Vec2>& a, const std::vector<Vec2>& b,
                      int p) const;
  // The contact of particle i with segment s at current geometry a, b (see disc_segment_contact).
  // In a periodic cell the particle's image nearest the segment's middle meets it: walls need not
  // lie in the cell (a wall translating along a periodic axis), and a particle's wrap changes
  // neither its candidates nor its contact.
  bool wall_hit(const double* px, const double* py, const std::vector<Vec2>& a, const std::vector<Vec2>& b, int i,
                int s, WallHit& hit, bool apart_too) const {
    return disc_segment_contact(scene_.segments, a, b, s, image_at(px, py, i, a[s], b[s]), radius_[i], hit, apart_too);
  }
  Vec2 image_at(const double* px, const double* py, int i, Vec2 a, Vec2 b) const {
    return cell_.image_near({px[i], py[i]}, 0.5 * (a + b));
  }

  // The contact kernel (contact_kernel.h): one touching contact, particle-particle or
  // particle-wall, from its kinematics to its forces, with its history.
  struct PairMasses {
    double m_eff = 0, inertia = 0, r_eff = 0;  // effective mass, rolling inertia I_r, R*
    double spin_inertia = 0;                   // of the relative rotation, 1/(1/I_i + 1/I_j)
  };
  PairMasses pair_masses(int i, int j) const;  // j < 0: a wall
  struct ContactKinematics {
    contact::ContactFrame frame;  // this state's
    Vec2 rv;                      // v_i - the velocity of the other body at i's centre (wall: at the contact)
    double overlap = 0;
    double arm_i = 0, arm_other = 0, arm_then = 0;  // lever arms now (the wall's: 0), i's in the committed frame
    double w_i = 0, w_other = 0;                    // spins (rad/s)
    double spun_i = 0, spun_other = 0;              // angles turned since the committed state (rad)
    int i = 0, j = 0;                               // the particles (j < 0: a wall)
  };
  struct ContactForces {
    double fx = 0, fy = 0;     // on i (N)
    double tangential = 0;     // along t, on i (N)
    double couple = 0;         // rolling couple on i (N m)
    double dashpot = 0;        // the normal force's dashpot part (N)
    double damping_power = 0;  // W
    double work_rate = 0;      // power of friction and rolling resistance on the relative motion (W)
  };
  template <bool History, class M>
  ContactForces contact(const ContactArrays& list, int p, const ContactKinematics& c) const;
  // The force on i from the normal force fn and f's tangential force, n = (nx, ny) from i.
  [[gnu::always_inline]] static void set_resultant(ContactForces& f, double fn, double nx, double ny) {
    f.fx = -fn * nx - f.tangential * ny;
    f.fy = -fn * ny + f.tangential * nx;
  }
  // A contact's row from its forces: the torques of its tangential force at the lever arms (a
  // wall's arm is 0) and its couple, friction's and the dashpot's work forces.
  // work_rate = -F_t ((v_i - v_j) . t + arm_i w_i + arm_j w_j) - M (w_i - w_j)
  [[gnu::always_inline]] static ContactRow row_of(const ContactForces& f, double nx, double ny, double arm_i,
                                                  double arm_other) {
    ContactRow row;
    row.fx = f.fx;
    row.fy = f.fy;
    row.torque_i = arm_i * f.tangential + f.couple;
    row.torque_j = arm_other * f.tangential - f.couple;
    row.gx = f.tangential * ny;
    row.gy = -f.tangential * nx;
    row.dx = f.dashpot * nx;
    row.dy = f.dashpot * ny;
    return row;
  }
  contact::TangentialLaw tangential_law(const ContactCoefficients& lf, const contact::NormalLaw& nl,
                                        double overlap) const;
  contact::RollingLaw rolling_law(const ContactCoefficients& lf, const contact::NormalLaw& nl, double overlap,
                                  const PairMasses& pm, double load) const;
  static void forget(const ContactArrays& list, int p);  // not touching: no history
  static contact::CappedSpringResult locked(const ContactArrays& list, int e, double k, double c, double limit,
                                            double spring, double rate, const contact::CapRates& rates);
  // The heat a contact's dissipation makes (W): its friction work, and its damping where the
  // scene says so (Nguyen et al. 2009, eq. 1: m c_p dT/dt = sum_j (H (T_j - T_i) + E_f / (2 dt))).
  // Friction heat is booked as the work of friction on the relative motion: what a spring holds
  // for a while is heat-to-be, subtracted again in energy() (see the header).
  [[gnu::always_inline]] double heat_made(double work_rate, double damping_power) const {
    return heat_power_factor_friction_ * work_rate + heat_power_factor_damping_ * damping_power;
  }
  // A touching contact's heat rate as a row on the velocities of its particles i and j (j < 0: a
  // wall), hx (v_xi - v_xj) + hy (v_yi - v_yj) - ti w_i - tj w_j, plus what does not go through
  // them (a moving wall's part): its work and dashpot rows (ContactRow) times the heat factors.
  // Particle i takes `share` of it, j the rest. Kept at the latest and the previous full evaluation
  // when the heat is booked by the step (book_contact_works).
  void heat_work_state(SnapshotFields& f);  // the latest evaluation's, for checkpoints
  struct HeatWork {
    int i = -1, j = -1;
    double share = 0, hx = 0, hy = 0, ti = 0, tj = 0, rest = 0;
  };
  [[gnu::always_inline]] HeatWork heat_work(int i, int j, double share, const ContactRow& row) const {
    const double f = heat_power_factor_friction_, d = heat_power_factor_damping_;
    return {i, j, share, f * row.gx + d * row.dx, f * row.gy + d * row.dy, f * row.torque_i, f * row.torque_j, 0.0};
  }

  // Conduction (stage_conduction.cpp).
  double pair_conductance(const double* px, const double* py, int p) const;
  // ... of a touching contact of law `law` with normal coefficients k, c and radii r_i, r_j (r_j
  // infinite: a wall), its centres (or centre and wall) `dist` apart with `overlap`; inlined in
  // the contact pass, which has all of them in registers or cache (loaded again through the
  // lists, they cost a tenth of its time). Hertz conductance takes the elastic normal force: the
  // contact radius is set by the elastic deformation, the dashpot does not widen it.
  [[gnu::always_inline]] double touching_conductance(int law, double k, double c, double ri, double rj, double dist,
                                                     double overlap) const {
    const ContactCoefficients& lf = laws_[law];
    const double elastic = lf.conduction.model == thermal::ConductionModel::hertz
                               ? contact::normal_force(lf.normal_law_of(k, c), overlap, 0.0)
                               : 0.0;
    return thermal::conductance(lf.conduction, lf.mean_conductivity, ri, rj, dist, elastic);
  }
  double wall_conductance(const double* px, const double* py, const std::vector<Vec2>& a, const std::vector<Vec2>& b,
                          int p, int& wall) const;
  double conduct(double t, const double* y, const double* temp, double* heat, bool wall_sources) const;
  // Where conducted heat goes: particle i's entry of a plain array, or (a full evaluation) the sum
  // at its slot.
  struct HeatSink {
    double* heat = nullptr;
    ParticleSum* sums = nullptr;
    const int* slot = nullptr;
    double& operator[](int i) const { return sums ? sums[slot[i]].heat : heat[i]; }
  };
  double conduct_walls(double t, const double* y, const double* temp, const HeatSink& heat, bool wall_sources,
                       double* conductance = nullptr) const;

  const Scene& scene_;
  const PeriodicCell& cell_;
  int n_ = 0;
  bool rotates_ = false;
  bool moving_walls_ = false;
  bool thermal_ = false;
  bool events_ = false;  // contact events: the acting set is locked within a step
  double heat_power_factor_damping_ = 0, heat_power_factor_friction_ = 0;  // 1 when that dissipation heats
  bool heat_by_step_ = false;  // book_contact_works_by_step(): the contacts' heat is booked by the step
  std::vector<HeatWork> heat_work_, heat_work_before_;  // per contact: pairs, then walls
  std::vector<double> capacity_, inv_capacity_;
  StateLayout layout_;
  std::vector<double> radius_, inv_radius_, mass_, inv_mass_, inertia_, inv_inertia_;
  std::vector<int> material_;
  std::vector<ContactCoefficients> laws_;  // per material pair
  bool mixed_models_ = false;              // the laws of used material pairs differ in normal model
  // Every used pair of materials has friction and none rolling resistance: particle contacts may
  // go in batches (FrictionBatch), unless turned off (contact_batches(false): the kernel's own
  // loop, the reference the batches are tested against).
  bool friction_everywhere_ = false, friction_batches_ = false;
  contact::NormalModel pair_model_ = contact::NormalModel::linear;  // otherwise, theirs

  double base_skin_ = 0;  // the scene's skin (or the automatic one); a rebuild may widen it for a step
  Broadphase broadphase_;
  std::vector<CandidatePair> candidates_;
  ContactList pp_, pw_;
  std::vector<double> x_ref_, y_ref_;  // positions at the last rebuild
  double t_ref_ = 0;
  bool built_ = false;
  long rebuilds_ = 0;
  // Angles at the last accepted step, and at the latest evaluation (kept when its step is
  // accepted), with their times: what the contact springs' rotations are measured from.
  std::vector<double> committed_angle_, trial_angle_;
  double committed_time_ = 0, trial_time_ = 0;
  std::vector<double> work_force_;  // see work_components(), from the latest evaluation
  std::vector<BlockSums> block_sums_;  // the particle contacts stage's, per block
  // The contact stage's order of the particles: particle i's kinematics and sums are at slot_[i],
  // the particle at slot s is particle_at_[s]. The lists are sorted by their pairs' slots, so the
  // contact loop walks the particles in this order. The identity until a pile has mixed so far
  // that its pairs' slots lie far apart: then the particles are ranked along a Hilbert curve
  // (reorder_slots()), as LAMMPS sorts its atoms, without renumbering the state.
  std::vector<int> slot_, particle_at_;
  std::vector<int> curve_order_;            // reorder_slots()'s scratch
  std::vector<uint64_t> curve_keys_;
  long reorders_ = 0;
  // The share of pairs apart (share_apart) that the latest ranking left: rank again only once it
  // has doubled. A ranking that could not bring the pairs together (a curve through a scene whose
  // extent one far particle sets, every disc of the pile in one or two of its cells) is not
  // repeated at every rebuild.
  double ranked_share_ = 0;
  std::vector<double> slot_x_, slot_y_, slot_r_;  // places_by_slot()'s
  std::vector<ParticleKinematics> kinematics_;  // the particle contacts stage's, per slot
  std::vector<ParticleSum> sums_;               // the contact stages', per slot
  bool latest_conducted_ = false;      // the latest evaluation was full: the lists hold its conductances
  int works_ = 2;
  double max_overlap_fraction_ = 0;
  std::vector<WallLoad> wall_loads_;
  std::vector<Vec2> wall_reference_, wall_centre_;  // what each wall's torque is about: at t = 0, now
  std::vector<int> body_wall_;       // the load-controlled walls
  std::vector<int> body_of_wall_;    // each wall's body index, or -1
  std::vector<double> body_ref_;     // their positions at the last rebuild
  std::vector<double> body_acceleration_;  // latest evaluation
  bool has_attached_ = false;
  std::vector<int> attached_list_;  // the attached (and fixed) particles
  std::vector<Vec2> wall_velocity_;  // of each wall's body (driven part plus free part), latest evaluation
  mutable StageProfile profile_;

  std::vector<Vec2> seg_a_, seg_b_;  // wall geometry at the latest time asked for
  mutable std::vector<Vec2> event_a_, event_b_;  // scratch of the event functions
  std::vector<double> event_rates_;               // ... and of their evaluation (stick and slip)
  double seg_time_ = -1;
};

}  // namespace kiln
