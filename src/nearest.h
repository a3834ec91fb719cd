// Suggestions for misspelt names: rank candidates by edit distance to what the user typed.
#pragma once
#include <algorithm>
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
inline std::string choices_nearest_first(const std::string& typed, std::vector<std::string> valid) {
  std::stable_sort(valid.begin(), valid.end(), [&](const std::string& x, const std::string& y) {
    return edit_distance(typed, x) < edit_distance(typed, y);
  });
  std::string s;
  for (size_t i = 0; i < valid.size(); ++i) {
    if (i > 0) s += (i + 1 == valid.size()) ? " or " : ", ";
    s += "'" + valid[i] + "'";
  }
  return s;
}

}  // namespace kiln
