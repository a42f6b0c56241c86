// Association by feature id: the one merge-join that pairs the features of two views or frames
// carrying the same id (a line's left and right segments in a stereo pair; a reference pair's
// features with the current pair's; any frame of a sliding window with another).
//
// Ranges hold elements with an `id` member (LineObservation, or a model's per-feature record)
// sorted by increasing id. With a duplicated id, equal runs pair element by element in order
// (the k-th of one with the k-th of the other) and the rest of the longer run is left out.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace slt {

// Calls on_match(i, j) for every pair a[i].id == b[j].id, in increasing i (and j). Both ranges
// must be sorted by id (SortedById).
template <typename A, typename B, typename OnMatch>
void JoinById(const std::vector<A>& a, const std::vector<B>& b, OnMatch&& on_match) {
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (a[i].id < b[j].id) {
      ++i;
    } else if (b[j].id < a[i].id) {
      ++j;
    } else {
      on_match(i, j);
      ++i;
      ++j;
    }
  }
}

// Whether a range sorted by id (SortedById) holds an element with this id (binary search).
template <typename T, typename Id>
bool ContainsId(const std::vector<T>& sorted, Id id) {
  const auto it = std::lower_bound(sorted.begin(), sorted.end(), id, [](const T& x, Id key) { return x.id < key; });
  return it != sorted.end() && it->id == id;
}

// `elements` when already sorted by id (files and the simulator list lines by id), else a copy
// sorted by id in *scratch (kept by the caller, so that nothing is allocated per frame).
template <typename T>
const std::vector<T>& SortedById(const std::vector<T>& elements, std::vector<T>* scratch) {
  const auto by_id = [](const T& x, const T& y) { return x.id < y.id; };
  if (std::is_sorted(elements.begin(), elements.end(), by_id)) return elements;
  scratch->assign(elements.begin(), elements.end());
  std::sort(scratch->begin(), scratch->end(), by_id);
  return *scratch;
}

}  // namespace slt
