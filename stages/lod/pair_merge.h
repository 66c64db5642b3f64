// Greedy pairwise agglomeration with a spatial index, shared by leaf collapse (FSA) and needle
// merging (E5), and the binary forest it records.
//
// Seeds: Remolar et al. (FSA/VDF), §3–4: "From the list of the active leaves, the algorithm
// repeatedly selects a pair that minimizes the error function... the structure is made up of a
// forest of binary trees"; Zhang et al. 2017, §5.5: needles merged pairwise, "an Octree data
// structure is used to improve finding the most similar needles".
//
// Algorithm: every active element keeps its best partner among the active elements in the
// neighbouring cells of a uniform grid (the spatial index; the search widens ring by ring until
// a candidate is found); a priority queue holds (cost, a, b) and is popped lowest first; an entry
// naming a merged element is stale: if its first element is still active, that element's best
// partner is recomputed and pushed again. The grid is rebuilt with twice the cell size whenever
// the active count halves, so cells stay populated. Ties break on element ids: deterministic.
// The queue pops pairs in cost order among the pairs it knows (each element's best within its
// neighbourhood), an approximation of the global minimum that docs/stages/lod.md states.
//
// The candidate set of a search is fixed: the first kMaxCandidates active elements (other than
// the searching one) in visiting order — own cell, then the cells of ring 1 in (dx, dy, dz)
// order, wider rings only while none was found; a cell lists its elements by ascending id. The
// partner is the candidate of lowest (cost, id). Which candidates get their cost evaluated is an
// implementation matter: a candidate that provably costs more than the best so far is skipped.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "libs/tree/vec3.h"

namespace sylva::lod {

// The binary forest: elements 0..n_leaves-1 are the originals; element n_leaves + i is made by
// merge i from left[i'] and right[i'] (i' = element index). error is monotone towards the roots.
struct BinaryForest {
  std::size_t original = 0;               // number of original elements
  std::vector<std::int32_t> parent;       // per element, -1 for roots
  std::vector<std::int32_t> left, right;  // per element, -1 for originals
  std::vector<double> error;              // per element, m; 0 for originals

  std::size_t size() const { return parent.size(); }
  // Active elements after the first `merges` merges (merge order), ascending ids.
  std::vector<std::uint32_t> cut_by_merges(std::size_t merges) const;
  // Active elements when every element with error <= max_error is used: the roots of the
  // subforest of elements with error <= max_error (an element is active when its error fits and
  // its parent's does not, or it has no parent). Ascending ids.
  std::vector<std::uint32_t> cut_by_error(double max_error) const;
  // Active elements for `count` elements (clamped to [roots, original]).
  std::vector<std::uint32_t> cut_by_count(std::size_t count) const;
  std::size_t roots() const;
};

// The frame of the agglomeration's uniform grid: cell (x, y, z) = floor((c - lo) / cell) of an
// element's centre c, and a dense box of cells that grows when an element lands outside it
// (merged leaves can: their centres are means of original corners, not of original centres).
class GridFrame {
 public:
  using Coord = std::array<std::int64_t, 3>;

  // Sets the origin and cell size; `lo_cell`..`hi_cell` is the expected range of cells.
  void set(tree::Vec3 lo, double cell, Coord lo_cell, Coord hi_cell);
  double cell_size() const { return cell_; }
  Coord cell_of(tree::Vec3 c) const {
    return {static_cast<std::int64_t>(std::floor((c.x - lo_.x) / cell_)),
            static_cast<std::int64_t>(std::floor((c.y - lo_.y) / cell_)),
            static_cast<std::int64_t>(std::floor((c.z - lo_.z) / cell_))};
  }
  // A lower bound of the distance from p to any centre that cell_of() puts in cell k (the cell
  // box widened by a rounding margin).
  double distance_to_cell(tree::Vec3 p, Coord k) const;

 protected:
  bool inside(const Coord& k) const {
    for (int i = 0; i < 3; ++i)
      if (k[i] < origin_[i] || k[i] >= origin_[i] + dims_[i]) return false;
    return true;
  }
  std::size_t index(const Coord& k) const {
    return (static_cast<std::size_t>(k[0] - origin_[0]) * static_cast<std::size_t>(dims_[1]) +
            static_cast<std::size_t>(k[1] - origin_[1])) *
               static_cast<std::size_t>(dims_[2]) +
           static_cast<std::size_t>(k[2] - origin_[2]);
  }
  std::size_t cell_count() const { return static_cast<std::size_t>(dims_[0] * dims_[1] * dims_[2]); }
  // The box (origin, dims) grown to hold k, with two spare cells beyond it.
  static void grow_to(const Coord& k, Coord& origin, Coord& dims);

  tree::Vec3 lo_;
  double cell_ = 1;
  Coord origin_{0, 0, 0}, dims_{0, 0, 0};
};

// The grid's contents: per cell, its active elements by ascending id with a copy of their keys,
// in one array ordered by cell (each cell a run of slots with spare ones at its end). The search
// reads a cell's candidates from contiguous memory instead of chasing ids into the key array.
// Occupied cells hold tens of elements (foliage is a shell, not the bounding box), and merges
// take elements from the front of a cell (the candidates are its first ids) while merged ones
// join at the back, so erase leaves a tombstone (kDead) instead of shifting the cell; a cell is
// compacted when its tombstones outnumber a quarter of its elements (amortised O(1) per erase).
template <class Key>
class CellGrid : public GridFrame {
 public:
  static constexpr std::uint32_t kDead = 0xffffffffu;
  struct Cell {
    const std::uint32_t* ids = nullptr;  // slots: element ids in ascending order, or kDead
    const Key* keys = nullptr;
    std::uint32_t slots = 0;  // slots to scan
    std::uint32_t live = 0;   // elements among them
  };

  // Fills the grid (frame set by set()) with `ids` (ascending); elems[id].key and
  // elems[id].cell (= cell_of(centre)) are read.
  template <class Elem>
  void fill(const std::vector<std::uint32_t>& ids, const std::vector<Elem>& elems) {
    for (std::uint32_t id : ids)
      if (!inside(elems[id].cell)) grow_to(elems[id].cell, origin_, dims_);
    runs_.assign(cell_count(), {});
    for (std::uint32_t id : ids) ++runs_[index(elems[id].cell)].live;
    lay_out();
    for (std::uint32_t id : ids) append(runs_[index(elems[id].cell)], id, elems[id].key);
  }
  // Appends `id` (larger than every id in the grid) to cell k.
  void insert(std::uint32_t id, const Key& key, const Coord& k) {
    if (!inside(k)) {
      Coord origin = origin_, dims = dims_;
      grow_to(k, origin, dims);
      relayout(origin, dims);
    } else if (Run& r = runs_[index(k)]; r.used == r.end - r.start) {
      if (r.live < r.used) {
        compact(r);
      } else {
        relayout(origin_, dims_);
      }
    }
    Run& r = runs_[index(k)];
    append(r, id, key);
    ++r.live;
  }
  // Removes `id` from cell k; the order of the others is kept.
  void erase(std::uint32_t id, const Coord& k) {
    Run& r = runs_[index(k)];
    std::uint32_t* ids = ids_.data() + r.start;
    std::uint32_t i = 0;
    while (ids[i] != id) ++i;
    ids[i] = kDead;
    --r.live;
    while (r.used > 0 && ids[r.used - 1] == kDead) --r.used;
    if (r.used - r.live > 4 + r.live / 4) compact(r);
  }
  // fn(k, cell) for every cell of the box, in memory order.
  template <class Fn>
  void for_each_cell(Fn fn) const {
    for (std::int64_t x = origin_[0]; x < origin_[0] + dims_[0]; ++x)
      for (std::int64_t y = origin_[1]; y < origin_[1] + dims_[1]; ++y)
        for (std::int64_t z = origin_[2]; z < origin_[2] + dims_[2]; ++z) fn(Coord{x, y, z}, cell(x, y, z));
  }
  // The elements of cell (x, y, z); empty outside the box.
  Cell cell(std::int64_t x, std::int64_t y, std::int64_t z) const {
    const Coord k{x, y, z};
    if (!inside(k)) return {};
    const Run& r = runs_[index(k)];
    return {ids_.data() + r.start, keys_.data() + r.start, r.used, r.live};
  }

 private:
  // A cell's slots [start, end), the first `used` of them in use (tombstones included), `live`
  // elements among them: one record, so a cell costs one cache miss to find.
  struct Run {
    std::uint32_t start = 0, end = 0, used = 0, live = 0;
  };
  // Spare slots per cell: a merged element usually lands in a cell its pair left, so cells grow
  // slowly; a full cell is compacted or, with no tombstone, the array is re-laid out (same
  // contents, same order).
  static std::uint32_t capacity(std::uint32_t count) { return count + count / 2 + 2; }

  void append(Run& r, std::uint32_t id, const Key& key) {
    ids_[r.start + r.used] = id;
    keys_[r.start + r.used] = key;
    ++r.used;
  }
  // Slots for runs_[c].live elements (per cell) plus spare ones; the slots are unused.
  void lay_out() {
    std::uint32_t at = 0;
    for (Run& r : runs_) {
      r.start = at;
      at += capacity(r.live);
      r.end = at;
      r.used = 0;
    }
    ids_.assign(at, kDead);
    keys_.assign(at, Key{});
  }
  // Drops the tombstones of run r, keeping the order.
  void compact(Run& r) {
    std::uint32_t* ids = ids_.data() + r.start;
    Key* keys = keys_.data() + r.start;
    std::uint32_t to = 0;
    for (std::uint32_t from = 0; from < r.used; ++from) {
      if (ids[from] == kDead) continue;
      ids[to] = ids[from];
      keys[to] = keys[from];
      ++to;
    }
    for (std::uint32_t i = to; i < r.used; ++i) ids[i] = kDead;
    r.used = to;
  }
  // Moves every cell's elements into a new box and fresh spare slots.
  void relayout(const Coord& origin, const Coord& dims) {
    const Coord old_origin = origin_, old_dims = dims_;
    const std::vector<Run> old_runs = std::move(runs_);
    const std::vector<std::uint32_t> old_ids = std::move(ids_);
    const std::vector<Key> old_keys = std::move(keys_);
    origin_ = origin;
    dims_ = dims;
    runs_.assign(cell_count(), {});
    auto for_each_old = [&](auto fn) {
      for (std::int64_t x = 0; x < old_dims[0]; ++x)
        for (std::int64_t y = 0; y < old_dims[1]; ++y)
          for (std::int64_t z = 0; z < old_dims[2]; ++z) {
            const auto from = static_cast<std::size_t>((x * old_dims[1] + y) * old_dims[2] + z);
            fn(old_runs[from], runs_[index({old_origin[0] + x, old_origin[1] + y, old_origin[2] + z})]);
          }
    };
    for_each_old([](const Run& from, Run& to) { to.live = from.live; });
    lay_out();
    for_each_old([&](const Run& from, Run& to) {
      for (std::uint32_t i = from.start; i < from.start + from.used; ++i)
        if (old_ids[i] != kDead) append(to, old_ids[i], old_keys[i]);
    });
  }

  std::vector<Run> runs_;           // per cell
  std::vector<std::uint32_t> ids_;  // slots
  std::vector<Key> keys_;           // slots, parallel to ids_
};

// The agglomeration's priority queue: (cost, a, b), lowest first, ties on a then b. Entries are
// distinct (an element has at most one entry at a time), so any exact min-queue pops them in the
// same order. The queue holds n to 3n entries (stale ones included) and outgrows the caches, so
// it has two parts: `near_`, a 4-ary heap of every entry below `limit_`, small enough to stay in
// cache (its four children share one 64-byte line: 16-byte entries, the array starting 3 entries
// into a line-aligned block); and `far_`, an unsorted array of the entries at or above `limit_`
// (a push there is an append). When `near_` runs dry, the smallest eighth of `far_` (at least
// kRefill) moves over by one nth_element pass.
class PairQueue {
 public:
  struct Entry {
    double cost;
    std::uint32_t a, b;
    bool operator<(const Entry& o) const {
      if (cost != o.cost) return cost < o.cost;
      if (a != o.a) return a < o.a;
      return b < o.b;
    }
  };
  bool empty() const { return size_ == 0 && far_.empty(); }
  // The lowest entry; the queue must not be empty.
  const Entry& top() {
    if (size_ == 0) refill();
    return at(0);
  }
  void push(const Entry& e) {
    if (unbounded_ || e < limit_) {
      push_near(e);
    } else {
      far_.push_back(e);
    }
  }
  Entry pop() {
    if (size_ == 0) refill();
    const Entry top = at(0);
    const Entry last = at(--size_);
    const std::size_t n = size_;
    if (n == 0) return top;
    std::size_t i = 0;
    for (;;) {
      const std::size_t first = 4 * i + 1;
      if (first >= n) break;
      std::size_t least = first;
      const std::size_t end = std::min(first + 4, n);
      for (std::size_t c = first + 1; c < end; ++c)
        if (at(c) < at(least)) least = c;
      if (!(at(least) < last)) break;
      at(i) = at(least);
      i = least;
    }
    at(i) = last;
    return top;
  }

 private:
  static constexpr std::size_t kOffset = 3;  // children 4i+1..4i+4 land on block i+1
  static constexpr std::size_t kRefill = 4096;
  struct alignas(64) Block {
    Entry e[4];
  };
  Entry& at(std::size_t i) { return blocks_[(i + kOffset) / 4].e[(i + kOffset) % 4]; }

  void push_near(const Entry& e) {
    if ((size_ + kOffset) / 4 + 1 > blocks_.size()) blocks_.resize(2 * blocks_.size() + 16);
    std::size_t i = size_++;
    while (i > 0) {
      const std::size_t up = (i - 1) / 4;
      if (!(e < at(up))) break;
      at(i) = at(up);
      i = up;
    }
    at(i) = e;
  }
  // Moves the smallest entries of far_ into the (empty) heap; limit_ becomes the smallest entry
  // left behind.
  void refill() {
    const std::size_t take = std::max(kRefill, far_.size() / 8);
    if (take >= far_.size()) {
      unbounded_ = true;
    } else {
      std::nth_element(far_.begin(), far_.begin() + static_cast<std::ptrdiff_t>(take), far_.end());
      limit_ = far_[take];
    }
    const std::size_t moved = std::min(take, far_.size());
    for (std::size_t i = 0; i < moved; ++i) push_near(far_[i]);
    far_.erase(far_.begin(), far_.begin() + static_cast<std::ptrdiff_t>(moved));
  }

  std::vector<Block> blocks_;  // near_: the heap
  std::size_t size_ = 0;
  std::vector<Entry> far_;
  Entry limit_{0, 0, 0};    // near_ < limit_ <= far_ (unless unbounded_)
  bool unbounded_ = false;  // far_ empty from the last refill on: everything goes near
};

// Runs the agglomeration. `items` holds the originals on entry and every merged element
// appended on exit. The metric caches what the search reads of an element:
//   metric.key(item) -> Key              a small copy of what cost() reads, one per element;
//   metric.center(key) -> Vec3           places the element in the grid;
//   metric.cost(a, b, bound) -> double   cost(a, b) >= 0, lower first (+inf: never merges); when
//                                        the cost exceeds `bound` it may return any value above
//                                        `bound` instead (an early exit: such a candidate can
//                                        never be the partner, as the best only falls);
//   metric.lower_bound(a, d) -> double   <= cost(a, b) for every b whose centre is >= d from a's.
// merge(a, b, err_a, err_b) returns the new item and its error.
template <class Item, class Metric, class MergeFn>
BinaryForest agglomerate(std::vector<Item>& items, const Metric& metric, MergeFn merge) {
  using tree::Vec3;
  using Key = decltype(metric.key(items[0]));
  const std::size_t n = items.size();
  BinaryForest f;
  f.original = n;
  f.parent.assign(n, -1);
  f.left.assign(n, -1);
  f.right.assign(n, -1);
  f.error.assign(n, 0.0);
  if (n < 2) return f;
  items.reserve(2 * n);
  // Per element, its key and its grid cell in one record: the search reads the key for ~24
  // candidates (from the grid's copies) and its own record once; the items themselves are
  // large (a leaf quad is 160 bytes).
  struct Elem {
    Key key;
    GridFrame::Coord cell;
    double error;  // copy of f.error: a merge reads it with the cell
  };
  std::vector<Elem> elems;
  elems.reserve(2 * n);
  for (const Item& it : items) elems.push_back({metric.key(it), {}, 0.0});
  std::vector<char> alive(n, 1);
  std::size_t alive_count = n;
  // Grid set-up from the bounding box: about two elements per cell.
  Vec3 lo = metric.center(elems[0].key), hi = lo;
  for (const Elem& e : elems) {
    const Vec3 c = metric.center(e.key);
    lo = {std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z)};
    hi = {std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z)};
  }
  const Vec3 ext = hi - lo;
  // Flat or linear sets: no axis thinner than 1/64 of the largest, and at most 64 cells across,
  // so a widening search never walks more than 65 rings.
  const double max_extent = std::max({ext.x, ext.y, ext.z, 1e-6});
  const double floor_ext = max_extent / 64;
  const double vol = std::max(ext.x, floor_ext) * std::max(ext.y, floor_ext) * std::max(ext.z, floor_ext);
  double cell = std::max(floor_ext, std::cbrt(2 * vol / static_cast<double>(n)));
  CellGrid<Key> grid;
  std::vector<std::uint32_t> active;
  std::size_t built_at = n;
  auto rebuild = [&]() {
    active.clear();
    for (std::uint32_t i = 0; i < items.size(); ++i)
      if (alive[i]) active.push_back(i);
    // The box of the originals' cells (merged elements outside it grow the grid).
    const GridFrame::Coord top{static_cast<std::int64_t>(std::floor(ext.x / cell)),
                               static_cast<std::int64_t>(std::floor(ext.y / cell)),
                               static_cast<std::int64_t>(std::floor(ext.z / cell))};
    grid.set(lo, cell, {0, 0, 0}, top);
    for (std::uint32_t i : active) elems[i].cell = grid.cell_of(metric.center(elems[i].key));
    grid.fill(active, elems);
    built_at = alive_count;
  };
  rebuild();
  PairQueue queue;
  // Best partner of `id` among the candidate set (file comment). At most kMaxCandidates active
  // elements per search: clustered sets (needles on a twig) would otherwise put hundreds into
  // one cell. The minimum over (cost, id) does not depend on the evaluation order, so a cell
  // whose lower bound already exceeds the best so far is counted but not evaluated, and the
  // metric may stop early on a candidate it knows to be worse (`bound`).
  constexpr int kMaxCandidates = 24;
  // A relative margin on cell bounds: the bound and the cost round differently.
  constexpr double kBoundMargin = 1 - 1e-9;
  auto push_best_at = [&](std::uint32_t id, const Key& key, const GridFrame::Coord& own) {
    const Vec3 c = metric.center(key);
    double best = std::numeric_limits<double>::infinity();
    std::uint32_t best_id = id;
    int seen = 0;
    auto visit = [&](std::int64_t x, std::int64_t y, std::int64_t z, bool own_cell) {
      if (seen >= kMaxCandidates) return;
      const typename CellGrid<Key>::Cell list = grid.cell(x, y, z);
      if (list.live == 0) return;
      if (!own_cell && std::isfinite(best) &&
          metric.lower_bound(key, grid.distance_to_cell(c, {x, y, z})) * kBoundMargin > best) {
        // Every candidate here is worse than the best so far: only count them.
        seen = std::min(kMaxCandidates, seen + static_cast<int>(list.live));
        return;
      }
      for (std::uint32_t i = 0; i < list.slots; ++i) {
        const std::uint32_t other = list.ids[i];
        if (other == id || other == CellGrid<Key>::kDead) continue;
        if (seen >= kMaxCandidates) return;
        ++seen;
        const double cost = metric.cost(key, list.keys[i], best);
        if (cost < best || (cost == best && other < best_id)) {
          best = cost;
          best_id = other;
        }
      }
    };
    visit(own[0], own[1], own[2], true);
    const auto max_ring = static_cast<std::int64_t>(std::ceil(max_extent / grid.cell_size())) + 1;
    for (std::int64_t ring = 1; ring <= max_ring && seen < kMaxCandidates; ++ring) {
      for (std::int64_t dx = -ring; dx <= ring; ++dx)
        for (std::int64_t dy = -ring; dy <= ring; ++dy)
          for (std::int64_t dz = -ring; dz <= ring; ++dz) {
            // Only the shell of this ring (the inside was searched before).
            if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != ring) continue;
            visit(own[0] + dx, own[1] + dy, own[2] + dz, false);
          }
      if (seen > 0) break;  // ring 1 always, wider rings only until something is found
    }
    if (seen > 0 && std::isfinite(best)) queue.push({best, id, best_id});
  };
  auto push_best = [&](std::uint32_t id) { push_best_at(id, elems[id].key, elems[id].cell); };
  // The first searches go cell by cell, reading each element's key from its cell's slots: the
  // neighbourhood stays in cache from one element to the next. The order of the pushes does not
  // matter (entries are distinct, the queue pops them in their order).
  grid.for_each_cell([&](const GridFrame::Coord& k, const typename CellGrid<Key>::Cell& list) {
    for (std::uint32_t i = 0; i < list.slots; ++i)
      if (list.ids[i] != CellGrid<Key>::kDead) push_best_at(list.ids[i], list.keys[i], k);
  });
  while (!queue.empty() && alive_count > 1) {
    const PairQueue::Entry e = queue.pop();
    // The next entry is usually the current top (new entries rarely cost less): start loading
    // what it will read while this one is processed.
    if (!queue.empty()) {
      const PairQueue::Entry& next = queue.top();
      __builtin_prefetch(&elems[next.a]);
      __builtin_prefetch(&items[next.a]);
      __builtin_prefetch(&elems[next.b]);
      __builtin_prefetch(&items[next.b]);
    }
    if (!alive[e.a]) continue;
    if (!alive[e.b]) {
      push_best(e.a);
      continue;
    }
    auto [item, err] = merge(items[e.a], items[e.b], elems[e.a].error, elems[e.b].error);
    const auto id = static_cast<std::uint32_t>(items.size());
    const double error = std::max({err, elems[e.a].error, elems[e.b].error});
    items.push_back(std::move(item));
    elems.push_back({metric.key(items.back()), {}, error});
    alive.push_back(1);
    alive[e.a] = alive[e.b] = 0;
    alive_count -= 1;
    f.left.push_back(static_cast<std::int32_t>(e.a));
    f.right.push_back(static_cast<std::int32_t>(e.b));
    f.error.push_back(error);
    if (alive_count * 2 < built_at) {
      cell *= 2;
      rebuild();
    } else {
      // Merged elements leave the grid at once, so a search never walks over dead ids.
      grid.erase(e.a, elems[e.a].cell);
      grid.erase(e.b, elems[e.b].cell);
      elems[id].cell = grid.cell_of(metric.center(elems[id].key));
      grid.insert(id, elems[id].key, elems[id].cell);
    }
    push_best(id);
  }
  // Parents last, from the children (one pass instead of two random writes per merge).
  f.parent.resize(items.size(), -1);
  for (std::size_t z = n; z < items.size(); ++z) {
    f.parent[static_cast<std::size_t>(f.left[z])] = static_cast<std::int32_t>(z);
    f.parent[static_cast<std::size_t>(f.right[z])] = static_cast<std::int32_t>(z);
  }
  return f;
}

}  // namespace sylva::lod
