// One layer per piece and the hierarchy graph (docs/method.md section 6): within a region
// each layer is deposited on the pieces of the slice below it overlaps; a sideways region's
// first layer on the layers of other regions it touches across its base plane.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <queue>
#include <utility>

#include <tbb/parallel_for.h>

#include "cell.hpp"
#include "maxslice/core/units.hpp"
#include "planner_state.hpp"

namespace maxslice::plan {
namespace detail {
namespace {

using geom2d::Paths2;

// A first layer rests on a layer of another region when their footprints on its base plane
// overlap by at least this share of a track width squared.
constexpr double kContactAreaShare = 0.05;
// ... or, for a piece smaller than that, by this share of its own area.
constexpr double kSmallPieceShare = 0.5;
// A layer whose wires lie this far (mm) outside the strip behind a base plane has nothing in
// it: far beyond the rounding of the strip's trace to micrometres.
constexpr double kStripSlackMm = 0.01;
// Slack (um) of the box test before an overlap is measured: beyond the rounding of offsets.
constexpr std::int64_t kNearSlackUm = 10;

// An axis-aligned box in the part frame (mm).
struct Box3 {
    double lo[3] = {1e300, 1e300, 1e300};
    double hi[3] = {-1e300, -1e300, -1e300};
};

Box3 box_of(const Layer& l) {
    Box3 b;
    for (const geom2d::WireNode& n : l.wires.nodes) {
        for (const geom2d::Point2& p : n.wire) {
            const core::Vec3d x = l.plane.to_3d(p);
            const double c[3] = {x.x, x.y, x.z};
            for (int k = 0; k < 3; ++k) {
                b.lo[k] = std::min(b.lo[k], c[k]);
                b.hi[k] = std::max(b.hi[k], c[k]);
            }
        }
    }
    return b;
}

// An axis-aligned box in a plane frame (um).
struct Box2 {
    geom2d::Point2 lo{std::numeric_limits<std::int64_t>::max(),
                      std::numeric_limits<std::int64_t>::max()};
    geom2d::Point2 hi{std::numeric_limits<std::int64_t>::min(),
                      std::numeric_limits<std::int64_t>::min()};
};

Box2 box2_of(const geom2d::Paths2& paths) {
    Box2 b;
    for (const geom2d::Path2& path : paths) {
        for (const geom2d::Point2& p : path) {
            b.lo = {std::min(b.lo.x, p.x), std::min(b.lo.y, p.y)};
            b.hi = {std::max(b.hi.x, p.x), std::max(b.hi.y, p.y)};
        }
    }
    return b;
}

// The edges of a plan's hierarchy graph, with the boxes and marks the searches reuse.
class GraphBuilder {
public:
    explicit GraphBuilder(Plan& plan) : plan_(plan), s_(plan.settings) {}

    // The hierarchy graph (METHOD.md section 6).
    core::Result<void> run() {
        std::vector<Layer>& layers = plan_.layers;
        boxes_.resize(layers.size());
        tbb::parallel_for(std::size_t{0}, layers.size(),
                          [&](std::size_t i) { boxes_[i] = box_of(layers[i]); });
        const auto link = [&](int from, int to) {
            layers[static_cast<std::size_t>(from)].children.push_back(to);
            layers[static_cast<std::size_t>(to)].parents.push_back(from);
        };
        // Within each region (and from a continuation's seed): each piece on the pieces of
        // the slice below whose projection it overlaps. Pure geometry, so the pairs are
        // tested in parallel; these edges are all made before the first layers' contacts,
        // whose cycle check and passes (link_first_layers) rely on them.
        std::vector<LinkTask> tasks;
        for (const Region& r : plan_.regions) {
            if (r.layers.empty()) continue;
            std::vector<int> below;
            for (const Decision& d : plan_.decisions) {
                if ((d.continuation == r.id && d.continuation != d.region) ||
                    std::find(d.far_regions.begin(), d.far_regions.end(), r.id) !=
                        d.far_regions.end()) {
                    below = step_of(d.layer);
                }
            }
            for (std::size_t i = 0; i < r.layers.size();) {
                std::size_t j = i;
                const int step = layers[static_cast<std::size_t>(r.layers[i])].index_in_region;
                while (j < r.layers.size() &&
                       layers[static_cast<std::size_t>(r.layers[j])].index_in_region == step) {
                    ++j;
                }
                const std::vector<int> here(r.layers.begin() + static_cast<std::ptrdiff_t>(i),
                                            r.layers.begin() + static_cast<std::ptrdiff_t>(j));
                for (const int b : below) tasks.push_back({r.id, b, here, {}});
                below = here;
                i = j;
            }
        }
        tbb::parallel_for(std::size_t{0}, tasks.size(), [&](std::size_t k) { rests_on(tasks[k]); });
        for (const LinkTask& t : tasks) {
            for (std::size_t k = 0; k < t.uppers.size(); ++k) {
                if (t.rests[k] != 0) link(t.lower, t.uppers[k]);
            }
        }
        // A sideways region's first layer: on the layers of other regions across its base.
        std::vector<Contacts> contacts;
        for (const Region& r : plan_.regions) {
            if (r.layers.empty() || r.parent < 0 ||
                r.direction == plan_.regions[static_cast<std::size_t>(r.parent)].direction) {
                continue;
            }
            const std::vector<int> others = others_of(r.id);
            // Every piece of the first slice (the slice may cut the part in several).
            const int first_step =
                layers[static_cast<std::size_t>(r.layers.front())].index_in_region;
            for (const int id : r.layers) {
                const Layer& first = layers[static_cast<std::size_t>(id)];
                if (first.index_in_region != first_step) break;
                // Empty sections between the base plane and the first layer: nothing across
                // the base plane touches it (a body beside the part, reached across the air).
                if (first.after_gap) continue;
                contacts.push_back(contacts_across(first, r.base.origin, r.direction, others));
            }
        }
        // A piece of any later slice that rests on nothing of its own region (material the
        // region's cell holds whose base lies in another cell: a wall cut at a slant by a
        // split plane starts as a tip there) rests, like a first layer, on the layers of
        // other regions just behind its own bottom plane along its region's direction.
        const std::vector<int> orphans = orphan_pieces(contacts);
        for (const int id : orphans) {
            const Layer& o = layers[static_cast<std::size_t>(id)];
            const core::Vec3d bottom =
                o.plane.origin + o.plane.normal * (o.span.bottom - o.span.cut);
            Contacts c = contacts_across(o, bottom, o.plane.normal, others_of(o.region));
            if (!c.others.empty()) contacts.push_back(std::move(c));
        }
        link_first_layers(contacts);
        for (Layer& l : layers) {
            std::sort(l.parents.begin(), l.parents.end());
            std::sort(l.children.begin(), l.children.end());
            if (l.parents.empty() && !l.on_plate) plan_.unsupported_layers.push_back(l.id);
        }
        if (topological_order(plan_).size() != layers.size()) {
            return core::fail(core::ErrorCode::kInternal,
                              "the hierarchy graph has a cycle (a bug in maxslice)", "planning");
        }
        return {};
    }

private:
    // The pieces of region rid's slice that layer id belongs to.
    std::vector<int> step_of(int id) const {
        const Layer& l = plan_.layers[static_cast<std::size_t>(id)];
        std::vector<int> out;
        for (const int q : plan_.regions[static_cast<std::size_t>(l.region)].layers) {
            if (plan_.layers[static_cast<std::size_t>(q)].index_in_region == l.index_in_region)
                out.push_back(q);
        }
        return out;
    }

    // Whether `to` can be reached from `from` along the edges made so far: a search over
    // from's descendants only (the marks of earlier searches are told apart by a stamp).
    bool reaches(int from, int to) {
        seen_.resize(plan_.layers.size(), 0);
        ++stamp_;
        std::vector<int> stack{from};
        while (!stack.empty()) {
            const int id = stack.back();
            stack.pop_back();
            if (id == to) return true;
            if (seen_[static_cast<std::size_t>(id)] == stamp_) continue;
            seen_[static_cast<std::size_t>(id)] = stamp_;
            for (const int c : plan_.layers[static_cast<std::size_t>(id)].children)
                stack.push_back(c);
        }
        return false;
    }

    bool descends_from(int region, int ancestor) const {
        for (int r = region; r >= 0; r = plan_.regions[static_cast<std::size_t>(r)].parent) {
            if (r == ancestor) return true;
        }
        return false;
    }

    // The layers of other regions a sideways region's first-layer piece touches across its
    // base plane, and which of those contacts are decided.
    struct Contacts {
        int first = -1;
        std::vector<int> others;
        std::vector<char> done;
    };

    // The layers of the regions other than rid and those split from it.
    std::vector<int> others_of(int rid) const {
        std::vector<int> out;
        for (const Region& other : plan_.regions) {
            if (other.id == rid || descends_from(other.id, rid)) continue;
            out.insert(out.end(), other.layers.begin(), other.layers.end());
        }
        return out;
    }

    // The layers among `others` that piece `first`, standing on the plane through s with
    // normal ns, rests on: contact over 5 % of a track's square, or, for a piece smaller than
    // that, over half its own area.
    Contacts contacts_across(const Layer& first, const core::Vec3d& s, const core::Vec3d& ns,
                             const std::vector<int>& others) const {
        const Box2 box = box2_of(first.wires.paths());
        const double least = std::min(kContactAreaShare * s_.track_width_mm * s_.track_width_mm,
                                      kSmallPieceShare * first.area_mm2);
        std::vector<char> touches(others.size(), 0);
        tbb::parallel_for(std::size_t{0}, others.size(), [&](std::size_t k) {
            const Layer& q = plan_.layers[static_cast<std::size_t>(others[k])];
            touches[k] = contact_mm2(q, first, box, s, ns) >= least ? 1 : 0;
        });
        Contacts c;
        c.first = first.id;
        for (std::size_t k = 0; k < others.size(); ++k) {
            if (touches[k] != 0) c.others.push_back(others[k]);
        }
        return c;
    }

    // The pieces without a parent (after the within-region edges) that are neither on the
    // plate nor first-layer pieces with contacts already sought (`firsts`), in id order.
    std::vector<int> orphan_pieces(const std::vector<Contacts>& firsts) const {
        std::vector<char> sought(plan_.layers.size(), 0);
        for (const Contacts& c : firsts) sought[static_cast<std::size_t>(c.first)] = 1;
        std::vector<int> out;
        for (const Layer& l : plan_.layers) {
            if (l.on_plate || !l.parents.empty() || sought[static_cast<std::size_t>(l.id)] != 0) {
                continue;
            }
            out.push_back(l.id);
        }
        return out;
    }

    // The edges of the first-layer pieces' contacts. The edges from layers the plate already
    // carries (through the edges made so far) come first, so that a piece rests on the built
    // part. Two first-layer pieces may touch each other across both base planes (sideways
    // regions side by side): of the two edges only one can be made, and it is made only for
    // a piece nothing else carries (from the other, when the plate carries that one); when
    // both are carried otherwise, neither is made and the build order puts them in the order
    // the nozzle allows. The contacts with layers the plate does not carry come last, in the
    // order the regions were made. An edge that would close a cycle is left out, so the
    // graph stays acyclic.
    void link_first_layers(std::vector<Contacts>& contacts) {
        std::vector<Layer>& layers = plan_.layers;
        std::vector<int> index(layers.size(), -1);
        for (std::size_t i = 0; i < contacts.size(); ++i) {
            index[static_cast<std::size_t>(contacts[i].first)] = static_cast<int>(i);
            contacts[i].done.assign(contacts[i].others.size(), 0);
        }
        const auto mutual = [&](int f, int q) {
            const int i = index[static_cast<std::size_t>(q)];
            if (i < 0) return false;
            const std::vector<int>& o = contacts[static_cast<std::size_t>(i)].others;
            return std::find(o.begin(), o.end(), f) != o.end();
        };
        std::vector<char> grounded(layers.size(), 0);
        const auto ground = [&](int from) {
            std::vector<int> stack{from};
            while (!stack.empty()) {
                const int id = stack.back();
                stack.pop_back();
                if (grounded[static_cast<std::size_t>(id)] != 0) continue;
                grounded[static_cast<std::size_t>(id)] = 1;
                for (const int c : layers[static_cast<std::size_t>(id)].children)
                    stack.push_back(c);
            }
        };
        const auto edge = [&](Contacts& c, std::size_t k) {
            c.done[k] = 1;
            const int q = c.others[k];
            if (reaches(c.first, q)) return false;
            layers[static_cast<std::size_t>(q)].children.push_back(c.first);
            layers[static_cast<std::size_t>(c.first)].parents.push_back(q);
            if (grounded[static_cast<std::size_t>(q)] != 0) ground(c.first);
            return true;
        };
        for (const Layer& l : layers) {
            if (l.on_plate) ground(l.id);
        }
        for (bool took = true; took;) {
            for (bool more = true; more;) {
                more = false;
                for (Contacts& c : contacts) {
                    for (std::size_t k = 0; k < c.others.size(); ++k) {
                        const int q = c.others[k];
                        if (c.done[k] == 0 && grounded[static_cast<std::size_t>(q)] != 0 &&
                            !mutual(c.first, q)) {
                            more = edge(c, k) || more;
                        }
                    }
                }
            }
            took = false;
            for (Contacts& c : contacts) {
                if (grounded[static_cast<std::size_t>(c.first)] != 0) continue;
                for (std::size_t k = 0; k < c.others.size() && !took; ++k) {
                    if (c.done[k] == 0 && grounded[static_cast<std::size_t>(c.others[k])] != 0) {
                        took = edge(c, k);
                    }
                }
                if (took) break;
            }
        }
        for (Contacts& c : contacts) {
            for (std::size_t k = 0; k < c.others.size(); ++k) {
                const int q = c.others[k];
                if (c.done[k] != 0 ||
                    (mutual(c.first, q) && grounded[static_cast<std::size_t>(q)] != 0 &&
                     grounded[static_cast<std::size_t>(c.first)] != 0)) {
                    continue;
                }
                edge(c, k);
            }
        }
    }

    // The uppers of one slice that rest on one lower layer (overlap_mm2 > 0).
    struct LinkTask {
        int region = 0;
        int lower = -1;
        std::vector<int> uppers;
        std::vector<char> rests;  // per upper
    };

    void rests_on(LinkTask& t) const {
        const Layer& lower = plan_.layers[static_cast<std::size_t>(t.lower)];
        t.rests.assign(t.uppers.size(), 0);
        const Box2 lower_box = box2_of(lower.wires.paths());
        Paths2 grown;  // lower grown by `grown_by`, made when first needed
        std::int64_t grown_by = -1;
        for (std::size_t k = 0; k < t.uppers.size(); ++k) {
            const Layer& upper = plan_.layers[static_cast<std::size_t>(t.uppers[k])];
            if (upper.after_gap || !may_overlap(lower, upper)) continue;
            const Paths2 u = project_paths(upper.wires.paths(), upper.plane, lower.plane);
            const std::int64_t grow = growth_um(lower, upper);
            // The grown region lies within twice the growth of lower (mitred corners): a
            // piece whose box stays clear of that has no overlap.
            if (!boxes_near(box2_of(u), lower_box, 2 * grow + kNearSlackUm)) {
                continue;
            }
            if (grow != grown_by) {
                grown = geom2d::offset_of(lower.wires.paths(), grow);
                grown_by = grow;
            }
            t.rests[k] = geom2d::signed_area_mm2(geom2d::intersection_of(u, grown)) > 0.0 ? 1 : 0;
        }
    }

    // Whether upper's footprint can reach lower's grown region (boxes of their wires in
    // 3D, grown by the growth overlap_mm2 allows and the distance between the layers).
    bool may_overlap(const Layer& lower, const Layer& upper) const {
        const Box3& a = boxes_[static_cast<std::size_t>(lower.id)];
        const Box3& b = boxes_[static_cast<std::size_t>(upper.id)];
        const double gap = 2.0 * s_.track_width_mm + 2.0 * s_.h_max_mm +
                           core::norm(upper.plane.origin - lower.plane.origin) *
                               std::tan(s_.self_supporting_deg * std::numbers::pi / 180.0);
        for (int k = 0; k < 3; ++k) {
            if (a.lo[k] > b.hi[k] + gap || b.lo[k] > a.hi[k] + gap) return false;
        }
        return true;
    }

    // How far lower is grown before the overlap is measured: the self-supporting allowance
    // over the height between them, and a track, so that what the analysis calls carried
    // (slivers narrower than a track included) rests on lower.
    std::int64_t growth_um(const Layer& lower, const Layer& upper) const {
        const double h = std::max(0.0, lower.plane.height(upper.plane.origin));
        return core::mm_to_um(h * std::tan(s_.self_supporting_deg * std::numbers::pi / 180.0) +
                              s_.track_width_mm);
    }

    static bool boxes_near(const Box2& a, const Box2& b, std::int64_t gap) {
        return a.lo.x <= b.hi.x + gap && b.lo.x <= a.hi.x + gap && a.lo.y <= b.hi.y + gap &&
               b.lo.y <= a.hi.y + gap;
    }

    // Area (mm2) where layer q's material just behind the plane through s with normal ns (a
    // region's base plane, or a piece's bottom plane) meets the footprint of the layer
    // `first` that stands on that plane.
    double contact_mm2(const Layer& q, const Layer& first, const Box2& first_box,
                       const core::Vec3d& s, const core::Vec3d& ns) const {
        const double depth = std::max(s_.layer_mm, q.span.thickness());
        // Most layers lie wholly in front of the base plane or far behind it: their box
        // tells, without clipping.
        const Box3& box = boxes_[static_cast<std::size_t>(q.id)];
        double centre = 0.0, radius = 0.0;
        for (int k = 0; k < 3; ++k) {
            centre += 0.5 * (box.lo[k] + box.hi[k] - 2.0 * s[k]) * ns[k];
            radius += 0.5 * (box.hi[k] - box.lo[k]) * std::abs(ns[k]);
        }
        if (centre - radius > kStripSlackMm || centre + radius < -depth - kStripSlackMm) return 0.0;
        // Nor can q's slab meet the first layer where its box, grown by the slab's half
        // thickness and seen on the first layer's plane, misses the first layer's box.
        const double ext =
            std::max(std::abs(q.span.bottom - q.span.cut), std::abs(q.span.top - q.span.cut));
        double u_lo = INFINITY, u_hi = -INFINITY, v_lo = INFINITY, v_hi = -INFINITY;
        for (int corner = 0; corner < 8; ++corner) {
            const core::Vec3d x{(corner & 1) != 0 ? box.hi[0] + ext : box.lo[0] - ext,
                                (corner & 2) != 0 ? box.hi[1] + ext : box.lo[1] - ext,
                                (corner & 4) != 0 ? box.hi[2] + ext : box.lo[2] - ext};
            const double u = core::dot(x - first.plane.origin, first.plane.u);
            const double v = core::dot(x - first.plane.origin, first.plane.v);
            u_lo = std::min(u_lo, u);
            u_hi = std::max(u_hi, u);
            v_lo = std::min(v_lo, v);
            v_hi = std::max(v_hi, v);
        }
        const double slack_um = core::kMicronsPerMm * kStripSlackMm;
        if (u_hi * core::kMicronsPerMm < static_cast<double>(first_box.lo.x) - slack_um ||
            u_lo * core::kMicronsPerMm > static_cast<double>(first_box.hi.x) + slack_um ||
            v_hi * core::kMicronsPerMm < static_cast<double>(first_box.lo.y) - slack_um ||
            v_lo * core::kMicronsPerMm > static_cast<double>(first_box.hi.y) + slack_um) {
            return 0.0;
        }
        const HalfSpace strip[] = {{s, -ns}, {s - ns * depth, ns}};
        const Paths2 near = clip_to_cell(q.wires.paths(), strip, q.plane);
        if (near.empty()) return 0.0;
        // q's slab: its section between its bottom and top, seen on r's base plane.
        geom2d::Paths2 hulls;
        for (const geom2d::Path2& path : near) {
            if (geom2d::signed_area_um2(path) <= 0.0) continue;
            geom2d::Path2 pts;
            for (const geom2d::Point2& p : path) {
                for (const double h : {q.span.bottom - q.span.cut, q.span.top - q.span.cut}) {
                    pts.push_back(first.plane.to_2d(q.plane.to_3d(p, h)));
                }
            }
            geom2d::Path2 hull = geom2d::convex_hull({pts});
            if (hull.size() >= 3) hulls.push_back(std::move(hull));
        }
        if (hulls.empty()) return 0.0;
        return geom2d::signed_area_mm2(
            geom2d::intersection_of(geom2d::union_of(hulls), first.wires.paths()));
    }

    Plan& plan_;
    PlanSettings s_;
    std::vector<Box3> boxes_;  // per layer id
    std::vector<int> seen_;    // marks of reaches(), per layer id
    int stamp_ = 0;
};

}  // namespace

// One layer per piece (METHOD.md section 6): a slice whose section falls apart into
// separate islands (two legs, two branches) gives one layer per island, so that branches
// can merge and fork in the graph and the build order can grow them in turn. Pieces of a
// slice share its index_in_region; ids stay contiguous per region, and the layer ids the
// decisions name are renumbered to the slice's first piece (their texts are made from them).
void split_pieces(Plan& plan) {
    std::vector<Layer> out;
    out.reserve(plan.layers.size());
    std::vector<int> first_piece(plan.layers.size(), -1);
    for (Region& r : plan.regions) {
        std::vector<int> ids;
        ids.reserve(r.layers.size());
        for (const int old : r.layers) {
            Layer& l = plan.layers[static_cast<std::size_t>(old)];
            std::vector<Paths2> parts = l.wires.islands();
            first_piece[static_cast<std::size_t>(old)] = static_cast<int>(out.size());
            if (parts.size() <= 1) {
                l.id = static_cast<int>(out.size());
                ids.push_back(l.id);
                out.push_back(std::move(l));
                continue;
            }
            l.wires = {};
            for (Paths2& part : parts) {
                Layer piece = l;
                piece.id = static_cast<int>(out.size());
                piece.wires = geom2d::build_wire_tree(part, geom2d::FillRule::kPositive);
                piece.area_mm2 = piece.wires.area_mm2();
                ids.push_back(piece.id);
                out.push_back(std::move(piece));
            }
        }
        r.layers = std::move(ids);
    }
    const auto renumber = [&](int old) {
        return old >= 0 && static_cast<std::size_t>(old) < first_piece.size()
                   ? first_piece[static_cast<std::size_t>(old)]
                   : old;
    };
    for (Decision& d : plan.decisions) d.layer = renumber(d.layer);
    plan.layers = std::move(out);
}

core::Result<void> build_graph(Plan& plan) {
    return GraphBuilder(plan).run();
}

}  // namespace detail

HangingLoad hanging_from(const Plan& plan, int id) {
    const std::size_t n = plan.layers.size();
    const auto at = [&](int i) -> const Layer& { return plan.layers[static_cast<std::size_t>(i)]; };
    // What the plate carries: every layer a path joins to a layer on the plate.
    std::vector<char> carried(n, 0);
    std::vector<int> stack;
    for (const Layer& l : plan.layers) {
        if (l.on_plate) stack.push_back(l.id);
    }
    while (!stack.empty()) {
        const int i = stack.back();
        stack.pop_back();
        if (carried[static_cast<std::size_t>(i)] != 0) continue;
        carried[static_cast<std::size_t>(i)] = 1;
        for (const int c : at(i).children) stack.push_back(c);
    }
    HangingLoad out;
    if (id < 0 || static_cast<std::size_t>(id) >= n) return out;
    std::vector<char> seen(n, 0);
    stack.push_back(id);
    while (!stack.empty()) {
        const int i = stack.back();
        stack.pop_back();
        if (seen[static_cast<std::size_t>(i)] != 0 || carried[static_cast<std::size_t>(i)] != 0) {
            continue;
        }
        seen[static_cast<std::size_t>(i)] = 1;
        ++out.layers;
        out.volume_mm3 += at(i).area_mm2 * at(i).thickness_mean_mm;
        for (const int c : at(i).children) stack.push_back(c);
    }
    return out;
}

std::vector<int> topological_order(const Plan& plan) {
    std::vector<int> indegree(plan.layers.size(), 0);
    for (const Layer& l : plan.layers)
        indegree[static_cast<std::size_t>(l.id)] = static_cast<int>(l.parents.size());
    std::priority_queue<int, std::vector<int>, std::greater<>> ready;
    for (const Layer& l : plan.layers) {
        if (indegree[static_cast<std::size_t>(l.id)] == 0) ready.push(l.id);
    }
    std::vector<int> order;
    order.reserve(plan.layers.size());
    while (!ready.empty()) {
        const int id = ready.top();
        ready.pop();
        order.push_back(id);
        for (const int c : plan.layers[static_cast<std::size_t>(id)].children) {
            if (--indegree[static_cast<std::size_t>(c)] == 0) ready.push(c);
        }
    }
    return order;
}

}  // namespace maxslice::plan
