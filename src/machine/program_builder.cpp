#include "maxslice/machine/program_builder.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "maxslice/core/assert.hpp"

namespace maxslice::machine {
namespace {

/// The head is "already there" when the last position is this close (mm).
constexpr double kAlreadyThereMm = 1e-9;
/// Two unit directions this close are one (the head is not turned between them).
constexpr double kSameDirection = 1e-9;

const Move* last_positioning(const Program& program) {
    for (auto it = program.moves.rbegin(); it != program.moves.rend(); ++it) {
        if (it->kind == MoveKind::kTravel || it->kind == MoveKind::kDeposit) return &*it;
    }
    return nullptr;
}

// A travel to `to` with the laser at the process's off power, no powder, at its travel feed.
Move travel_to(const core::Vec3d& to, const ProcessProfile& process, int layer, int region,
               const core::Vec3d& direction) {
    Move m;
    m.kind = MoveKind::kTravel;
    m.position = to;
    m.direction = direction;
    m.feed_mm_min = process.travel_feed_mm_min;
    m.laser_w = process.laser_power_off_w;
    m.layer = layer;
    m.region = region;
    return m;
}

// Laser and powder off at `at`, in the layer, region and direction of `like`.
Move laser_off(const Move& like, const core::Vec3d& at, const ProcessProfile& process) {
    Move off = like;
    off.kind = MoveKind::kLaserOff;
    off.position = at;
    off.feed_mm_min = 0.0;
    off.laser_w = process.laser_power_off_w;
    off.powder_g_min = 0.0;
    off.dwell_ms = 0.0;
    return off;
}

// Distance from p to the segment [a, b].
double to_segment(const core::Vec3d& p, const core::Vec3d& a, const core::Vec3d& b) {
    const core::Vec3d ab = b - a;
    const double len2 = core::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(core::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return core::norm(p - (a + ab * t));
}

}  // namespace

void append_travel(Program& program, const core::Vec3d& to, const ProcessProfile& process,
                   int layer, int region, const core::Vec3d& direction) {
    program.moves.push_back(travel_to(to, process, layer, region, direction));
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
    program.moves.push_back(laser_off(on, points.back(), process));
}

double leave_out_deposits(Program& program, std::span<const core::Vec3d> tips,
                          const ProcessProfile& process, double within_mm) {
    if (tips.empty()) return 0.0;
    // The tips by X: a track's candidates are those within its X range.
    std::vector<core::Vec3d> by_x(tips.begin(), tips.end());
    std::sort(by_x.begin(), by_x.end(),
              [](const core::Vec3d& a, const core::Vec3d& b) { return a.x < b.x; });
    const auto near_a_tip = [&](const core::Vec3d& a, const core::Vec3d& b) {
        auto it = std::lower_bound(by_x.begin(), by_x.end(), std::min(a.x, b.x) - within_mm,
                                   [](const core::Vec3d& t, double x) { return t.x < x; });
        for (; it != by_x.end() && it->x <= std::max(a.x, b.x) + within_mm; ++it) {
            if (to_segment(*it, a, b) <= within_mm) return true;
        }
        return false;
    };
    std::vector<Move> out;
    out.reserve(program.moves.size());
    core::Vec3d at{};               // where the head is
    bool on = false;                // the laser as written so far
    std::optional<Move> switch_on;  // the laser-on of the wire being read
    double left_out = 0.0;
    for (const Move& m : program.moves) {
        switch (m.kind) {
            case MoveKind::kLaserOn: switch_on = m; break;
            case MoveKind::kLaserOff:
                if (on) {
                    Move off = m;
                    off.position = at;
                    out.push_back(off);
                    on = false;
                }
                break;
            case MoveKind::kTravel:
                out.push_back(m);
                at = m.position;
                break;
            case MoveKind::kDeposit: {
                if (!near_a_tip(at, m.position)) {
                    if (!on && switch_on) {
                        Move again = *switch_on;
                        again.position = at;
                        out.push_back(again);
                        on = true;
                    }
                    out.push_back(m);
                } else {
                    if (on) {
                        out.push_back(laser_off(m, at, process));
                        on = false;
                    }
                    out.push_back(travel_to(m.position, process, m.layer, m.region, m.direction));
                    left_out += core::norm(m.position - at);
                }
                at = m.position;
                break;
            }
        }
    }
    program.moves = std::move(out);
    return left_out;
}

std::size_t lift_travels(Program& program, std::span<const core::Vec3d> ends, double within_mm,
                         const std::function<double(const core::Vec3d&)>& top_mm) {
    if (ends.empty()) return 0;
    const auto flagged = [&](const core::Vec3d& p) {
        return std::any_of(ends.begin(), ends.end(),
                           [&](const core::Vec3d& e) { return core::norm(e - p) <= within_mm; });
    };
    std::vector<Move> out;
    out.reserve(program.moves.size());
    std::optional<Move> last;  // the last positioning move
    std::size_t lifted = 0;
    for (const Move& m : program.moves) {
        const bool positions = m.kind == MoveKind::kTravel || m.kind == MoveKind::kDeposit;
        if (m.kind == MoveKind::kTravel && last &&
            core::norm(last->direction - m.direction) < kSameDirection && flagged(m.position)) {
            const core::Vec3d& d = m.direction;
            const double top = top_mm(d);
            const double up_from = top - core::dot(last->position, d);
            const double up_to = top - core::dot(m.position, d);
            if (up_from > 0.0) {
                Move up = m;
                up.position = last->position + d * up_from;
                out.push_back(up);
            }
            if (up_to > 0.0) {
                Move across = m;
                across.position = m.position + d * up_to;
                out.push_back(across);
            }
            ++lifted;
        }
        out.push_back(m);
        if (positions) last = m;
    }
    program.moves = std::move(out);
    return lifted;
}

}  // namespace maxslice::machine
