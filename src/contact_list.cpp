#include "src/contact_list.h"

namespace kiln {

void ContactList::replace(const std::vector<CandidatePair>& fresh) {
  const size_t n = fresh.size();
  std::vector<uint8_t> kept_active(n, 2);
  std::vector<double> kept_spring(history ? n : 0, 0.0), kept_roll(history ? n : 0, 0.0);
  std::vector<contact::ContactFrame> kept_frame(history ? n : 0);
  size_t old = 0;
  for (size_t p = 0; p < n; ++p) {
    const CandidatePair want = fresh[p];
    while (old < i.size() && (CandidatePair{i[old], j[old]} < want)) ++old;
    if (old < i.size() && i[old] == want.i && j[old] == want.j) {
      if (old < active.size()) kept_active[p] = active[old];
      if (history) {
        kept_spring[p] = spring[old];
        kept_roll[p] = roll[old];
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
}

}  // namespace kiln
