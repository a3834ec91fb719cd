#include "src/contact_list.h"

namespace kiln {

void ContactList::replace(const std::vector<CandidatePair>& fresh) {
  const size_t n = fresh.size();
  std::vector<double> kept(n, 0.0);
  std::vector<uint8_t> kept_active(n, 2);
  size_t old = 0;
  for (size_t p = 0; p < n; ++p) {
    const CandidatePair want = fresh[p];
    while (old < i.size() && (CandidatePair{i[old], j[old]} < want)) ++old;
    if (old < i.size() && i[old] == want.i && j[old] == want.j) {
      kept[p] = spring[old];
      if (old < active.size()) kept_active[p] = active[old];
    }
  }
  active.swap(kept_active);
  i.resize(n);
  j.resize(n);
  for (size_t p = 0; p < n; ++p) {
    i[p] = fresh[p].i;
    j[p] = fresh[p].j;
  }
  spring.swap(kept);
  trial = spring;
  k.resize(n);
  c.resize(n);
  law.resize(n);
}

}  // namespace kiln
