#pragma once
// The search behind dijkstra(): per-thread scratch, the heap and the search itself, a template on
// the path cost so that a cost the caller knows is called directly (inlined in the inner loop)
// instead of through std::function. Private to src/layout.

#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

#include "detail/surface.h"

namespace quadcage::layout::detail {
namespace search {

// Per-thread arrays of the searches, sized to the largest surface searched so far and left clean
// (arrival +inf, flags 0) after each search: a search that settles a few hundred vertices of a
// large surface then costs no pass over all of them. The layout runs thousands of such searches
// (around one corner, along one edge), and the orthogonal system's two directions run in threads.
struct SearchScratch {
    std::vector<double> arrival;
    std::vector<char> done, wanted;
    std::vector<int> reached;  // vertices given a distance, each once
    std::vector<std::pair<double, int>> heap;

    void reserve(int n) {
        if (static_cast<int>(done.size()) >= n) return;
        arrival.resize(n, std::numeric_limits<double>::infinity());
        done.resize(n, 0);
        wanted.resize(n, 0);
    }
};

// Puts a search's scratch back as it found it, also when the search throws.
class ScratchGuard {
public:
    ScratchGuard(SearchScratch& w, const PathSearch& q) : w_(w), q_(q) {}
    ScratchGuard(const ScratchGuard&) = delete;
    ScratchGuard& operator=(const ScratchGuard&) = delete;
    ~ScratchGuard() {
        for (int v : w_.reached) w_.done[v] = 0;
        for (const auto& [v, c] : q_.sources) w_.done[v] = 0;
        for (const auto& [v, c] : q_.targets) w_.arrival[v] = std::numeric_limits<double>::infinity();
        for (int v : q_.settle) w_.wanted[v] = 0;
        w_.reached.clear();
        w_.heap.clear();
    }

private:
    SearchScratch& w_;
    const PathSearch& q_;
};

// A 4-ary min-heap on (distance, vertex) pairs, in `a`. The pairs are totally ordered and a search
// never pushes one pair twice, so they leave in one order whatever the heap's shape: the order
// std::priority_queue gives, with half the levels to sift through.
using HeapItem = std::pair<double, int>;

inline void heap_push(std::vector<HeapItem>& a, const HeapItem& item) {
    size_t i = a.size();
    a.push_back(item);
    while (i > 0) {
        const size_t p = (i - 1) / 4;
        if (!(item < a[p])) break;
        a[i] = a[p];
        i = p;
    }
    a[i] = item;
}

inline HeapItem heap_pop(std::vector<HeapItem>& a) {
    const HeapItem top = a[0];
    const HeapItem last = a.back();
    a.pop_back();
    const size_t n = a.size();
    if (n == 0) return top;
    size_t i = 0;
    for (;;) {
        const size_t c = 4 * i + 1;
        if (c >= n) break;
        size_t m = c;
        const size_t end = std::min(c + 4, n);
        for (size_t k = c + 1; k < end; ++k)
            if (a[k] < a[m]) m = k;
        if (!(a[m] < last)) break;
        a[i] = a[m];
        i = m;
    }
    a[i] = last;
    return top;
}

template <class Cost>
PathResult run_dijkstra(const Surface& s, const PathSearch& q, const Cost& cost) {
    const int n = s.num_vertices();
    const double inf = std::numeric_limits<double>::infinity();
    thread_local SearchScratch w;
    w.reserve(n);
    const ScratchGuard guard(w, q);
    PathResult r;
    r.distance.assign(n, inf);
    r.parent_half_edge.assign(n, -1);
    std::vector<double>& arrival = w.arrival;
    std::vector<char>& done = w.done;
    for (auto [v, c] : q.targets) arrival[v] = std::min(arrival[v], c);
    // A heap on (distance, vertex) (heap_push, heap_pop).
    std::vector<HeapItem>& heap = w.heap;
    for (auto [v, c] : q.sources)
        if (c < r.distance[v]) {
            r.distance[v] = c;
            heap_push(heap, {c, v});
        }
    double best = inf;
    const bool settle = !q.settle.empty(), has_targets = !q.targets.empty();
    size_t still_wanted = 0;
    for (int v : q.settle)
        if (!w.wanted[v]) {
            w.wanted[v] = 1;
            ++still_wanted;
        }
    std::vector<int>& reached = w.reached;
    while (!heap.empty()) {
        const auto [d, v] = heap_pop(heap);
        if (done[v]) continue;
        if (d > q.max_distance) break;  // everything left is farther
        done[v] = 1;
        if (settle && w.wanted[v] && --still_wanted == 0) break;
        if (has_targets) {  // else arrival is +inf everywhere
            if (d >= best) break;
            if (arrival[v] < inf && d + arrival[v] < best) {
                best = d + arrival[v];
                r.target = v;
            }
        }
        const int h0 = s.out_half_edge(v);
        int h = h0;
        do {
            const int x = s.to(h);
            if (!done[x] && !(q.blocked && (*q.blocked)[x])) {
                const double nd = d + cost(h);
                if (nd < r.distance[x]) {
                    if (r.distance[x] == inf) reached.push_back(x);
                    r.distance[x] = nd;
                    r.parent_half_edge[x] = h;
                    heap_push(heap, {nd, x});
                }
            }
            h = s.rotate(h);
        } while (h != h0);
    }
    // A search stopped early leaves tentative distances behind: only settled vertices count.
    for (const auto& [v, c] : q.sources)
        if (!done[v]) r.distance[v] = inf;
    for (int x : reached)
        if (!done[x]) r.distance[x] = inf;
    r.target_cost = best;
    return r;
}


// One end of run_both_ways(): distances, the half-edge each vertex was reached by and settled
// flags, sized to the largest surface searched and left clean (+inf, -1, 0) after each search.
struct Front {
    std::vector<double> d;
    std::vector<int> parent;
    std::vector<char> done;
    std::vector<HeapItem> heap;
    std::vector<int> touched;  // vertices given a distance, each once

    void reserve(int n) {
        if (static_cast<int>(d.size()) >= n) return;
        d.resize(n, std::numeric_limits<double>::infinity());
        parent.resize(n, -1);
        done.resize(n, 0);
    }
    void note(int v, double c, int h) {  // a distance, not to be settled from
        if (d[v] == std::numeric_limits<double>::infinity()) touched.push_back(v);
        d[v] = c;
        parent[v] = h;
    }
    void reach(int v, double c, int h) {
        note(v, c, h);
        heap_push(heap, {c, v});
    }
    // The nearest vertex not settled yet, or -1.
    int top() {
        while (!heap.empty() && done[heap.front().second]) heap_pop(heap);
        return heap.empty() ? -1 : heap.front().second;
    }
    void clear() {
        for (int v : touched) d[v] = std::numeric_limits<double>::infinity(), parent[v] = -1, done[v] = 0;
        touched.clear();
        heap.clear();
    }
};

// The cheapest path from q.sources to q.targets (their costs, and q.blocked, as run_dijkstra()
// reads them; q.max_distance and q.settle are not read), searched from both ends at once: a forward
// search from the sources and a backward one from the targets (entering w from x costs
// cost(twin of x->w)). Each step settles the nearer of the two fronts' next vertices; the search
// stops once those two distances add up to no less than the cheapest path through a vertex both
// have reached. Where a search settles the vertices within distance D of its sources, the two
// settle those within about D/2 of either end: on a loop round a handle, searched from the two
// sides of one vertex, about half as many. Returns the path (a source first, a target last) and its
// cost in *total, or nothing. The cost is the same sum as run_dijkstra()'s target_cost, grouped
// from both ends, so it can differ from it in the last bits. Where two paths' costs are that close,
// either may be returned. Only paths cheaper than `bound` are looked for (nothing if there is none).
// `settled` (sized to the surface, zeroed; for unbounded searches) is for a search that fails: once
// the backward front has run out without meeting the forward one, the forward one runs on to its end,
// and every vertex it settled is marked, the vertices a one-way search from the sources settles when
// it finds no target.
template <class Cost>
std::vector<int> run_both_ways(const Surface& s, const PathSearch& q, const Cost& cost, double* total,
                               double bound = std::numeric_limits<double>::infinity(),
                               std::vector<char>* settled = nullptr) {
    const int n = s.num_vertices();
    thread_local Front f, b;
    f.reserve(n);
    b.reserve(n);
    struct Clean {
        ~Clean() { f.clear(), b.clear(); }
    } clean;
    for (auto [v, c] : q.sources)
        if (c < f.d[v]) f.reach(v, c, -1);
    for (auto [v, c] : q.targets)
        if (c < b.d[v]) b.reach(v, c, -1);
    double best = bound;
    int meet = -1;
    for (auto [v, c] : q.sources)
        if (f.d[v] + b.d[v] < best) best = f.d[v] + b.d[v], meet = v;
    for (;;) {
        const int fv = f.top(), bv = b.top();
        if (fv < 0) break;
        if (bv >= 0 ? f.d[fv] + b.d[bv] >= best : meet >= 0 || !settled) break;
        const bool forward = bv < 0 || f.d[fv] <= b.d[bv];  // bv < 0: the forward front alone, to its end
        Front& me = forward ? f : b;
        const Front& other = forward ? b : f;
        const int v = forward ? fv : bv;
        const double d = me.d[v];
        heap_pop(me.heap);
        me.done[v] = 1;
        const int h0 = s.out_half_edge(v);
        int h = h0;
        do {
            const int x = s.to(h);
            if (!me.done[x] && !(q.blocked && (*q.blocked)[x])) {
                const double nd = d + (forward ? cost(h) : cost(s.twin(h)));
                if (nd < me.d[x]) {
                    me.reach(x, nd, h);
                    if (nd + other.d[x] < best) best = nd + other.d[x], meet = x;
                }
            } else if (!forward && !me.done[x] && f.parent[x] < 0 && f.d[x] < bound) {
                // A blocked source: a path may start there (as run_dijkstra() lets it), but not
                // pass through it, so the backward front notes it without going on from it.
                const double nd = d + cost(s.twin(h));
                if (nd < me.d[x]) {
                    me.note(x, nd, h);
                    if (nd + f.d[x] < best) best = nd + f.d[x], meet = x;
                }
            }
            h = s.rotate(h);
        } while (h != h0);
    }
    std::vector<int> path;
    if (meet < 0) {
        if (settled)
            for (int v : f.touched)
                if (f.done[v]) (*settled)[v] = 1;
        return path;
    }
    for (int v = meet; f.parent[v] >= 0;) path.push_back(v = s.from(f.parent[v]));
    std::reverse(path.begin(), path.end());
    path.push_back(meet);
    for (int v = meet; b.parent[v] >= 0;) path.push_back(v = s.from(b.parent[v]));
    *total = best;
    return path;
}

}  // namespace search

/// dijkstra() with the path cost `cost` (search.cost is not used): the same search, with a cost
/// that it calls directly.
template <class Cost>
PathResult dijkstra_with(const Surface& s, const PathSearch& search, const Cost& cost) {
    return search::run_dijkstra(s, search, cost);
}

}  // namespace quadcage::layout::detail
