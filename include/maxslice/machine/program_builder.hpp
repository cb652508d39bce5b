#pragma once

#include <cstddef>
#include <functional>
#include <span>

#include "maxslice/core/vec3.hpp"
#include "maxslice/machine/profile.hpp"
#include "maxslice/machine/program.hpp"

namespace maxslice::machine {

/// Appends a travel move to `to` (part coordinates, mm) with the laser at the process's off
/// power, no powder, at the process's travel feed.
void append_travel(Program& program, const core::Vec3d& to, const ProcessProfile& process,
                   int layer, int region = 0, const core::Vec3d& direction = {0.0, 0.0, 1.0});

/// Appends one deposited wire with the process's nominal values: a travel to the first point
/// (left out when the head is already there), laser-on there with the process's dwell, a
/// deposit move to each further point at the deposition feed, power and powder feed, and
/// laser-off at the last point. A wire of fewer than 2 points appends nothing.
void append_wire(Program& program, std::span<const core::Vec3d> points,
                 const ProcessProfile& process, int layer, int region = 0,
                 const core::Vec3d& direction = {0.0, 0.0, 1.0});

/// append_wire with a feed per segment: `feeds[i]` (mm/min) runs from points[i] to
/// points[i + 1] (feeds.size() == points.size() - 1), e.g. from the speed law for the local
/// thickness of a wedge layer (METHOD.md section 10).
void append_wire(Program& program, std::span<const core::Vec3d> points,
                 std::span<const double> feeds, const ProcessProfile& process, int layer,
                 int region = 0, const core::Vec3d& direction = {0.0, 0.0, 1.0});

/// Leaves out of `program` the deposit moves whose track passes within `within_mm` of one of
/// `tips` (part coordinates): each becomes a travel along the same path at the travel feed,
/// with the laser switched off before it and on again (the process's dwell) before the next
/// deposit move kept. The job leaves out the beads the verifier finds resting on nothing
/// (docs/decisions/0039). Returns the length of track left out (mm).
double leave_out_deposits(Program& program, std::span<const core::Vec3d> tips,
                          const ProcessProfile& process, double within_mm);

/// Takes the travel moves that end within `within_mm` of one of `ends` (part coordinates) and
/// keep the head's direction over the part: up along the direction to `top_mm` along it,
/// across, and down to where the travel ended (a leg is left out where the head is that high
/// already). The job lifts the travels the verifier finds meeting the part or within the
/// clearance (docs/decisions/0048). Returns how many travels were lifted.
std::size_t lift_travels(Program& program, std::span<const core::Vec3d> ends, double within_mm,
                         const std::function<double(const core::Vec3d&)>& top_mm);

}  // namespace maxslice::machine
