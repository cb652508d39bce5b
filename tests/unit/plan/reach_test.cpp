// Build directions chosen by reach (decision 0029): with the head set, a region split off
// sideways leans up where the head, standing on it along the seed's N_s, would meet the
// plate or what is built before it. Checked with the brute-force head of tests/support
// (nozzle_check: its own cone and body, its own sampling), not with the planner's margins.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "maxslice/plan/analysis.hpp"
#include "maxslice/plan/order.hpp"
#include "maxslice/plan/planner.hpp"
#include "support/fixtures.hpp"
#include "support/nozzle_check.hpp"
#include "support/planner_fixtures.hpp"

namespace maxslice::plan {
namespace {

using core::Vec3d;

using test::reference_head;

PlanSettings settings(bool with_head) {
    PlanSettings s;
    s.layer_mm = 0.5;
    s.track_width_mm = 2.5;
    s.self_supporting_deg = 20.0;
    if (with_head) s.head = reference_head();
    return s;
}

Plan plan_of(const mesh::TriangleMesh& m, const PlanSettings& s) {
    auto p = plan_part(m, {0, 0, 1}, s);
    EXPECT_TRUE(p.has_value()) << (p ? "" : p.error().describe());
    return p ? std::move(*p) : Plan{};
}

// The smallest hardware clearance (mm) of the head from the plate (the plane z = 0) with
// the head standing on the toolpath of every layer of `region`, its axis along the layer's
// top normal: per apex, the plate sampled on a 2 mm grid under the head, then on a 0.05 mm
// grid around the closest sample. Sampling can only overestimate it.
double plate_clearance(const Plan& p, int region, const Nozzle& n, double track_mm) {
    double best = std::numeric_limits<double>::infinity();
    const double reach = n.cone_length_mm + n.body_length_mm + n.body_radius_mm;
    const auto smallest = [&](const Vec3d& apex, const Vec3d& axis, double cx, double cy,
                              double half, double step, Vec3d& at) {
        double m = std::numeric_limits<double>::infinity();
        for (double x = cx - half; x <= cx + half; x += step) {
            for (double y = cy - half; y <= cy + half; y += step) {
                const double c = test::hardware_clearance_mm(n, apex, axis, {x, y, 0.0});
                if (c < m) {
                    m = c;
                    at = {x, y, 0.0};
                }
            }
        }
        return m;
    };
    for (const int id : p.regions[static_cast<std::size_t>(region)].layers) {
        const Layer& l = p.layers[static_cast<std::size_t>(id)];
        for (const Vec3d& apex : test::nozzle_apexes(l, track_mm, 5.0)) {
            Vec3d at;
            smallest(apex, l.top.normal, apex.x, apex.y, reach, 2.0, at);
            best = std::min(best, smallest(apex, l.top.normal, at.x, at.y, 2.0, 0.05, at));
        }
    }
    return best;
}

const Decision* first_split(const Plan& p) {
    for (const Decision& d : p.decisions) {
        if (d.kind == Decision::Kind::kSplit) return &d;
    }
    return nullptr;
}

TEST(Reach, ASidewaysBossBesideThePlateLeansUpUntilTheHeadClearsIt) {
    const auto f = test::bearing_seat();
    const Nozzle head = reference_head();
    const Plan seed = plan_of(f.mesh, settings(false));
    const Plan leaned = plan_of(f.mesh, settings(true));
    const Decision* s = first_split(seed);
    const Decision* d = first_split(leaned);
    ASSERT_NE(s, nullptr);
    ASSERT_NE(d, nullptr);
    EXPECT_FALSE(s->head_checked);
    EXPECT_TRUE(d->head_checked);
    const int boss_seed = s->new_region, boss = d->new_region;
    const Vec3d ns = seed.regions[static_cast<std::size_t>(boss_seed)].direction;
    const Vec3d dir = leaned.regions[static_cast<std::size_t>(boss)].direction;
    // Along the seed's sideways direction the head's body goes through the plate.
    EXPECT_LT(plate_clearance(seed, boss_seed, head, 2.5), 0.0);
    // Leaned up, towards the base direction, by the angle the decision states, and clear.
    EXPECT_GT(d->split_lean_deg, 0.0);
    EXPECT_TRUE(d->head_clears);
    EXPECT_GE(d->head_margin_mm, head.clearance_mm);
    EXPECT_LT(d->seed_margin_mm, head.clearance_mm);
    const double lean =
        std::acos(std::clamp(core::dot(ns, dir), -1.0, 1.0)) * 180.0 / std::numbers::pi;
    EXPECT_NEAR(lean, d->split_lean_deg, 0.5);
    EXPECT_GT(dir.z, ns.z + 0.1);
    EXPECT_GE(plate_clearance(leaned, boss, head, 2.5), head.clearance_mm - 0.05);
    // Every layer still rests on the one below, and an order keeps the head off the part.
    EXPECT_TRUE(leaned.unsupported_layers.empty());
    OrderSettings os;
    os.nozzle = head;
    const auto order = order_layers(leaned, os);
    ASSERT_TRUE(order.has_value()) << order.error().describe();
    EXPECT_TRUE(order->conflicts.empty());
    test::NozzleCheckSettings cs;
    cs.clearance_mm = head.clearance_mm;
    cs.sample_step_mm = 2.0;
    cs.max_pairs = 1;
    const auto hits = test::brute_force_collisions(leaned, *order, head, 2.5, cs);
    EXPECT_TRUE(hits.empty()) << test::describe(hits.front());
}

TEST(Reach, ASidewaysRegionTheHeadReachesKeepsTheSeedsDirection) {
    // The boss 60 mm above the plate: along its axis the head clears the plate and the block.
    test::BearingSeatSpec spec;
    spec.block_height = 120.0;
    const auto f = test::bearing_seat(spec);
    const Plan seed = plan_of(f.mesh, settings(false));
    const Plan checked = plan_of(f.mesh, settings(true));
    const Decision* s = first_split(seed);
    const Decision* d = first_split(checked);
    ASSERT_NE(s, nullptr);
    ASSERT_NE(d, nullptr);
    EXPECT_TRUE(d->head_checked);
    EXPECT_TRUE(d->head_clears);
    EXPECT_EQ(d->split_lean_deg, 0.0);
    EXPECT_GE(d->seed_margin_mm, reference_head().clearance_mm);
    ASSERT_EQ(seed.regions.size(), checked.regions.size());
    for (std::size_t i = 0; i < seed.regions.size(); ++i) {
        EXPECT_LT(core::norm(seed.regions[i].direction - checked.regions[i].direction), 1e-12);
        EXPECT_EQ(seed.regions[i].layers.size(), checked.regions[i].layers.size());
    }
}

// Where no lean or turn of the sideways direction keeps a wide nozzle (60 degree half angle)
// clear of the plate and the block, as for the bearing seat's and the wall's bosses, the
// planner searches a sample of the sphere within the tilt range (decision 0046). The
// direction it keeps clears by its own margin, every layer rests on the one below, and an
// order exists that the brute-force head of tests/support (its own cone, body and sampling)
// finds clear.
TEST(Reach, WhereNoLeanClearsTheHeadASampleOfTheSphereFindsADirectionThatDoes) {
    for (const auto& f : {test::bearing_seat(), test::wall_boss()}) {
        SCOPED_TRACE(f.name);
        PlanSettings s = settings(true);
        s.head->half_angle_deg = 60.0;
        s.max_tilt_deg = 120.0;
        const Plan p = plan_of(f.mesh, s);
        int searched = 0;
        for (const Decision& d : p.decisions) {
            if (d.kind == Decision::Kind::kTilt || !(d.split_searched_deg > 0.0)) continue;
            ++searched;
            EXPECT_TRUE(d.moved_for_reach());
            EXPECT_TRUE(d.head_clears);
            EXPECT_GE(d.head_margin_mm, s.head->clearance_mm);
            // No lean or turn of N_s kept the clearance: along N_s itself the head did not.
            EXPECT_LT(d.seed_margin_mm, s.head->clearance_mm);
            const Region& r = p.regions[static_cast<std::size_t>(d.new_region)];
            EXPECT_LE(angle_deg(r.direction, {0, 0, 1}), s.max_tilt_deg + 1e-9);
            EXPECT_NE(describe(p, d).find("found in a sample of the sphere"), std::string::npos)
                << describe(p, d);
        }
        EXPECT_GT(searched, 0);
        EXPECT_TRUE(p.unsupported_layers.empty());
        OrderSettings os;
        os.nozzle = *s.head;
        const auto order = order_layers(p, os);
        ASSERT_TRUE(order.has_value()) << order.error().describe();
        EXPECT_TRUE(order->conflicts.empty());
        test::NozzleCheckSettings cs;
        cs.clearance_mm = s.head->clearance_mm;
        cs.sample_step_mm = 2.0;
        cs.max_pairs = 1;
        const auto hits = test::brute_force_collisions(p, *order, *s.head, 2.5, cs);
        EXPECT_TRUE(hits.empty()) << test::describe(hits.front());
    }
}

// A finger hanging from the end of an arm built sideways grows towards the plate, beyond the
// table's tilt range, and the directions that keep the head clear lean up: a split plane along
// one of them can leave the finger behind it. The region such a split leaves below the finger
// has not started; it is walked again and must be split along a direction that takes the
// finger off, not again and again along the same one (the planner ran into max_regions, NIST
// CTC-04 as given alike).
TEST(Reach, ARegionThatHasNotStartedIsSplitForAPieceOnlyAlongAPlaneThatTakesItOff) {
    PlanSettings s = settings(true);
    s.max_tilt_deg = 120.0;
    const test::PlannerFixture f = test::hook();
    auto p = plan_part(f.mesh, {0, 0, 1}, s);
    ASSERT_TRUE(p.has_value()) << p.error().describe();
    EXPECT_LE(p->regions.size(), 16U);
    int not_started = 0;
    for (std::size_t i = 0; i < p->decisions.size(); ++i) {
        const Decision& d = p->decisions[i];
        if (d.kind != Decision::Kind::kSplit && d.kind != Decision::Kind::kFloating) continue;
        if (d.continuation == d.region) {
            ++not_started;
            EXPECT_GT(core::dot(d.piece.C - d.split_plane.point, d.split_plane.normal), 0.0)
                << describe(*p, d);
        }
        for (std::size_t j = i + 1; j < p->decisions.size(); ++j) {
            const Decision& e = p->decisions[j];
            const bool same = e.kind == d.kind && e.region == d.region && e.layer == d.layer &&
                              core::norm(e.piece.C - d.piece.C) < 1e-9;
            EXPECT_FALSE(same) << describe(*p, d);
        }
    }
    EXPECT_GT(not_started, 0);
}

// Turning a part about Z (the plate's normal) and moving it change neither what the head can
// reach nor the plate under it: every fixture keeps its number of regions and its layers on
// nothing, and its verdict on a collision-free order, but for conflicts within the order's
// sampling of the clearance (toolpaths turn with the part, and so do the samples: a conflict
// 0.04 mm inside the clearance one way may be 0.02 mm outside it the other).
TEST(Reach, EveryFixtureTurnedAboutZKeepsItsRegionsAndItsVerdict) {
    OrderSettings os;
    os.nozzle = reference_head();
    // The order's samples are this close to the material they stand for (a tenth of a track).
    const double resolution = 0.25;
    const auto borderline = [&](const BuildOrder& o) {
        return std::all_of(o.conflicts.begin(), o.conflicts.end(), [&](const Conflict& c) {
            return c.margin_mm >= os.nozzle.clearance_mm - resolution;
        });
    };
    for (const auto& f : test::all_planner_fixtures()) {
        SCOPED_TRACE(f.name);
        const Plan given = plan_of(f.mesh, settings(true));
        const Plan turned = plan_of(test::rotated(f.mesh, {0, 0, 1}, 37.0), settings(true));
        const Plan moved =
            plan_of(test::translated(f.mesh, {173.25, -61.5, 42.125}), settings(true));
        const auto a = order_layers(given, os);
        ASSERT_TRUE(a.has_value());
        for (const Plan* other : {&turned, &moved}) {
            SCOPED_TRACE(other == &turned ? "turned 37 degrees about Z" : "moved");
            EXPECT_EQ(given.regions.size(), other->regions.size());
            EXPECT_EQ(given.unsupported_layers.size(), other->unsupported_layers.size());
            const auto b = order_layers(*other, os);
            ASSERT_TRUE(b.has_value());
            if (a->complete() != b->complete()) {
                const BuildOrder& refused = a->complete() ? *b : *a;
                EXPECT_TRUE(borderline(refused)) << refused.conflicts.front().reason;
            }
        }
    }
}

// A table that tilts at most 60 degrees (decision 0032): every region of every fixture is
// built along a direction within 60 degrees of the plate's normal, and every layer's top (the
// head's axis) lies within it too; where the seed's N_s lies beyond (the sideways regions of
// the fixtures, 90 degrees), the region is turned up to the edge of the range, no further.
TEST(Reach, EveryRegionIsBuiltWithinTheTablesTiltRange) {
    constexpr double kRange = 60.0;
    int turned = 0;
    for (const auto& f : test::all_planner_fixtures()) {
        SCOPED_TRACE(f.name);
        PlanSettings s = settings(true);
        const Plan free = plan_of(f.mesh, s);
        s.max_tilt_deg = kRange;
        const Plan p = plan_of(f.mesh, s);
        for (const Region& r : p.regions) {
            EXPECT_LE(angle_deg(r.direction, {0, 0, 1}), kRange + 1e-9) << "region " << r.id;
        }
        for (const Layer& l : p.layers) {  // tilted layers too: the head stands along them
            EXPECT_LE(angle_deg(l.top.normal, {0, 0, 1}), kRange + 1e-9) << "layer " << l.id;
        }
        const auto beyond = [&](const Region& r) {
            return angle_deg(r.direction, {0, 0, 1}) > kRange + 1e-6;
        };
        if (std::any_of(free.regions.begin(), free.regions.end(), beyond)) {
            ++turned;
            EXPECT_TRUE(std::any_of(p.regions.begin(), p.regions.end(), [&](const Region& r) {
                return std::abs(angle_deg(r.direction, {0, 0, 1}) - kRange) < 1e-6;
            }));
        }
    }
    EXPECT_GT(turned, 0);  // some fixture has a sideways region beyond the range
}

// A refusal names the feature in the way (its region, where its piece is, how big, how far it
// was leaned) and the closest gap, from the plan's own fields. The helical ring as modelled has
// no collision-free order: the planner does not yet follow its turns.
TEST(Reach, ARefusedOrderNamesTheRegionInTheWayAndTheClosestGap) {
    const auto f = test::helical_ring();
    const Plan p = plan_of(f.mesh, settings(true));
    OrderSettings os;
    os.nozzle = reference_head();
    const auto order = order_layers(p, os);
    ASSERT_TRUE(order.has_value());
    ASSERT_FALSE(order->complete()) << "the helical ring as modelled has no collision-free order";
    const std::string text = describe_refusal(p, *order, os.nozzle);
    const int rid = p.layers[static_cast<std::size_t>(order->conflicts.front().layer)].region;
    EXPECT_NE(text.find(fmt::format("region {}", rid)), std::string::npos) << text;
    for (const Decision& d : p.decisions) {
        if (d.kind != Decision::Kind::kSplit || d.new_region != rid) continue;
        EXPECT_NE(text.find(fmt::format("{:.1f} mm2", d.piece.area_mm2)), std::string::npos)
            << text;
        if (d.split_lean_deg > 0.0) {
            EXPECT_NE(text.find(fmt::format("leaned up {:.0f} deg", d.split_lean_deg)),
                      std::string::npos)
                << text;
        }
    }
    double closest = os.nozzle.clearance_mm;
    for (const Conflict& c : order->conflicts) closest = std::min(closest, c.margin_mm);
    EXPECT_NE(text.find(closest < 0.0
                            ? fmt::format("it would reach {:.2f} mm into what is built", -closest)
                            : fmt::format("closest gap: {:.2f} mm", closest)),
              std::string::npos)
        << text;
    EXPECT_NE(text.find("--orient auto"), std::string::npos);
    BuildOrder none;
    EXPECT_TRUE(describe_refusal(p, none, os.nozzle).empty());
}

// Far features (decision 0035): the arm's split plane leaves the post, further along +X, in
// the half-space of the arm's region, though the post does not grow from the arm. Built along
// the arm's direction the post would start as a tip in the air; it carries on upright instead,
// in a region of its own, and the whole part orders without a conflict and rests on the plate.
TEST(Reach, AFeatureBeyondTheSplitPlaneThatDoesNotGrowFromThePieceCarriesOnUpright) {
    const test::ArmAndPostSpec spec;
    const auto f = test::arm_and_post(spec);
    const Plan p = plan_of(f.mesh, settings(true));
    ASSERT_FALSE(p.layers.empty());
    EXPECT_TRUE(p.unsupported_layers.empty()) << p.unsupported_layers.size() << " on nothing";
    int far = 0;
    for (const Decision& d : p.decisions) {
        for (const int rid : d.far_regions) {
            ++far;
            const Region& r = p.regions[static_cast<std::size_t>(rid)];
            // Along the old direction, the one the region split carried on along.
            EXPECT_LT(
                angle_deg(r.direction, p.layers[static_cast<std::size_t>(d.layer)].top.normal),
                1e-6);
        }
    }
    EXPECT_GT(far, 0) << "no far feature was set apart";
    const double arm_top = spec.base_height + spec.column_height + spec.arm_thickness;
    const double arm_end = spec.column_width + spec.arm_length;
    int post = 0, arm = 0;
    for (const Layer& l : p.layers) {
        const Vec3d c = centroid_of(l);
        const double lean =
            angle_deg(p.regions[static_cast<std::size_t>(l.region)].direction, {0, 0, 1});
        if (c.x > spec.post_x && c.z > spec.base_height + spec.column_height) {
            ++post;  // the post above the arm's level: upright (the column's march aside)
            EXPECT_LT(lean, 10.0) << "layer " << l.id << " at z " << c.z;
        } else if (c.x > spec.column_width + 1.0 && c.x < arm_end && c.z < arm_top &&
                   c.z > spec.base_height + spec.column_height) {
            ++arm;  // the arm: sideways
            EXPECT_GT(lean, 30.0) << "layer " << l.id;
        }
    }
    EXPECT_GT(post, 0);
    EXPECT_GT(arm, 0);
    OrderSettings os;
    os.nozzle = reference_head();
    const auto order = order_layers(p, os);
    ASSERT_TRUE(order.has_value());
    EXPECT_TRUE(order->complete())
        << (order->conflicts.empty() ? "" : order->conflicts.front().reason);
}

}  // namespace
}  // namespace maxslice::plan
