#include "maxslice/machine/program_builder.hpp"

#include <vector>

#include "maxslice/core/assert.hpp"

namespace maxslice::machine {
namespace {

/// The head is "already there" when the last position is this close (mm).
constexpr double kAlreadyThereMm = 1e-9;

const Move* last_positioning(const Program& program) {
    for (auto it = program.moves.rbegin(); it != program.moves.rend(); ++it) {
        if (it->kind == MoveKind::kTravel || it->kind == MoveKind::kDeposit) return &*it;
    }
    return nullptr;
}

}  // namespace

void append_travel(Program& program, const core::Vec3d& to, const ProcessProfile& process,
                   int layer, int region, const core::Vec3d& direction) {
    Move m;
    m.kind = MoveKind::kTravel;
    m.position = to;
    m.direction = direction;
    m.feed_mm_min = process.travel_feed_mm_min;
    m.laser_w = process.laser_power_off_w;
    m.layer = layer;
    m.region = region;
    program.moves.push_back(m);
}

void append_wire(Program& program, std::span<const core::Vec3d> points,
                 const ProcessProfile& process, int layer, int region,
                 const core::Vec3d& direction) {
    if (points.size() < 2) return;
    const std::vector<double> feeds(points.size() - 1, process.deposition_feed_mm_min);
    append_wire(program, points, feeds, process, layer, region, direction);
}

void append_wire(Program& program, std::span<const core::Vec3d> points,
                 std::span<const double> feeds, const ProcessProfile& process, int layer,
                 int region, const core::Vec3d& direction) {
    if (points.size() < 2) return;
    MAXSLICE_ASSERT(feeds.size() + 1 == points.size());
    const Move* last = last_positioning(program);
    if (last == nullptr || core::norm(last->position - points.front()) > kAlreadyThereMm) {
        append_travel(program, points.front(), process, layer, region, direction);
    }
    Move on;
    on.kind = MoveKind::kLaserOn;
    on.position = points.front();
    on.direction = direction;
    on.laser_w = process.laser_power_w;
    on.powder_g_min = process.powder_feed_g_min;
    on.dwell_ms = process.dwell_after_laser_on_ms;
    on.layer = layer;
    on.region = region;
    program.moves.push_back(on);
    for (std::size_t i = 1; i < points.size(); ++i) {
        Move d = on;
        d.kind = MoveKind::kDeposit;
        d.position = points[i];
        d.feed_mm_min = feeds[i - 1];
        d.dwell_ms = 0.0;
        program.moves.push_back(d);
    }
    Move off = on;
    off.kind = MoveKind::kLaserOff;
    off.position = points.back();
    off.laser_w = process.laser_power_off_w;
    off.powder_g_min = 0.0;
    off.dwell_ms = 0.0;
    program.moves.push_back(off);
}

}  // namespace maxslice::machine
