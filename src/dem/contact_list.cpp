#include "src/dem/contact_list.h"

namespace kiln {

void ContactList::replace(const std::vector<CandidatePair>& fresh, int particles, bool pairs) {
  const size_t n = fresh.size();
  // The merge writes into the trial arrays (copied from the committed ones below anyway) and a
  // scratch array kept for the next rebuild: once the lists have reached their size, rebuilds
  // allocate nothing (freed and reallocated blocks grew a 100,000-disc run's peak by a third).
  std::vector<uint8_t>& kept_active = scratch_active;
  kept_active.assign(n, 2);
  std::vector<double>& kept_spring = trial;
  std::vector<double>& kept_roll = trial_roll;
  std::vector<contact::ContactFrame>& kept_frame = trial_frame;
  kept_spring.assign(history ? n : 0, 0.0);
  kept_roll.assign(rolling ? n : 0, 0.0);
  kept_frame.assign(history ? n : 0, {});
  size_t old = 0;
  for (size_t p = 0; p < n; ++p) {
    const CandidatePair want = fresh[p];
    while (old < i.size() && (CandidatePair{i[old], j[old]} < want)) ++old;
    if (old < i.size() && i[old] == want.i && j[old] == want.j) {
      if (old < active.size()) kept_active[p] = active[old];
      if (history) {
        kept_spring[p] = spring[old];
        if (rolling) kept_roll[p] = roll[old];
        kept_frame[p] = frame[old];
      }
    }
  }
  active.swap(kept_active);
  i.resize(n);
  j.resize(n);
  for (size_t p = 0; p < n; ++p) {
    i[p] = fresh[p].i;
    j[p] = fresh[p].j;
  }
  spring.swap(kept_spring);
  roll.swap(kept_roll);
  frame.swap(kept_frame);
  trial = spring;
  trial_roll = roll;
  trial_frame = frame;
  k.resize(n);
  c.resize(n);
  law.resize(n);
  index(particles, pairs);
}

void ContactList::index(int particles, bool pairs) {
  const size_t n = i.size();
  if (!rows.empty()) rows.resize(n);
  // Where each particle's rows are: counting sorts by i (already in order) and by j.
  by_i.assign(particles + 1, 0);
  for (size_t p = 0; p < n; ++p) ++by_i[i[p] + 1];
  for (int q = 0; q < particles; ++q) by_i[q + 1] += by_i[q];
  by_j.assign(pairs ? particles + 1 : 0, 0);
  by_j_rows.resize(pairs ? n : 0);
  if (!pairs) return;
  for (size_t p = 0; p < n; ++p) ++by_j[j[p] + 1];
  for (int q = 0; q < particles; ++q) by_j[q + 1] += by_j[q];
  scratch_next.assign(by_j.begin(), by_j.end() - 1);
  for (size_t p = 0; p < n; ++p) by_j_rows[scratch_next[j[p]]++] = static_cast<int>(p);
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
  f.field("j", j);
  f.field("law", law);
  f.field("active", active);
  f.field("k", k);
  f.field("c", c);
  if (!history) return;
  f.field("spring", spring);
  f.field("trial", trial);
  f.field("roll", roll);
  f.field("trial_roll", trial_roll);
  for (auto [key, frames] : {std::pair{"frame", &frame}, std::pair{"trial_frame", &trial_frame}}) {
    std::vector<double> flat = f.saving() ? flatten(*frames) : std::vector<double>{};
    f.field(key, flat);
    if (!f.saving()) *frames = unflatten(flat);
  }
}

}  // namespace kiln
