// The build order on every valid part of the shared test data: each order the planner calls
// complete is checked by the independent brute-force nozzle check (tests/support), with the
// reference cell's head; a part without a collision-free order must name its conflicts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "maxslice/machine/profile.hpp"
#include "maxslice/mesh/triangle_mesh.hpp"
#include "maxslice/pipeline/plan_job.hpp"
#include "maxslice/pipeline/slice_job.hpp"
#include "maxslice/plan/order.hpp"
#include "support/nozzle_check.hpp"

namespace fs = std::filesystem;
namespace ms = maxslice;

namespace {

ms::plan::Nozzle reference_nozzle() {
    std::ifstream in(fs::path(MAXSLICE_SOURCE_DIR) / "examples/profiles/reference_lmd.toml");
    std::stringstream text;
    text << in.rdbuf();
    auto file = ms::machine::parse_profile(text.str(), "reference_lmd.toml");
    EXPECT_TRUE(file.has_value());
    EXPECT_TRUE(file && file->machine && file->machine->nozzle) << "the reference has a head";
    std::string source;
    return file && file->machine ? ms::pipeline::nozzle_of(*file->machine, &source)
                                 : ms::plan::Nozzle{};
}

TEST(OrderSharedMeshes, EverySharedMeshOrderIsCollisionFree) {
    const ms::plan::Nozzle nozzle = reference_nozzle();
    int complete = 0, conflicted = 0;
    for (const auto& e :
         fs::recursive_directory_iterator(fs::path(MAXSLICE_TESTDATA_DIR) / "meshes")) {
        if (!e.is_regular_file()) continue;
        SCOPED_TRACE(e.path().string());
        ms::pipeline::PrepareSettings ps;
        ps.repair = true;
        auto part = ms::pipeline::prepare_part(e.path(), ps);
        if (!part) continue;  // malformed files are the CLI tests' business
        const ms::plan::PlanSettings settings;
        auto plan = ms::plan::plan_part(part->imported.mesh, {0.0, 0.0, 1.0}, settings);
        if (!plan) continue;  // refused with a message: the planner tests' business
        ms::plan::OrderSettings os;
        os.nozzle = nozzle;
        auto order = ms::plan::order_layers(*plan, os);
        ASSERT_TRUE(order.has_value()) << order.error().describe();
        if (!order->complete()) {
            ++conflicted;
            for (const ms::plan::Conflict& c : order->conflicts) {
                EXPECT_LT(c.margin_mm, nozzle.clearance_mm);
                EXPECT_NE(c.layer, c.other);
                EXPECT_FALSE(c.reason.empty());
            }
            continue;
        }
        ++complete;
        ASSERT_EQ(order->order.size(), plan->layers.size());
        // A 2 mm sampling, coarser on parts over 200 mm across (a hundredth of the box's
        // diagonal: the pairs' cost grows as the samples' square), keeps the sweep over 22
        // parts within a few minutes; the fixtures' tests check at 1 mm.
        const ms::core::Box3d box = ms::mesh::bounding_box(part->imported.mesh);
        ms::test::NozzleCheckSettings check;
        check.sample_step_mm = std::max(2.0, ms::core::norm(box.max - box.min) / 100.0);
        check.max_pairs = 1;
        const auto hits =
            ms::test::brute_force_collisions(*plan, *order, nozzle, settings.track_width_mm, check);
        EXPECT_TRUE(hits.empty()) << hits.size() << " colliding pairs, first: "
                                  << ms::test::describe(hits.front());
    }
    std::printf("%d parts ordered and checked, %d with conflicts\n", complete, conflicted);
    EXPECT_GE(complete, 15);
}

}  // namespace
