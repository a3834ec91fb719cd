// The particle contacts stage: every candidate pair that touches (or, with contact events, acts)
// gets its contact forces from the kernel, and its forces, their lever arms' torques, its work
// forces and what it dissipates make its row (ContactRow; HeatRow in a thermal scene). A
// particle's sums are its rows added in the order of the list, so the bits do not depend on the
// number of threads: on one thread the loop adds each row to its two particles as it makes it
// (no row is stored); on several, each contact writes its own row and rows_to_particles() adds
// them per particle in that same order. The scalar sums are taken over fixed blocks of contacts in
// order either way. In a thermal scene's full evaluation the row also carries the heat conducted
// through the contact, and the contact's conductance is kept for conduction's Jacobian: the
// geometry is computed once for all.
//
// The loop is compiled for each normal model, for lists with and without history, for one thread
// or several, and for what the scene adds (PairExtras: nothing, heat, or heat, contact events and
// particles of walls): what a scene uses is chosen once per evaluation, not tested per contact.
#include <algorithm>
#include <type_traits>

#include "src/dem/contact_kernel.h"
#include "src/base/parallel.h"

namespace kiln {

// One batch of acting contacts (FrictionBatch::size at most) of a block: `acting` are their
// places in the block (from `begin`), whose separations, distances and inverse distances the
// block computed. Three loops: the contacts' kinematics, coefficients and committed frames
// gathered into arrays; their forces from the law functions of the kernel (contact(), whose
// branches here are selects: one normal model, friction everywhere, nothing located), a loop
// without a branch or a call that the compiler vectorises; their trial springs, frames and rows
// written in the order of the list. The same operations in the same order as contact(): the same
// bits (tests/dem/friction_batch_test.cpp). A normal that turned too far for the series of
// contact/contact_frame.h (never within a healthy step) is redone by the kernel, `act`.
template <bool Threaded, class M, class Act>
[[gnu::always_inline]] inline void DemSystem::friction_batch(const ContactArrays& list, const ParticleKinematics* kin,
                                                             ParticleSum* to, const int* acting, int count, int begin,
                                                             const double* sep_x, const double* sep_y,
                                                             const double* dist_of, const double* inv_dist,
                                                             FrictionBatch& q, BlockSums& sums, Act& act, int first) {
  for (int u = 0; u < count; ++u) {
    const int k = acting[u], p = begin + k;
    const ParticleKinematics &pi = kin[list.si[p]], &pj = kin[list.sj[p]];
    const double inv_d = inv_dist[k];
    q.nx[u] = sep_x[k] * inv_d;
    q.ny[u] = sep_y[k] * inv_d;
    q.dist[u] = dist_of[k];
    q.r_i[u] = pi.r;
    q.r_j[u] = pj.r;
    q.vx[u] = pi.vx - pj.vx;
    q.vy[u] = pi.vy - pj.vy;
    q.w_i[u] = pi.w;
    q.w_j[u] = pj.w;
    q.spun_i[u] = pi.spun;
    q.spun_j[u] = pj.spun;
    q.inv_r[u] = std::max(pi.inv_r, pj.inv_r);
    q.k[u] = list.k[p];
    q.c[u] = list.c[p];
    const contact::ContactLaw& law = laws_[list.law[p]].law;
    q.tension[u] = law.tension;
    q.stiffness_ratio[u] = law.tangential_stiffness_ratio;
    q.damping_ratio[u] = law.tangential_damping_ratio;
    q.friction[u] = law.friction;
    const contact::ContactFrame& from = list.frame[p];
    q.from_nx[u] = from.nx;
    q.from_ny[u] = from.ny;
    q.from_rho_t[u] = from.rho_t;
    q.from_rho_n[u] = from.rho_n;
    q.spring[u] = list.spring[p];
  }
  for (int u = 0; u < count; ++u) {
    const double nx = q.nx[u], ny = q.ny[u];
    const double rsum = q.r_i[u] + q.r_j[u];
    const double overlap = rsum - q.dist[u];
    const double vn = q.vx[u] * nx + q.vy[u] * ny;
    const double drift = -q.vx[u] * ny + q.vy[u] * nx;
    const contact::NormalLaw nl{q.k[u], q.c[u], M::model, q.tension[u] != 0};
    const double fn = contact::normal_force(nl, overlap, vn);
    const double dashpot = contact::dashpot_force(nl, overlap, fn);
    q.damping[u] = contact::normal_dissipation(nl, overlap, vn, fn);
    const contact::ContactFrame from{q.from_nx[u], q.from_ny[u], q.from_rho_t[u], q.from_rho_n[u]};
    const contact::ContactFrame now{nx, ny, 0.0, -q.dist[u]};
    const double arm_i = contact::pair_arm(q.r_i[u], overlap), arm_j = contact::pair_arm(q.r_j[u], overlap);
    const double arm_then = contact::pair_arm(q.r_i[u], rsum + from.rho_n);
    const double slip_speed = drift + q.w_i[u] * arm_i + q.w_j[u] * arm_j;
    const contact::TangentialLaw law =
        contact::tangential_law(nl, overlap, q.stiffness_ratio[u], q.damping_ratio[u], q.friction[u]);
    const double sine = contact::turn_sine(from, now), cosine = contact::turn_cosine(from, now);
    const bool known = from.known();
    q.redo[u] = known & !contact::small_turn(sine, cosine) ? 1.0 : 0.0;
    const double stretched = q.spring[u] + contact::tangential_displacement(from, now, contact::small_turn_angle(sine),
                                                                             arm_then, arm_i, q.spun_i[u], q.spun_j[u]);
    const double trial = known ? stretched : 0.0;  // a contact that began in this step starts unstretched
    const contact::TangentialResult t = contact::tangential_force(law, trial, slip_speed, fn);
    q.spring[u] = t.spring;
    ContactForces f;  // no rolling couple
    f.tangential = t.force;
    f.dashpot = dashpot;
    f.work_rate -= t.force * slip_speed;
    set_resultant(f, fn, nx, ny);
    const ContactRow row = row_of(f, nx, ny, arm_i, arm_j);
    q.work[u] = f.work_rate;
    q.fx[u] = row.fx;
    q.fy[u] = row.fy;
    q.torque_i[u] = row.torque_i;
    q.torque_j[u] = row.torque_j;
    q.gx[u] = row.gx;
    q.gy[u] = row.gy;
    q.dx[u] = row.dx;
    q.dy[u] = row.dy;
    q.worst[u] = overlap * q.inv_r[u];
  }
  for (int u = 0; u < count; ++u) {
    if (q.redo[u] != 0) {
      act(first + u);
      continue;
    }
    const int p = begin + acting[u];
    list.trial[p] = q.spring[u];
    contact::ContactFrame& frame = list.trial_frame[p];
    frame.nx = q.nx[u];
    frame.ny = q.ny[u];
    frame.rho_t = 0.0;
    frame.rho_n = -q.dist[u];
    ContactRow row;
    row.fx = q.fx[u];
    row.fy = q.fy[u];
    row.torque_i = q.torque_i[u];
    row.torque_j = q.torque_j[u];
    row.gx = q.gx[u];
    row.gy = q.gy[u];
    row.dx = q.dx[u];
    row.dy = q.dy[u];
    if constexpr (Threaded)
      pp_.rows[p] = row;
    else
      add_row(to, list.si[p], list.sj[p], row);
    sums.damping += q.damping[u];
    sums.friction_work += q.work[u];
    sums.worst = std::max(sums.worst, q.worst[u]);
  }
}

template <bool Threaded, bool History, DemSystem::PairExtras X, class M>
[[gnu::always_inline]] inline void DemSystem::pair_contact_loop(Evaluation& e) {
  constexpr bool Plain = X == PairExtras::none, Any = X == PairExtras::any;
  const int np = pp_.size();
  const int blocks = block_count(np);
  block_sums_.resize(blocks);
  // One block of contacts, on whichever thread has it. On one thread the blocks run in a plain
  // loop, not an OpenMP region of one thread. What the loop reads is taken here, in the block:
  // locals of the enclosing function reach an outlined region (or a lambda's closure) through
  // memory, and were loaded again for every contact, the constant flags of this instantiation
  // included; so were the arrays through their vectors, and the cell (the loop's stores of
  // doubles could have changed its members, for all the compiler knew).
  auto block = [&](int b) __attribute__((always_inline)) {
    const bool thermal = !Plain && e.heat != nullptr;
    const bool events = Any && events_, has_attached = Any && has_attached_;
    const double* temp = !Plain && e.conduct ? e.state + temperature_at() : nullptr;
    const PeriodicCell cell = cell_;
    const ParticleKinematics* kin = kinematics_.data();
    const ContactArrays list = pp_.arrays();
    ParticleSum* to = sums_.data();
    HeatRow* heat_rows = pp_.heat_rows.data();
    double* conductance = pp_.conductance.data();
    HeatWork* heat_work = thermal && heat_by_step_ ? heat_work_.data() : nullptr;  // booked by the step
    // A contact's heat: its row on several threads, added to its two particles on one.
    auto book_heat = [&](int p, const HeatRow& heat) {
      if constexpr (Threaded)
        heat_rows[p] = heat;
      else
        add_heat_row(to, list.si[p], list.sj[p], heat);
    };
    BlockSums sums;
    // First the geometry of every candidate, without a branch on whether it touches (a third do
    // not, in an order no branch predictor follows): its separation, distance and inverse
    // distance (square roots and divisions independent of each other), and the lists of the
    // candidates that act and of those that do not. With one loop doing all, the benchmark pile's
    // step took about 1.2 times as long (README, Performance).
    const int begin = b * sum_block, count = std::min(np, begin + sum_block) - begin;
    double sep_x[sum_block], sep_y[sum_block], dist_of[sum_block], inv_dist[sum_block];
    int acting_list[sum_block], idle_list[sum_block];
    int acting_count = 0, idle_count = 0;
    for (int k = 0; k < count; ++k) {
      const int p = begin + k;
      const ParticleKinematics &pi = kin[list.si[p]], &pj = kin[list.sj[p]];
      const Vec2 d = cell.minimum_image(pj.x - pi.x, pj.y - pi.y);  // separation()
      const double rsum = pi.r + pj.r;
      const double d2 = d.x * d.x + d.y * d.y;
      // With contact events the acting set is locked for the step: an acting contact keeps its
      // (continued) law past separation until its release is located, a new one waits for its onset.
      const bool acting = events ? pp_.active[p] != 0 : d2 < rsum * rsum;
      sep_x[k] = d.x;
      sep_y[k] = d.y;
      dist_of[k] = std::sqrt(d2);
      inv_dist[k] = 1 / dist_of[k];
      acting_list[acting_count] = k;
      idle_list[idle_count] = k;
      acting_count += acting;
      idle_count += !acting;
    }
    // What a candidate that does not act leaves: no history, a zero row, no conductance.
    for (int a = 0; a < idle_count; ++a) {
      const int p = begin + idle_list[a];
      if (History && list.history) forget(list, p);
      if constexpr (Threaded) pp_.rows[p] = {};
      if (Threaded && thermal) heat_rows[p] = {};
      if (temp) conductance[p] = 0;
    }
    // Then the contacts that act, one by one through the kernel ...
    auto act = [&](int a) __attribute__((always_inline)) {
      const int k = acting_list[a], p = begin + k, i = list.i[p], j = list.j[p];
      const ParticleKinematics &pi = kin[list.si[p]], &pj = kin[list.sj[p]];
      const Vec2 d{sep_x[k], sep_y[k]};
      const double rsum = pi.r + pj.r;
      // Two particles of walls (attached or fixed) do not push each other: walls do not touch
      // walls. They still conduct heat.
      const bool walls_both = has_attached && attached(i) && attached(j);
      if (walls_both) {
        if (History && list.history) forget(list, p);
        if constexpr (Threaded) pp_.rows[p] = {};
        if (Threaded && thermal) heat_rows[p] = {};
        if (!temp) return;
      }
      const double dist = dist_of[k];
      const double overlap = rsum - dist;
      // Conducted heat: the row is written once, with the friction heat below.
      HeatRow heat;
      if (temp) {
        const double h = touching_conductance(list.law[p], list.k[p], list.c[p], pi.r, pj.r, dist, overlap);
        const double q = h * (temp[j] - temp[i]);
        heat = {q, -q};
        conductance[p] = h;
        if (walls_both) {
          book_heat(p, heat);
          return;
        }
      }
      const double inv_d = inv_dist[k];
      const double nx = d.x * inv_d, ny = d.y * inv_d;  // from i to j
      ContactKinematics c;
      c.frame = {nx, ny, 0.0, -dist};
      c.rv = {pi.vx - pj.vx, pi.vy - pj.vy};
      c.overlap = overlap;
      c.i = i;
      c.j = j;
      if (History && list.history) {
        c.arm_i = contact::pair_arm(pi.r, c.overlap);
        c.arm_other = contact::pair_arm(pj.r, c.overlap);
        c.arm_then = contact::pair_arm(pi.r, rsum + list.frame[p].rho_n);
        c.w_i = pi.w;
        c.w_other = pj.w;
        c.spun_i = pi.spun;
        c.spun_other = pj.spun;
      }
      const ContactForces f = contact<History, M>(list, p, c);
      const ContactRow row = row_of(f, nx, ny, c.arm_i, c.arm_other);
      if constexpr (Threaded)
        pp_.rows[p] = row;
      else
        add_row(to, list.si[p], list.sj[p], row);
      sums.damping += f.damping_power;
      sums.friction_work += f.work_rate;
      if (thermal) {
        const double share = laws_[list.law[p]].heat_share;
        if (heat_work) {
          heat_work[p] = this->heat_work(i, j, share, row);
        } else {
          const double made = heat_made(f.work_rate, f.damping_power);
          heat.to_i += share * made;
          heat.to_j += (1 - share) * made;
          sums.heat_generated += made;
        }
        book_heat(p, heat);
      }
      sums.worst = std::max(sums.worst, c.overlap * std::max(pi.inv_r, pj.inv_r));
        };
    // ... or, where every contact is a frictional one of one normal model with nothing located
    // (the Verlet schemes' plain scenes), in batches: the same law functions over arrays, which
    // the compiler vectorises, the contacts gathered before and their rows added after, in order.
    if constexpr (Plain && History && !std::is_void_v<M>) {
      if (friction_batches_ && list.history && !list.rolling && !list.mode && !list.stage_path && !list.active &&
          !list.load_margin) {
        FrictionBatch batch;
        for (int a0 = 0; a0 < acting_count; a0 += FrictionBatch::size)
          friction_batch<Threaded, M>(list, kin, to, acting_list + a0, std::min(FrictionBatch::size, acting_count - a0),
                                      begin, sep_x, sep_y, dist_of, inv_dist, batch, sums, act, a0);
        block_sums_[b] = sums;
        return;
      }
    }
    for (int a = 0; a < acting_count; ++a) act(a);
    block_sums_[b] = sums;
  };
  if constexpr (Threaded) {
#pragma omp parallel for schedule(static)
    for (int b = 0; b < blocks; ++b) block(b);
  } else {
    for (int b = 0; b < blocks; ++b) block(b);
  }
  add_block_sums(e);
}

// The single-threaded loop of plain scenes (the benchmark's: no heat, contact events or particles
// of walls) is compiled twice, for baseline x86-64 and for AVX2, the one to run chosen by the
// processor when the program starts (GCC's function multiversioning): AVX2 puts four contacts in
// a batch's vectors where SSE2 holds two, and the default build still runs on any x86-64. The
// loop, its blocks and the kernel are inlined into each version. No FMA: the bits are the same on
// both (CMakeLists.txt compiles this file without contraction). The other loops have the baseline
// version only (each version of the loop is one more copy of it to compile: all of them in two
// versions took the sanitizer build 7.7 minutes of CPU for this file, these 5.3), and so have
// clang's builds (the fuzzers): clang 14 does not link clones of a template.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define KILN_CONTACT_LOOP_VERSIONS __attribute__((target_clones("avx2", "default")))
#else
#define KILN_CONTACT_LOOP_VERSIONS
#endif
template <bool History, class M>
KILN_CONTACT_LOOP_VERSIONS void DemSystem::plain_contact_loop(Evaluation& e) {
  pair_contact_loop<false, History, PairExtras::none, M>(e);
}
template <bool Threaded, bool History, DemSystem::PairExtras X, class M>
void DemSystem::contact_loop(Evaluation& e) {
  if constexpr (!Threaded && X == PairExtras::none)
    plain_contact_loop<History, M>(e);
  else
    pair_contact_loop<Threaded, History, X, M>(e);
}

void DemSystem::prepare_particles(const Evaluation& e) {
  kinematics_.resize(n_);
  sums_.resize(n_);
  ParticleKinematics* kin = kinematics_.data();
  ParticleSum* sums = sums_.data();
  const int* slot = slot_.data();
  const bool spins = e.w != nullptr, history = pp_.history, threaded = e.threaded;
#pragma omp parallel for schedule(static) if (parallel_worthwhile(n_))
  for (int i = 0; i < n_; ++i) {
    const int s = slot[i];
    kin[s] = {e.x[i], e.y[i], e.vx[i], e.vy[i], spins ? e.w[i] : 0.0, history ? e.angle[i] - committed_angle_[i] : 0.0,
              radius_[i], inv_radius_[i]};
    if (!threaded) sums[s] = {};
  }
}

void DemSystem::particle_contact_forces(Evaluation& e) {
  const StageTimer timer(profile_, Stage::particle_contacts);
  prepare_particles(e);
  if (e.threaded) pp_.rows.resize(pp_.size());
  if (e.heat && e.threaded) pp_.heat_rows.resize(pp_.size());
  if (e.conduct) pp_.conductance.resize(pp_.size());
  const PairExtras extras = events_ || has_attached_ ? PairExtras::any : e.heat ? PairExtras::heat : PairExtras::none;
  auto with_extras = [&](auto threaded, auto history, auto model) {
    using M = typename decltype(model)::type;
    constexpr bool T = decltype(threaded)::value, H = decltype(history)::value;
    switch (extras) {
      case PairExtras::none: return contact_loop<T, H, PairExtras::none, M>(e);
      case PairExtras::heat: return contact_loop<T, H, PairExtras::heat, M>(e);
      case PairExtras::any: return contact_loop<T, H, PairExtras::any, M>(e);
    }
  };
  auto with_threads = [&](auto history, auto model) {
    if (e.threaded)
      with_extras(std::true_type{}, history, model);
    else
      with_extras(std::false_type{}, history, model);
  };
  auto with_history = [&](auto model) {
    if (pp_.history)
      with_threads(std::true_type{}, model);
    else
      with_threads(std::false_type{}, model);
  };
  if (mixed_models_)
    with_history(std::type_identity<void>{});
  else
    contact::with_normal_model(pair_model_, [&](auto m) { with_history(std::type_identity<decltype(m)>{}); });
}

}  // namespace kiln
