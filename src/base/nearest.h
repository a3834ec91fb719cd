// Suggestions for misspelt names: rank candidates by edit distance to what the user typed.
#pragma once
#include <algorithm>
#include <numeric>
#include <string>
#include <vector>

namespace kiln {

inline int edit_distance(const std::string& a, const std::string& b) {
  std::vector<int> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = static_cast<int>(j);
  for (size_t i = 1; i <= a.size(); ++i) {
    int diag = row[0];
    row[0] = static_cast<int>(i);
    for (size_t j = 1; j <= b.size(); ++j) {
      const int up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] != b[j - 1])});
      diag = up;
    }
  }
  return row[b.size()];
}

// "a, b or c", closest to `typed` first (all of them, so the user sees every valid choice).
// The distance costs length(typed) x length(name): only the first 64 characters of what was
// typed are compared (a text that long is no misspelling of a name), and each name's distance is
// computed once, so that a megabyte typed by mistake is answered at once.
inline std::string choices_nearest_first(const std::string& typed, const std::vector<std::string>& valid) {
  const std::string probe = typed.substr(0, 64);
  std::vector<int> distance;
  for (const std::string& name : valid) distance.push_back(edit_distance(probe, name));
  std::vector<size_t> order(valid.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](size_t x, size_t y) { return distance[x] < distance[y]; });
  std::string s;
  for (size_t i = 0; i < order.size(); ++i) {
    if (i > 0) s += (i + 1 == order.size()) ? " or " : ", ";
    s += "'" + valid[order[i]] + "'";
  }
  return s;
}

}  // namespace kiln
