#include "box_tree.hpp"

#include <algorithm>

namespace maxslice::plan::detail {
namespace {

constexpr std::uint32_t kLeafSize = 8;

}  // namespace

BoxTree::BoxTree(const std::vector<core::Vec3d>& lo, const std::vector<core::Vec3d>& hi) {
    const std::size_t n = lo.size();
    std::vector<core::Vec3d> mid(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (lo[i].x <= hi[i].x && lo[i].y <= hi[i].y && lo[i].z <= hi[i].z) {
            items_.push_back(static_cast<std::uint32_t>(i));
            mid[i] = (lo[i] + hi[i]) * 0.5;
        }
    }
    if (items_.empty()) return;
    // Depth: a median split halves the items, so the depth stays below log2(n) + 1 and the
    // visit's fixed stack (64) never overflows.
    struct Job {
        std::size_t node;
        std::uint32_t begin, end;
    };
    nodes_.reserve(2 * (items_.size() / kLeafSize + 1));
    nodes_.push_back({});
    std::vector<Job> stack{{0, 0, static_cast<std::uint32_t>(items_.size())}};
    while (!stack.empty()) {
        const Job job = stack.back();
        stack.pop_back();
        core::Box3d box, centres;
        for (std::uint32_t i = job.begin; i < job.end; ++i) {
            box.add(lo[items_[i]]);
            box.add(hi[items_[i]]);
            centres.add(mid[items_[i]]);
        }
        nodes_[job.node].lo = box.min;
        nodes_[job.node].hi = box.max;
        if (job.end - job.begin <= kLeafSize) {
            nodes_[job.node].first = job.begin;
            nodes_[job.node].count = job.end - job.begin;
            continue;
        }
        const core::Vec3d ext = centres.size();
        const int k = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
        const std::uint32_t m = job.begin + (job.end - job.begin) / 2;
        std::nth_element(items_.begin() + job.begin, items_.begin() + m, items_.begin() + job.end,
                         [&](std::uint32_t a, std::uint32_t b) {
                             const double ca = mid[a][k], cb = mid[b][k];
                             return ca < cb || (ca == cb && a < b);
                         });
        const auto child = static_cast<std::uint32_t>(nodes_.size());
        nodes_[job.node].first = child;
        nodes_[job.node].count = 0;
        nodes_.push_back({});
        nodes_.push_back({});
        stack.push_back({child, job.begin, m});
        stack.push_back({child + 1, m, job.end});
    }
}

}  // namespace maxslice::plan::detail
