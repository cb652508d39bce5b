#pragma once
// Disjoint sets over indices 0..n-1 whose root is always the lowest index of its set
// (deterministic representatives), with path halving.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace maxslice::core {

class UnionFind {
public:
    explicit UnionFind(std::size_t n) : parent_(n) {
        for (std::size_t i = 0; i < n; ++i) parent_[i] = static_cast<std::uint32_t>(i);
    }
    [[nodiscard]] std::size_t size() const { return parent_.size(); }
    std::uint32_t find(std::uint32_t v) {
        while (parent_[v] != v) {
            parent_[v] = parent_[parent_[v]];
            v = parent_[v];
        }
        return v;
    }
    void unite(std::uint32_t a, std::uint32_t b) {
        a = find(a);
        b = find(b);
        if (a < b) {
            parent_[b] = a;
        } else if (b < a) {
            parent_[a] = b;
        }
    }
    /// A hint that v's entry is about to be written (long runs over large sets).
    void prefetch(std::uint32_t v) const { __builtin_prefetch(&parent_[v], 1); }

private:
    std::vector<std::uint32_t> parent_;
};

}  // namespace maxslice::core
