#include "src/dem/contact_list.h"

#include "src/base/error.h"

#include <algorithm>

namespace kiln {

namespace {

// A candidate's place in a list's order: its lower and higher slot (a wall pair: its particle's
// slot and its segment) in one integer.
uint64_t order_key(int a, int b) { return (static_cast<uint64_t>(static_cast<uint32_t>(a)) << 32) | static_cast<uint32_t>(b); }

}  // namespace

void ContactList::replace(const std::vector<CandidatePair>& fresh, int particles, bool pairs, const int* at,
                          const int* slot) {
  const size_t n = fresh.size(), kept = i.size();
  // The kept pairs' keys under the slots of now, and the order to walk them in: their own, unless
  // the slots changed since they were found.
  std::vector<uint64_t>& keys = scratch_keys;
  std::vector<int>& walk = scratch_walk;
  keys.resize(kept);
  walk.resize(kept);
  for (size_t o = 0; o < kept; ++o) {
    const int a = slot[i[o]], b = pairs ? slot[j[o]] : j[o];
    keys[o] = pairs && b < a ? order_key(b, a) : order_key(a, b);
    walk[o] = static_cast<int>(o);
  }
  if (!std::is_sorted(keys.begin(), keys.end()))
    std::sort(walk.begin(), walk.end(), [&](int u, int v) { return keys[u] < keys[v]; });
  // The merge writes into the trial arrays (copied from the committed ones below anyway) and a
  // scratch array kept for the next rebuild: once the lists have reached their size, rebuilds
  // allocate nothing (freed and reallocated blocks grew a 100,000-disc run's peak by a third).
  std::vector<uint8_t>& kept_active = scratch_active;
  kept_active.assign(n, 2);
  std::vector<int8_t>& kept_mode = scratch_mode;
  kept_mode.assign(located ? 2 * n : 0, 0);
  std::vector<double>& kept_spring = trial;
  std::vector<double>& kept_roll = trial_roll;
  std::vector<contact::ContactFrame>& kept_frame = trial_frame;
  kept_spring.assign(history ? n : 0, 0.0);
  kept_roll.assign(rolling ? n : 0, 0.0);
  kept_frame.assign(history ? n : 0, {});
  size_t w = 0;
  for (size_t p = 0; p < n; ++p) {
    const uint64_t want = order_key(fresh[p].i, fresh[p].j);
    while (w < kept && keys[walk[w]] < want) ++w;
    if (w < kept && keys[walk[w]] == want) {
      const int old = walk[w];
      if (old < static_cast<int>(active.size())) kept_active[p] = active[old];
      if (located && 2 * old < static_cast<int>(mode.size())) {
        kept_mode[2 * p] = mode[2 * old];
        kept_mode[2 * p + 1] = mode[2 * old + 1];
      }
      if (history) {
        kept_spring[p] = spring[old];
        if (rolling) kept_roll[p] = roll[old];
        kept_frame[p] = frame[old];
      }
    }
  }
  active.swap(kept_active);
  mode.swap(kept_mode);
  margin.assign(mode.size(), 0.0);
  pull.assign(mode.size(), 0.0);
  load_margin.assign(load_events ? n : 0, 1.0);
  i.resize(n);
  j.resize(n);
  for (size_t p = 0; p < n; ++p) {
    // A pair's particles in index order, whatever their slots: its springs and frame are i's.
    const int a = at[fresh[p].i], b = pairs ? at[fresh[p].j] : fresh[p].j;
    i[p] = pairs ? std::min(a, b) : a;
    j[p] = pairs ? std::max(a, b) : b;
  }
  spring.swap(kept_spring);
  roll.swap(kept_roll);
  frame.swap(kept_frame);
  trial = spring;
  trial_roll = roll;
  trial_frame = frame;
  // New lists, new state components: every path starts again from 0 (the integrator's too).
  path.assign(integrated ? n : 0, 0.0);
  trial_path = path;
  k.resize(n);
  c.resize(n);
  law.resize(n);
  place(slot, pairs);
  index(particles, pairs);
}

void ContactList::place(const int* slot, bool pairs) {
  const size_t n = i.size();
  si.resize(n);
  sj.resize(n);
  for (size_t p = 0; p < n; ++p) {
    si[p] = slot[i[p]];
    sj[p] = pairs ? slot[j[p]] : -1;
  }
}

void ContactList::index(int particles, bool pairs) {
  const size_t n = i.size();
  if (!rows.empty()) rows.resize(n);
  // Where each slot's rows are: counting sorts by the lower slot (already in order) and by the
  // higher.
  auto lower = [&](size_t p) { return pairs ? std::min(si[p], sj[p]) : si[p]; };
  by_i.assign(particles + 1, 0);
  for (size_t p = 0; p < n; ++p) ++by_i[lower(p) + 1];
  for (int q = 0; q < particles; ++q) by_i[q + 1] += by_i[q];
  by_j.assign(pairs ? particles + 1 : 0, 0);
  by_j_rows.resize(pairs ? n : 0);
  if (!pairs) return;
  for (size_t p = 0; p < n; ++p) ++by_j[std::max(si[p], sj[p]) + 1];
  for (int q = 0; q < particles; ++q) by_j[q + 1] += by_j[q];
  scratch_next.assign(by_j.begin(), by_j.end() - 1);
  for (size_t p = 0; p < n; ++p) by_j_rows[scratch_next[std::max(si[p], sj[p])]++] = static_cast<int>(p);
}

namespace {

std::vector<double> flatten(const std::vector<contact::ContactFrame>& frames) {
  std::vector<double> v;
  v.reserve(4 * frames.size());
  for (const auto& f : frames) v.insert(v.end(), {f.nx, f.ny, f.rho_t, f.rho_n});
  return v;
}

std::vector<contact::ContactFrame> unflatten(const std::vector<double>& v) {
  std::vector<contact::ContactFrame> frames(v.size() / 4);
  for (size_t p = 0; p < frames.size(); ++p) frames[p] = {v[4 * p], v[4 * p + 1], v[4 * p + 2], v[4 * p + 3]};
  return frames;
}

}  // namespace

void ContactList::state(SnapshotFields& f) {
  f.field("i", i);
  // Every other array holds one value per contact (four per contact frame), or, for the history a
  // contact law may not keep (springs, modes, frames, rolling, integrated paths), none.
  const size_t n = i.size();
  f.field("j", j, {n});
  f.field("law", law, {n});
  f.field("active", active, {n});
  if (!f.saving()) {
    for (uint8_t a : active)
      if (a > 3) throw InputError("the checkpoint's contact list has an acting state that is none of 0 to 3");
    load_margin.assign(load_events ? active.size() : 0, 1.0);
  }
  f.field("k", k, {n});
  f.field("c", c, {n});
  if (!history) return;
  f.field("spring", spring, {0, n});
  f.field("trial", trial, {0, n});
  f.field("roll", roll, {0, n});
  f.field("trial_roll", trial_roll, {0, n});
  f.field("path", path, {0, n});
  f.field("trial_path", trial_path, {0, n});
  f.field("mode", mode, {0, 2 * n});  // a tangential and a rolling element per contact
  if (!f.saving()) {
    margin.assign(mode.size(), 0.0);
    pull.assign(mode.size(), 0.0);
  }
  for (auto [key, frames] : {std::pair{"frame", &frame}, std::pair{"trial_frame", &trial_frame}}) {
    std::vector<double> flat = f.saving() ? flatten(*frames) : std::vector<double>{};
    f.field(key, flat, {0, 4 * n});
    if (!f.saving()) *frames = unflatten(flat);
  }
}

}  // namespace kiln
