#pragma once
// A bounding volume hierarchy over axis-aligned boxes (mm, part frame): the planner finds the
// triangles a plane may cross with it, the build order the layers a nozzle may reach.

#include <cstdint>
#include <vector>

#include "maxslice/core/vec3.hpp"

namespace maxslice::plan::detail {

/// Boxes given by index, grouped top-down at the median of their centres along the widest
/// axis; leaves hold up to 8 boxes. Built in O(n log n); deterministic.
class BoxTree {
public:
    BoxTree() = default;
    /// lo[i], hi[i]: box i (lo <= hi; an item with lo > hi on some axis is never reported).
    BoxTree(const std::vector<core::Vec3d>& lo, const std::vector<core::Vec3d>& hi);

    /// Calls leaf(i) for every item i inside a node the test accepts on the way down:
    /// node_test(lo, hi) -> bool for a node's box (its items' union). Items come in tree
    /// order, not index order; leaf does its own exact test.
    template <class NodeTest, class Leaf>
    void visit(NodeTest&& node_test, Leaf&& leaf) const {
        if (nodes_.empty()) return;
        std::uint32_t stack[64];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& node = nodes_[stack[--top]];
            if (!node_test(node.lo, node.hi)) continue;
            if (node.count == 0) {
                stack[top++] = node.first;
                stack[top++] = node.first + 1;
                continue;
            }
            for (std::uint32_t i = node.first; i < node.first + node.count; ++i) leaf(items_[i]);
        }
    }

private:
    struct Node {
        core::Vec3d lo;
        core::Vec3d hi;
        std::uint32_t first = 0;  // leaves: items_[first, first + count)
        std::uint32_t count = 0;  // 0: an inner node with children `first` and `first + 1`
    };
    std::vector<Node> nodes_;
    std::vector<std::uint32_t> items_;
};

}  // namespace maxslice::plan::detail
