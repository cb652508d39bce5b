// The independent verifier (METHOD.md section 12, docs/verifier.md): replays a program through
// the forward kinematics, lays beads in a voxel grid as it goes and checks the head against
// the material of earlier blocks. It shares nothing with the planner.
#include "maxslice/verify/verify.hpp"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <string_view>
#include <utility>

#include "maxslice/machine/kinematics.hpp"
#include "maxslice/machine/speed_law.hpp"
#include "model_voxels.hpp"
#include "region_query.hpp"
#include "stock_distance.hpp"
#include "voxel_grid.hpp"

namespace maxslice::verify {
namespace {

using core::ErrorCode;
using core::Vec3d;
using detail::OccupancyPyramid;
using detail::Region;

/// Nozzle points closer than this many voxels to the apex (along the axis) are not checked:
/// the bead under the tip touches the apex by construction (voxel centres lie up to half a
/// voxel off the bead's true top).
constexpr double kApexToleranceVoxels = 1.0;
/// Support: earlier material is looked for from this many voxels below the bead's bottom
/// (so the neighbouring track of the same layer does not count) ...
constexpr double kSupportGapVoxels = 0.25;
/// ... down to this many voxels further (a layer below found within about two voxels).
constexpr double kSupportDepthVoxels = 2.0;
/// ... and across to half a track plus this many voxels: a voxel counts only when its centre
/// lies inside a bead, so a bead's voxel image can end up to one voxel inside its true edge;
/// without the slack, support within half a track in exact geometry would be missed at
/// random (decision 0010).
constexpr double kSupportReachSlackVoxels = 1.0;
/// A bead bottom this many voxels above the plate (part z = 0) or lower rests on the plate.
constexpr double kPlateToleranceVoxels = 1.0;
/// The automatic grid is coarsened by this factor at a time ...
constexpr double kCoarsenStep = 1.25;
/// ... until it holds this many voxels (about 160 MB), unless the layers need it finer
/// (VerifySettings::max_voxels bounds it then).
constexpr double kPreferredVoxels = 4.0e8;
/// Without a substrate, a head reaching less than this below the plate's level is not noted.
constexpr double kBelowPlateToleranceMm = 1e-6;
/// Axis values within this of a limit pass (the program rounds to 3 decimals).
constexpr double kLimitToleranceMmOrDeg = 1e-6;
/// Most poses checked along one block (a 100 m move at 1 mm; a program sending the tool
/// farther is caught by the axis limits).
constexpr double kMaxSamples = 1.0e5;
/// A block's poses are checked side by side from this many on (fewer: one after another, the
/// threads would cost more than they save).
constexpr std::size_t kSideBySidePoses = 8;
/// Subdivisions used to estimate the path of a move that turns the table.
constexpr int kArcProbe = 16;
/// The machining stock is searched this far (mm) from the finished part's surface, and at
/// least kStockSearchVoxels voxels; stocks from practice are 0.5 - 3 mm (decision 0026).
constexpr double kStockSearchMm = 5.0;
constexpr int kStockSearchVoxels = 8;
/// The distance search's planes stay within this many bytes (a finer grid searches fewer
/// voxels out).
constexpr std::size_t kStockSearchBytes = std::size_t{256} << 20;

double lerp(double a, double b, double t) {
    return a + (b - a) * t;
}

machine::MachinePose lerp(const machine::MachinePose& a, const machine::MachinePose& b, double t) {
    return {lerp(a.x, b.x, t), lerp(a.y, b.y, t), lerp(a.z, b.z, t),
            lerp(a.a_or_b_deg, b.a_or_b_deg, t), lerp(a.c_deg, b.c_deg, t)};
}

Vec3d any_perpendicular(const Vec3d& d) {
    const Vec3d other = std::abs(d.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
    return core::normalized(core::cross(d, other));
}

struct Sample {
    machine::MachinePose pose;
    Vec3d tip;
    Vec3d dir;
};

class Verifier {
public:
    Verifier(const machine::Profiles& profiles, const machine::MachineKinematics& kin,
             const VerifySettings& settings, const machine::NozzleProfile& nozzle)
        : profiles_(profiles),
          process_(profiles.process),
          kin_(kin),
          settings_(settings),
          nozzle_(nozzle),
          law_(machine::SpeedLaw::of(profiles.process)) {
        clearance_ = settings.clearance_mm.value_or(
            profiles.machine.nozzle ? profiles.machine.nozzle->clearance_mm : 0.0);
        if (const auto& p = profiles.machine.substrate) {
            const Vec3d c = machine::plate_center(profiles.machine);
            substrate_ = Box{{c.x - 0.5 * p->size_x_mm, c.y - 0.5 * p->size_y_mm, -p->thickness_mm},
                             {c.x + 0.5 * p->size_x_mm, c.y + 0.5 * p->size_y_mm, 0.0}};
        }
    }

    core::Result<Report> run(const Replay& replay, const mesh::TriangleMesh& model,
                             const mesh::TriangleMesh* finished) {
        Report rep;
        rep.dialect = std::string(dialect_name(replay.dialect));
        rep.machine_kinematics =
            std::string(machine::kinematics_name(profiles_.machine.kinematics));
        rep.lines = replay.line_count;
        rep.laser_on_count = replay.laser_on_count;
        rep.clearance_mm = clearance_;
        rep.min_coverage = settings_.min_coverage;
        rep.max_excess = settings_.max_excess;
        note_program_faults(replay, rep);
        if (auto ok = setup_grid(replay, model, finished, rep); !ok) {
            return std::unexpected(ok.error());
        }
        // The model's (and the finished part's) voxels are needed only for the volumes at the
        // end: they are made on other cores while the program is replayed.
        tbb::task_group model_task;
        model_task.run(
            [&] { model_ = detail::voxelize_model(model, origin_, voxel_, nx_, ny_, nz_); });
        if (finished != nullptr) {
            model_task.run([&] {
                finished_ = detail::voxelize_model(*finished, origin_, voxel_, nx_, ny_, nz_);
            });
        }
        build_regions();

        double hmin = std::numeric_limits<double>::infinity(), hmax = 0.0;
        bool prev_known = false;
        for (const ReplayBlock& b : replay.blocks) {
            if (b.kind == ReplayBlock::Kind::kDwell) {
                rep.dwell_time_s += b.dwell_s;
                continue;
            }
            ++rep.moves;
            check_limits(b, b.pose, rep, true);
            const bool deposit = b.laser_on;
            // A wire ends where the next move does not continue it: its round end goes in
            // before this move is checked.
            const bool joined =
                deposit && prev_known && b.pose_known && open_end_ &&
                core::norm(open_end_->tip - kin_.forward(b.from).tip_mm) < 0.5 * voxel_;
            if (open_end_ && !joined) {
                lay_joint(open_end_->tip, open_end_->dir, open_end_->h);
                open_end_.reset();
            }
            if (!prev_known || !b.pose_known) {
                prev_known = b.pose_known;
                continue;
            }
            prev_known = true;
            const double h = deposit ? law_.height_mm(b.feed_mm_min) : 0.0;
            if (deposit) {
                ++rep.deposit_moves;
                hmin = std::min(hmin, h);
                hmax = std::max(hmax, h);
            }
            sample_block(b, samples_);
            const std::vector<Sample>& samples = samples_;
            // Lengths and time.
            const Vec3d programmed_from =
                b.tcp ? kin_.forward(b.from).tip_mm : Vec3d{b.from.x, b.from.y, b.from.z};
            const Vec3d programmed_to = b.tcp ? b.tip_mm : Vec3d{b.pose.x, b.pose.y, b.pose.z};
            const double linear = core::norm(programmed_to - programmed_from);
            const double rotary = std::abs(b.pose.a_or_b_deg - b.from.a_or_b_deg) +
                                  std::abs(b.pose.c_deg - b.from.c_deg);
            rep.rotary_travel_deg += rotary;
            const double time_s = 60.0 * (linear > 0.0 ? linear : rotary) / b.feed_mm_min;
            double tip_path = 0.0, machine_path = 0.0;
            for (std::size_t i = 1; i < samples.size(); ++i) {
                tip_path += core::norm(samples[i].tip - samples[i - 1].tip);
                const auto& p = samples[i].pose;
                const auto& q = samples[i - 1].pose;
                machine_path += core::norm(Vec3d{p.x - q.x, p.y - q.y, p.z - q.z});
            }
            if (deposit) {
                rep.deposition_length_mm += tip_path;
                rep.deposit_time_s += time_s;
            } else {
                rep.idle_length_mm += machine_path;
                rep.idle_time_s += time_s;
            }
            // Checks against the material of earlier blocks, then this block's bead.
            if (b.tcp) {
                for (std::size_t i = 1; i + 1 < samples.size(); ++i) {
                    if (!check_limits(b, samples[i].pose, rep, false)) break;
                }
            }
            check_collisions(b, samples, rep);
            if (deposit) {
                check_support(b, samples, h, rep);
                const bool turns =
                    b.pose.a_or_b_deg != b.from.a_or_b_deg || b.pose.c_deg != b.from.c_deg;
                lay_bead(samples, h, joined, turns);
                if (!joined) lay_joint(samples.front().tip, samples.front().dir, h);
                open_end_ = OpenEnd{samples.back().tip, samples.back().dir, h};
            }
        }
        if (open_end_) lay_joint(open_end_->tip, open_end_->dir, open_end_->h);
        rep.poses_checked = poses_checked_;
        rep.bead_height_min_mm = rep.deposit_moves > 0 ? hmin : 0.0;
        rep.bead_height_max_mm = hmax;
        rep.build_time_s = rep.deposit_time_s + rep.idle_time_s + rep.dwell_time_s;
        rep.unsupported_length_mm = unsupported_length_;
        model_task.wait();
        measure_volumes(rep);
        measure_finished(rep, finished != nullptr ? finished_ : model_);
        rep.finished_given = finished != nullptr;
        return rep;
    }

private:
    // What the replay found in the program's values and its end (not in its geometry).
    static void note_program_faults(const Replay& replay, Report& rep) {
        if (const ReplayFault& f = replay.out_of_range; f.count > 0) {
            rep.out_of_range = Finding{f.count, Location{f.line, f.tip_mm, f.detail}};
        }
        const bool needs_end_code = replay.dialect != ProgramDialect::kGm;
        if (replay.cut || (needs_end_code && !replay.end_code)) {
            std::string what =
                replay.cut ? "the last line has no line break: the program is cut off" : "";
            if (needs_end_code && !replay.end_code) {
                what +=
                    fmt::format("{}the program ends without M2 or M30", what.empty() ? "" : "; ");
            }
            rep.unfinished = Finding{1, Location{replay.last_line, replay.end_tip_mm, what}};
        }
        if (replay.laser_on_at_end || replay.powder_on_at_end) {
            const std::string what =
                replay.laser_on_at_end && replay.powder_on_at_end
                    ? "the laser and the powder are"
                    : (replay.laser_on_at_end ? "the laser is" : "the powder is");
            rep.left_on =
                Finding{1, Location{replay.last_line, replay.end_tip_mm,
                                    what + " still on after the program's last line read"}};
        }
    }

    core::Result<void> setup_grid(const Replay& replay, const mesh::TriangleMesh& model,
                                  const mesh::TriangleMesh* finished, Report& rep) {
        core::Box3d box = mesh::bounding_box(model);
        if (finished != nullptr) {
            const core::Box3d f = mesh::bounding_box(*finished);
            if (!f.empty()) {
                box.add(f.min);
                box.add(f.max);
            }
        }
        double reach = 0.0;
        double thinnest = std::numeric_limits<double>::infinity();
        for (const ReplayBlock& b : replay.blocks) {
            if (b.kind != ReplayBlock::Kind::kMove || !b.laser_on || !b.pose_known) continue;
            const double h = law_.height_mm(b.feed_mm_min);
            reach = std::max(reach, std::max(h, 0.5 * process_.track_width_mm));
            if (h > 0.0) thinnest = std::min(thinnest, h);
            box.add(b.tip_mm);
            box.add(kin_.forward(b.from).tip_mm);
            // A joint-space deposit that turns the table (the contract has none) lays an arc.
            if (!b.tcp &&
                (b.pose.a_or_b_deg != b.from.a_or_b_deg || b.pose.c_deg != b.from.c_deg)) {
                for (int i = 1; i < kArcProbe; ++i) {
                    box.add(kin_.forward(lerp(b.from, b.pose, static_cast<double>(i) / kArcProbe))
                                .tip_mm);
                }
            }
        }
        if (box.empty()) {
            return core::fail(ErrorCode::kInvalidInput,
                              "nothing to verify: the model is empty and the program deposits "
                              "nothing");
        }
        double v = settings_.voxel_mm;
        const bool automatic = v <= 0.0;
        if (automatic) v = std::min(process_.track_width_mm / 4.0, process_.h_min_mm / 2.0);
        // The support check sees the layer under a bead only through voxel centres between
        // kSupportGapVoxels voxels under the bead's bottom and the layer's own bottom: a voxel
        // finer than the thinnest bead by that share puts one in every column.
        const double resolves = thinnest / (1.0 + kSupportGapVoxels);
        const auto unresolved = [&](const Vec3d& size) {
            const std::string need = fmt::format(
                "its thinnest bead is {:.3f} mm high, so the support check needs voxels of at most "
                "{:.3f} mm",
                thinnest, resolves);
            if (!automatic) {
                return core::fail(ErrorCode::kInvalidInput,
                                  fmt::format("the verifier cannot see this program's layers "
                                              "with {:g} mm voxels: {}",
                                              v, need),
                                  "--voxel");
            }
            return core::fail(
                ErrorCode::kInvalidInput,
                fmt::format("the verifier cannot see this program's layers: {}, and over {:.1f} x "
                            "{:.1f} x {:.1f} mm those are more than the {:.3g} voxels it may hold; "
                            "a model read in the wrong unit (--units) makes the grid this large",
                            need, size.x, size.y, size.z, settings_.max_voxels),
                "verify grid");
        };
        if (automatic) v = std::min(v, resolves);
        for (;;) {
            const double margin = reach * 1.5 + 3.0 * v;
            const Vec3d lo = box.min - Vec3d{margin, margin, margin};
            const Vec3d size = box.size() + Vec3d{2 * margin, 2 * margin, 2 * margin};
            const double n = std::ceil(size.x / v) * std::ceil(size.y / v) * std::ceil(size.z / v);
            // The automatic grid coarsens to hold kPreferredVoxels, but no further than the
            // layers allow: then it may hold up to max_voxels.
            const bool may_coarsen = automatic && v * kCoarsenStep <= resolves;
            if (n <= (may_coarsen ? std::min(kPreferredVoxels, settings_.max_voxels)
                                  : settings_.max_voxels)) {
                if (v > resolves) return unresolved(size);
                // A fixed small shift of the origin keeps voxel centres off round coordinates,
                // where axis-aligned model faces usually lie.
                origin_ = lo - Vec3d{v * 0.01234567, v * 0.02345678, v * 0.01357913};
                nx_ = static_cast<int>(std::ceil(size.x / v)) + 1;
                ny_ = static_cast<int>(std::ceil(size.y / v)) + 1;
                nz_ = static_cast<int>(std::ceil(size.z / v)) + 1;
                break;
            }
            if (!automatic) {
                return core::fail(ErrorCode::kInvalidInput,
                                  fmt::format("a {:.4f} mm voxel grid over {:.1f} x {:.1f} x "
                                              "{:.1f} mm needs {:.3g} voxels, more than {:.3g}",
                                              v, size.x, size.y, size.z, n, settings_.max_voxels),
                                  "--voxel");
            }
            if (!may_coarsen) return unresolved(size);
            v *= kCoarsenStep;
        }
        voxel_ = v;
        rep.voxel_mm = v;
        sample_ = settings_.sample_mm > 0.0
                      ? settings_.sample_mm
                      : std::max(v, std::min(1.0, 0.5 * process_.track_width_mm));
        rep.sample_mm = sample_;
        grid_ = OccupancyPyramid(nx_, ny_, nz_);
        return {};
    }

    void build_regions() {
        const double t = std::tan(nozzle_.half_angle_deg * std::numbers::pi / 180.0);
        const double apex = kApexToleranceVoxels * voxel_;
        const double len = nozzle_.cone_length_mm;
        nozzle_region_ = Region{};
        nozzle_region_.add(
            {{{apex, -apex * t}, {len, -len * t}, {len, len * t}, {apex, apex * t}}});
        if (nozzle_.body_radius_mm > 0.0 && nozzle_.body_length_mm > 0.0) {
            const double r = nozzle_.body_radius_mm, top = len + nozzle_.body_length_mm;
            nozzle_region_.add({{{len, -r}, {top, -r}, {top, r}, {len, r}}});
        }
        // The hardware, which keeps clearance_ (decision 0023): the cone above the nozzle tip
        // and the body. The outline's cone is split at the tip for the substrate check.
        const double nozzle_tip = std::max(apex, nozzle_.standoff_mm);
        hardware_region_ = Region{};
        if (len > nozzle_tip) {
            hardware_region_.add({{{nozzle_tip, -nozzle_tip * t},
                                   {len, -len * t},
                                   {len, len * t},
                                   {nozzle_tip, nozzle_tip * t}}});
        }
        if (nozzle_.body_radius_mm > 0.0 && nozzle_.body_length_mm > 0.0) {
            const double r = nozzle_.body_radius_mm, top = len + nozzle_.body_length_mm;
            hardware_region_.add({{{len, -r}, {top, -r}, {top, r}, {len, r}}});
        }
        head_outline_.clear();
        if (nozzle_tip > apex) {
            head_outline_.push_back({{apex, apex * t}, {nozzle_tip, nozzle_tip * t}});
        }
        if (len > nozzle_tip) {
            head_outline_.push_back({{nozzle_tip, nozzle_tip * t}, {len, len * t}});
        }
        if (nozzle_.body_radius_mm > 0.0 && nozzle_.body_length_mm > 0.0) {
            const double r = nozzle_.body_radius_mm;
            head_outline_.push_back({{len, r}, {len + nozzle_.body_length_mm, r}});
        }
        head_reach_ = 0.0;
        for (const auto& [p, q] : head_outline_) {
            head_reach_ = std::max({head_reach_, std::hypot(p.t, p.r), std::hypot(q.t, q.r)});
        }
    }

    // Poses along a move: joint-space blocks interpolate every axis, tool-centre-point blocks
    // move the tip linearly in the part frame (rotary axes linear). At most sample_ between
    // neighbours, for the tip and for the far end of the head.
    void sample_block(const ReplayBlock& b, std::vector<Sample>& out) const {
        const Vec3d tip0 = kin_.forward(b.from).tip_mm;
        const bool turns = b.pose.a_or_b_deg != b.from.a_or_b_deg || b.pose.c_deg != b.from.c_deg;
        const auto at = [&](double t) {
            Sample s;
            s.pose = lerp(b.from, b.pose, t);
            if (!turns) {
                // Fixed rotary values: forward is affine in X Y Z, and in tool-centre-point
                // mode X Y Z are affine in the tip, so everything is linear along the block.
                s.tip = tip0 + (b.tip_mm - tip0) * t;
                s.dir = b.direction;
                return s;
            }
            if (b.tcp) {
                const Vec3d tip = tip0 + (b.tip_mm - tip0) * t;
                const Vec3d m = linear_axes_for_tip(kin_, tip, s.pose);
                s.pose.x = m.x;
                s.pose.y = m.y;
                s.pose.z = m.z;
            }
            const machine::ToolPose tp = kin_.forward(s.pose);
            s.tip = tp.tip_mm;
            s.dir = tp.direction;
            return s;
        };
        double path = 0.0;
        if (!turns) {
            path = core::norm(b.tip_mm - tip0);
        } else {
            const double reach = nozzle_.cone_length_mm + nozzle_.body_length_mm;
            Sample prev = at(0.0);
            for (int i = 1; i <= kArcProbe; ++i) {
                const Sample s = at(static_cast<double>(i) / kArcProbe);
                const double dt = core::norm(s.tip - prev.tip);
                const double dtop =
                    core::norm((s.tip + s.dir * reach) - (prev.tip + prev.dir * reach));
                path += std::max(dt, dtop);
                prev = s;
            }
        }
        const int n = static_cast<int>(std::clamp(std::ceil(path / sample_), 1.0, kMaxSamples));
        out.clear();
        for (int i = 0; i <= n; ++i) out.push_back(at(static_cast<double>(i) / n));
    }

    // Returns false when a violation was recorded (one per block).
    bool check_limits(const ReplayBlock& b, const machine::MachinePose& pose, Report& rep,
                      bool endpoint) {
        if (endpoint) limit_block_counted_ = false;
        if (limit_block_counted_) return false;
        const std::array<double, 5> values{pose.x, pose.y, pose.z, pose.a_or_b_deg, pose.c_deg};
        const std::size_t axes = machine::is_table_tilt(profiles_.machine.kinematics) ? 5 : 3;
        for (std::size_t i = 0; i < axes && i < profiles_.machine.axes.size(); ++i) {
            const machine::AxisLimits& lim = profiles_.machine.axes[i];
            const double v = values[i];
            if (v >= lim.min - kLimitToleranceMmOrDeg && v <= lim.max + kLimitToleranceMmOrDeg) {
                continue;
            }
            if (endpoint && !b.pose_known && !axis_programmed(b, i)) continue;
            limit_block_counted_ = true;
            ++rep.limit_violations.count;
            if (!rep.limit_violations.first) {
                rep.limit_violations.first =
                    Location{b.line, kin_.forward(pose).tip_mm,
                             fmt::format("{} = {:.3f} outside machine.axes.{} [{:.3f}, {:.3f}]",
                                         lim.name, v, lim.name, lim.min, lim.max)};
            }
            return false;
        }
        return true;
    }

    // Before the whole pose is known only the axes the block changed are checked.
    static bool axis_programmed(const ReplayBlock& b, std::size_t axis) {
        const std::array<double, 5> from{b.from.x, b.from.y, b.from.z, b.from.a_or_b_deg,
                                         b.from.c_deg};
        const std::array<double, 5> to{b.pose.x, b.pose.y, b.pose.z, b.pose.a_or_b_deg,
                                       b.pose.c_deg};
        return from[axis] != to[axis];
    }

    void check_collisions(const ReplayBlock& b, const std::vector<Sample>& samples, Report& rep) {
        // One per block: the first pose whose head meets material, or the substrate.
        const auto travel_fault = [&] {
            if (!b.laser_on && !samples.empty() &&
                rep.travel_fault_ends.size() < Report::kMaxUnsupportedTips) {
                rep.travel_fault_ends.push_back(samples.back().tip);
            }
        };
        const auto collide = [&](const Sample& s, const Vec3d& hit, std::string_view what) {
            travel_fault();
            ++rep.collisions.count;
            if (!rep.collisions.first) {
                rep.collisions.first = Location{
                    b.line, hit,
                    fmt::format("{} with the tip at ({:.3f}, {:.3f}, {:.3f}): the head meets {}",
                                b.laser_on ? "deposit" : "travel", s.tip.x, s.tip.y, s.tip.z,
                                what)};
            }
        };
        // The first pose whose hardware comes within clearance_ without contact: counted when
        // the whole block makes no contact.
        std::optional<Location> near;
        const auto within = [&](const Sample& s, const Vec3d& hit, std::string_view what) {
            near = Location{b.line, hit,
                            fmt::format("{} with the tip at ({:.3f}, {:.3f}, {:.3f}): the nozzle "
                                        "or head body comes within {:.2f} mm of {}",
                                        b.laser_on ? "deposit" : "travel", s.tip.x, s.tip.y,
                                        s.tip.z, clearance_, what)};
        };
        // Every pose against the material of earlier blocks, side by side (the grid does not
        // change within a block), then taken in order as one pose after another would be.
        const bool clearance = clearance_ > 0.0;
        std::vector<PoseFinding>& found = pose_findings_;
        found.assign(samples.size(), PoseFinding{});
        for_each_sample(samples.size(), [&](std::size_t i) {
            const Sample& s = samples[i];
            PoseFinding& f = found[i];
            if (detail::find_occupied(grid_, origin_, voxel_, s.tip, s.dir, nozzle_region_, 0.0,
                                      &f.hit)) {
                f.contact = true;
                return;
            }
            if (substrate_ && substrate_hit(s.tip, s.dir, 0.0, false, &f.hit)) {
                f.contact_plate = true;
                return;
            }
            if (!clearance) return;
            if (detail::find_occupied(grid_, origin_, voxel_, s.tip, s.dir, hardware_region_,
                                      clearance_, &f.near_hit)) {
                f.near = true;
            } else if (substrate_ && substrate_hit(s.tip, s.dir, clearance_, true, &f.near_hit)) {
                f.near_plate = true;
            }
        });
        for (std::size_t i = 0; i < samples.size(); ++i) {
            const Sample& s = samples[i];
            const PoseFinding& f = found[i];
            ++poses_checked_;
            if (f.contact) {
                collide(s, f.hit, "material deposited earlier");
                return;
            }
            if (!substrate_) {
                note_below_plate(b, s, rep);
            } else if (f.contact_plate) {
                collide(s, f.hit, "the substrate plate (machine.substrate)");
                return;
            }
            if (near || !clearance) continue;
            if (f.near) {
                within(s, f.near_hit, "material deposited earlier");
            } else if (f.near_plate) {
                within(s, f.near_hit, "the substrate plate (machine.substrate)");
            }
        }
        if (near) {
            travel_fault();
            ++rep.clearance.count;
            if (!rep.clearance.first) rep.clearance.first = std::move(near);
        }
    }

    // Whether the head standing at `tip` with axis `dir` comes within c of the substrate box
    // (with hardware_only, the outline from the nozzle tip up). The head is the nozzle region's
    // outline (the cone from a voxel above the apex, then the body) turned about the axis: its
    // lowest point lies on the circle of one of the outline's corners, so a head that stays
    // above the plate costs four circles; one that dips is sampled on its surface, a circle
    // every sample_ along the axis and 64 points on each (enough for a plate's face; the caps
    // of the body are not sampled).
    bool substrate_hit(const Vec3d& tip, const Vec3d& dir, double c, bool hardware_only,
                       Vec3d* hit) const {
        const Box& box = *substrate_;
        if (lowest_point(tip, dir).z >= box.hi.z + c) return false;
        // How far below its centre a circle of radius 1 about `dir` reaches.
        const double dip = std::sqrt(std::max(0.0, 1.0 - dir.z * dir.z));
        const auto below = [&](double t, double r) {
            return tip.z + dir.z * t - r * dip < box.hi.z + c;
        };
        const Vec3d e1 = any_perpendicular(dir), e2 = core::cross(dir, e1);
        constexpr int kAround = 64;
        for (const auto& [a, b] : head_outline_) {
            if (hardware_only && a.t < nozzle_.standoff_mm) continue;
            const int n = std::max(1, static_cast<int>(std::ceil((b.t - a.t) / sample_)));
            for (int k = 0; k <= n; ++k) {
                const double f = static_cast<double>(k) / n;
                const double t = lerp(a.t, b.t, f), r = lerp(a.r, b.r, f);
                if (!below(t, r)) continue;
                const Vec3d centre = tip + dir * t;
                for (int j = 0; j < kAround; ++j) {
                    const double phi = 2.0 * std::numbers::pi * j / kAround;
                    const Vec3d x = centre + (e1 * std::cos(phi) + e2 * std::sin(phi)) * r;
                    if (x.x >= box.lo.x - c && x.x <= box.hi.x + c && x.y >= box.lo.y - c &&
                        x.y <= box.hi.y + c && x.z >= box.lo.z - c && x.z <= box.hi.z + c) {
                        *hit = x;
                        return true;
                    }
                }
            }
        }
        return false;
    }

    // The head's lowest point at a pose: on the circle of one of its outline's corners. A pose
    // whose tip is farther above the plate than the head reaches gives just the tip's height
    // minus that reach (every point of the head lies within head_reach_ of the tip).
    Vec3d lowest_point(const Vec3d& tip, const Vec3d& dir) const {
        if (tip.z >= head_reach_) return tip - Vec3d{0, 0, head_reach_};
        const double dip = std::sqrt(std::max(0.0, 1.0 - dir.z * dir.z));
        Vec3d at{0, 0, std::numeric_limits<double>::infinity()};
        for (const auto& [p, q] : head_outline_) {
            for (const OutlinePoint& o : {p, q}) {
                if (tip.z + dir.z * o.t - o.r * dip >= at.z) continue;
                at = tip + dir * o.t;
                if (dip > 0.0) at = at + (Vec3d{0, 0, -1} + dir * dir.z) * (o.r / dip);
            }
        }
        return at;
    }

    // Without a substrate: how far the head at this pose reaches below the plate's level,
    // counted once per block.
    void note_below_plate(const ReplayBlock& b, const Sample& s, Report& rep) {
        const Vec3d at = lowest_point(s.tip, s.dir);
        const double lowest = at.z;
        if (lowest >= -kBelowPlateToleranceMm) return;
        rep.below_plate_mm = std::max(rep.below_plate_mm, -lowest);
        if (below_plate_line_ == b.line) return;
        below_plate_line_ = b.line;
        ++rep.below_plate.count;
        if (!rep.below_plate.first) {
            rep.below_plate.first = Location{
                b.line, at,
                fmt::format("{} with the tip at ({:.3f}, {:.3f}, {:.3f}): the head "
                            "reaches {:.1f} mm below the plate's level",
                            b.laser_on ? "deposit" : "travel", s.tip.x, s.tip.y, s.tip.z, -lowest)};
        }
    }

    // Whether a bead bottom at `base` rests on the plate: at its height and, with a substrate,
    // within half a track of its top face.
    bool on_plate(const Vec3d& base) const {
        if (base.z > kPlateToleranceVoxels * voxel_) return false;
        if (!substrate_) return true;
        const double w = 0.5 * process_.track_width_mm;
        return base.x >= substrate_->lo.x - w && base.x <= substrate_->hi.x + w &&
               base.y >= substrate_->lo.y - w && base.y <= substrate_->hi.y + w;
    }

    void check_support(const ReplayBlock& b, const std::vector<Sample>& samples, double h,
                       Report& rep) {
        Region region;
        const double top = -(h + kSupportGapVoxels * voxel_);
        const double bottom = top - kSupportDepthVoxels * voxel_;
        const double r = 0.5 * process_.track_width_mm + kSupportReachSlackVoxels * voxel_;
        region.add({{{bottom, -r}, {top, -r}, {top, r}, {bottom, r}}});
        bool counted = false;
        const double piece = samples.size() > 1
                                 ? core::norm(samples.back().tip - samples.front().tip) /
                                       static_cast<double>(samples.size() - 1)
                                 : 0.0;
        // Every pose side by side (the grid does not change within a block), then in order.
        std::vector<PoseFinding>& found = pose_findings_;
        found.assign(samples.size(), PoseFinding{});
        for_each_sample(samples.size(), [&](std::size_t i) {
            const Sample& s = samples[i];
            found[i].contact = on_plate(s.tip - s.dir * h) ||
                               detail::find_occupied(grid_, origin_, voxel_, s.tip, s.dir, region,
                                                     0.0, &found[i].hit);
        });
        for (std::size_t i = 0; i < samples.size(); ++i) {
            const Vec3d base = samples[i].tip - samples[i].dir * h;
            if (found[i].contact) continue;  // on the plate or on earlier material
            if (i > 0) unsupported_length_ += piece;
            if (rep.unsupported_tips.size() < Report::kMaxUnsupportedTips) {
                rep.unsupported_tips.push_back(samples[i].tip);
            }
            if (!counted) {
                counted = true;
                ++rep.unsupported.count;
                if (!rep.unsupported.first) {
                    rep.unsupported.first = Location{
                        b.line, base,
                        fmt::format("bead bottom at ({:.3f}, {:.3f}, {:.3f}) rests on nothing "
                                    "(no earlier material within {:.3f} mm below, {:.3f} mm "
                                    "across, and not on the plate)",
                                    base.x, base.y, base.z,
                                    (kSupportGapVoxels + kSupportDepthVoxels) * voxel_, r)};
                }
            }
        }
    }

    // The bead of one block: boxes track_width wide and h high under the tip (top edge centre
    // at the tip). A block that keeps its direction is laid in straight pieces of up to four track
    // widths (longer pieces waste time on their bounding boxes). Where the track turns by phi
    // (within the block, or from the previous block's bead), the outer corner is closed: up to 90
    // deg by a mitre (both pieces extended by w/2 tan(phi/2) past the corner), beyond by a round
    // joint (an octagonal prism). Wire ends get the same round joint (run() lays them): the
    // melt pool is a disc of the track's width.
    void lay_bead(const std::vector<Sample>& samples, double h, bool joined_to_previous,
                  bool turns) {
        const double w = process_.track_width_mm;
        const std::size_t stride =
            turns ? 1 : std::max<std::size_t>(1, static_cast<std::size_t>(4.0 * w / sample_));
        std::vector<std::size_t> at;
        for (std::size_t i = 0; i + 1 < samples.size(); i += stride) at.push_back(i);
        at.push_back(samples.size() - 1);
        bool has_prev = joined_to_previous && last_piece_;
        Vec3d prev_t = last_piece_ ? last_piece_->t : Vec3d{};
        for (std::size_t n = 1; n < at.size(); ++n) {
            const Sample& a = samples[at[n - 1]];
            const Sample& b = samples[at[n]];
            const Vec3d d = core::normalized(a.dir + b.dir);
            Vec3d along = b.tip - a.tip;
            along = along - d * core::dot(along, d);
            const double len = core::norm(along);
            if (len < 1e-9) continue;
            const Vec3d t = along / len;
            double back = 0.0;
            if (has_prev) {
                Vec3d p = prev_t - d * core::dot(prev_t, d);
                p = core::normalized(p);
                const double c = std::clamp(core::dot(p, t), -1.0, 1.0);
                if (c < 1.0 - 1e-12) {
                    const double phi = std::acos(c);
                    if (phi <= 0.5 * std::numbers::pi) {
                        back = 0.5 * w * std::tan(0.5 * phi);
                        lay_box(a.tip, p, d, 0.0, back, h);  // the previous piece's mitre
                    } else {
                        lay_joint(a.tip, d, h);
                    }
                }
            }
            lay_box(a.tip, t, d, back, len, h);
            prev_t = t;
            has_prev = true;
            last_piece_ = Piece{t};
        }
    }

    // The box from `tip - back t` to `tip + len t`, track wide across t and d, h deep below
    // the tip along d.
    void lay_box(const Vec3d& tip, const Vec3d& t, const Vec3d& d, double back, double len,
                 double h) {
        const double hw = 0.5 * process_.track_width_mm;
        const Vec3d s = core::cross(d, t);
        const double at = core::dot(t, tip), as = core::dot(s, tip), ad = core::dot(d, tip);
        detail::Slabs box;
        box.add(t, at - back, at + len);
        box.add(s, as - hw, as + hw);
        box.add(d, ad - h, ad);
        const Vec3d a = tip - t * back, b = tip + t * len;
        for (const Vec3d& e : {a, b, a - d * h, b - d * h}) {
            box.add_corner(e + s * hw);
            box.add_corner(e - s * hw);
        }
        detail::fill(grid_, origin_, voxel_, box);
    }

    void lay_joint(const Vec3d& tip, const Vec3d& d, double h) {
        const double r = 0.5 * process_.track_width_mm;
        const Vec3d u = any_perpendicular(d);
        const Vec3d v = core::cross(d, u);
        detail::Slabs prism;
        prism.add(d, core::dot(d, tip) - h, core::dot(d, tip));
        const double k = std::numbers::sqrt2 / 2.0;
        for (const Vec3d n : {u, v, (u + v) * k, (u - v) * k}) {
            prism.add(n, core::dot(n, tip) - r, core::dot(n, tip) + r);
        }
        // A circumscribed octagon reaches r / cos(22.5 deg) from the axis.
        static const std::array<std::array<double, 2>, 8> kOctagon = [] {
            std::array<std::array<double, 2>, 8> c{};
            const double rc = 1.0 / std::cos(std::numbers::pi / 8.0);
            for (int i = 0; i < 8; ++i) {
                const double ang = (i + 0.5) * std::numbers::pi / 4.0;
                c[static_cast<std::size_t>(i)] = {rc * std::cos(ang), rc * std::sin(ang)};
            }
            return c;
        }();
        for (const double top : {0.0, -h}) {
            for (const auto& [cu, cv] : kOctagon) {
                prism.add_corner(tip + d * top + u * (r * cu) + v * (r * cv));
            }
        }
        detail::fill(grid_, origin_, voxel_, prism);
    }

    void measure_volumes(Report& rep) const {
        const auto& dep = grid_.fine().words();
        const auto& mod = model_.grid.words();
        std::size_t n_model = 0, n_dep = 0, n_both = 0;
        for (std::size_t i = 0; i < dep.size(); ++i) {
            n_model += static_cast<std::size_t>(std::popcount(mod[i]));
            n_dep += static_cast<std::size_t>(std::popcount(dep[i]));
            n_both += static_cast<std::size_t>(std::popcount(mod[i] & dep[i]));
        }
        const double v3 = voxel_ * voxel_ * voxel_;
        rep.model_volume_mm3 = static_cast<double>(n_model) * v3;
        rep.deposited_volume_mm3 = static_cast<double>(n_dep) * v3;
        rep.covered_volume_mm3 = static_cast<double>(n_both) * v3;
        rep.excess_volume_mm3 = static_cast<double>(n_dep - n_both) * v3;
        rep.model_columns = model_.columns;
        rep.model_open_columns = model_.open_columns;
        rep.model_inverted_columns = model_.inverted_columns;
        rep.coverage =
            n_model > 0 ? static_cast<double>(n_both) / static_cast<double>(n_model) : 0.0;
        rep.excess =
            n_model > 0 ? static_cast<double>(n_dep - n_both) / static_cast<double>(n_model) : 0.0;
    }

    // The finished part's share inside beads and its smallest stock (decision 0026): the
    // distances are searched on the voxels, one voxel being their resolution.
    void measure_finished(Report& rep, const detail::ModelVoxels& fin) const {
        const auto& dep = grid_.fine().words();
        const auto& f = fin.grid.words();
        std::size_t n_fin = 0, n_in = 0;
        for (std::size_t i = 0; i < dep.size(); ++i) {
            n_fin += static_cast<std::size_t>(std::popcount(f[i]));
            n_in += static_cast<std::size_t>(std::popcount(f[i] & dep[i]));
        }
        const double v3 = voxel_ * voxel_ * voxel_;
        rep.finished_volume_mm3 = static_cast<double>(n_fin) * v3;
        rep.finished_inside_volume_mm3 = static_cast<double>(n_in) * v3;
        rep.finished_inside =
            n_fin > 0 ? static_cast<double>(n_in) / static_cast<double>(n_fin) : 0.0;
        rep.finished_columns = fin.columns;
        rep.finished_open_columns = fin.open_columns;
        rep.finished_inverted_columns = fin.inverted_columns;
        const int want =
            std::max(kStockSearchVoxels, static_cast<int>(std::ceil(kStockSearchMm / voxel_)) + 1);
        const int limit = detail::stock_limit_within(want, nx_, ny_, kStockSearchBytes);
        const double limit_mm = (limit - 1) * voxel_;
        rep.stock_limit_mm = limit_mm;
        const detail::StockDistance s = detail::smallest_stock(grid_.fine(), fin.grid, limit);
        if (s.empty) return;
        // Inside: centre to centre, less the half voxel each surface lies beyond its last
        // centre on average. Sticking out: the finished voxel's centre to the nearest bead
        // voxel's centre (the two half voxels cancel).
        rep.smallest_stock_mm = s.inside ? std::min((s.distance - 1.0) * voxel_, limit_mm)
                                         : -std::min(s.distance * voxel_, limit_mm);
        rep.smallest_stock_at_mm =
            origin_ + Vec3d{(s.i + 0.5) * voxel_, (s.j + 0.5) * voxel_, (s.k + 0.5) * voxel_};
    }

    const machine::Profiles& profiles_;
    const machine::ProcessProfile& process_;
    const machine::MachineKinematics& kin_;
    const VerifySettings& settings_;
    machine::NozzleProfile nozzle_;
    machine::SpeedLaw law_;  // deposit feed -> bead height (docs/program-dialects.md)
    Vec3d origin_{};
    double voxel_ = 1.0;
    double sample_ = 1.0;
    int nx_ = 0, ny_ = 0, nz_ = 0;
    OccupancyPyramid grid_;
    detail::ModelVoxels model_;
    detail::ModelVoxels finished_;  // the finished part, when given
    Region nozzle_region_;
    Region hardware_region_;  // the nozzle above its tip and the body
    double clearance_ = 0.0;  // the gap the hardware keeps (mm; 0: contact only)
    // The head's side as (axis distance, radius) segments: the cone, then the body.
    struct OutlinePoint {
        double t = 0.0;
        double r = 0.0;
    };
    std::vector<std::pair<OutlinePoint, OutlinePoint>> head_outline_;
    double head_reach_ = 0.0;  // the farthest point of the outline from the tip (mm)
    struct Box {
        Vec3d lo, hi;
    };
    std::optional<Box> substrate_;  // the substrate plate (part frame), when modelled
    int below_plate_line_ = -1;     // the block last counted in Report::below_plate
    std::size_t poses_checked_ = 0;
    double unsupported_length_ = 0.0;
    bool limit_block_counted_ = false;
    struct Piece {
        Vec3d t;
    };
    std::optional<Piece> last_piece_;  // direction of the last bead piece laid
    struct OpenEnd {
        Vec3d tip;
        Vec3d dir;
        double h = 0.0;
    };
    std::optional<OpenEnd> open_end_;  // the end of the wire being laid
    std::vector<Sample> samples_;      // the poses of the block being checked (reused)
    /// What one pose of a block meets: contact with material or the plate, or (without
    /// contact) material or the plate within the clearance; where. Support: `contact`.
    struct PoseFinding {
        bool contact = false, contact_plate = false, near = false, near_plate = false;
        Vec3d hit, near_hit;
    };
    std::vector<PoseFinding> pose_findings_;  // per pose of the block being checked (reused)
    /// fn(i) for every pose i of a block, side by side when there are enough to pay for it.
    template <class Fn>
    static void for_each_sample(std::size_t n, const Fn& fn) {
        if (n < kSideBySidePoses) {
            for (std::size_t i = 0; i < n; ++i) fn(i);
            return;
        }
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kSideBySidePoses / 2),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t i = r.begin(); i != r.end(); ++i) fn(i);
                          });
    }
};

}  // namespace

std::vector<std::string_view> failed_checks(const Report& r) {
    std::vector<std::string_view> out;
    const std::pair<const Finding*, std::string_view> findings[] = {
        {&r.collisions, "contact"},
        {&r.clearance, "clearance"},
        {&r.unsupported, "unsupported"},
        {&r.limit_violations, "limit_violations"},
        {&r.out_of_range, "out_of_range"},
        {&r.unfinished, "unfinished"},
        {&r.left_on, "left_on"}};
    for (const auto& [f, name] : findings) {
        if (f->count > 0) out.push_back(name);
    }
    if (r.deposits_nothing()) out.push_back("nothing_deposited");
    if (r.coverage_low()) out.push_back("coverage");
    if (r.excess_high()) out.push_back("excess");
    if (r.finished_given && r.finished_low()) out.push_back("finished_inside");
    return out;
}

core::Result<mesh::TriangleMesh> place_model(mesh::TriangleMesh model,
                                             const core::Vec3d& base_direction,
                                             const machine::MachineProfile& machine) {
    if (model.empty()) return core::fail(ErrorCode::kInvalidInput, "the model has no triangles");
    if (!core::is_finite(base_direction) || core::norm(base_direction) == 0.0) {
        return core::fail(ErrorCode::kInvalidInput,
                          "the base direction must be a finite non-zero vector", "--direction");
    }
    return mesh::placed_on_plate(std::move(model), base_direction, machine::plate_center(machine));
}

core::Result<mesh::TriangleMesh> place_like(mesh::TriangleMesh other,
                                            const mesh::TriangleMesh& model,
                                            const core::Vec3d& base_direction,
                                            const machine::MachineProfile& machine) {
    if (other.empty()) {
        return core::fail(ErrorCode::kInvalidInput, "the finished part has no triangles");
    }
    auto placed = place_model(model, base_direction, machine);
    if (!placed) return std::unexpected(placed.error());
    // Both together take one rotation and a shift; the model's own vertices then tell the
    // shift that separates that placement from the model's.
    const std::size_t first = other.vertices.size();
    const std::size_t triangles = other.triangles.size();
    mesh::append(other, model);
    other = mesh::placed_on_plate(std::move(other), base_direction, machine::plate_center(machine));
    const Vec3d shift = placed->vertices.front() - other.vertices[first];
    other.vertices.resize(first);
    other.triangles.resize(triangles);
    for (Vec3d& v : other.vertices) v = v + shift;
    return other;
}

core::Result<Report> verify_program(std::string_view program_text,
                                    const mesh::TriangleMesh& placed_model,
                                    const machine::Profiles& profiles,
                                    const VerifySettings& settings,
                                    const mesh::TriangleMesh* placed_finished) {
    if (auto ok = machine::validate(profiles.machine); !ok) return std::unexpected(ok.error());
    if (auto ok = machine::validate(profiles.process); !ok) return std::unexpected(ok.error());
    const double clearance = settings.clearance_mm.value_or(0.0);
    if (!(settings.voxel_mm >= 0.0) || !(settings.sample_mm >= 0.0) || !(clearance >= 0.0) ||
        !(settings.max_voxels >= 1.0) || !std::isfinite(settings.voxel_mm) ||
        !std::isfinite(settings.sample_mm) || !std::isfinite(clearance)) {
        return core::fail(ErrorCode::kInvalidInput,
                          "verify settings: voxel, sample, clearance must be finite and >= 0",
                          "verify settings");
    }
    if (!(settings.min_coverage >= 0.0 && settings.min_coverage <= 1.0) ||
        !(settings.max_excess >= 0.0) || !std::isfinite(settings.max_excess)) {
        return core::fail(ErrorCode::kInvalidInput,
                          fmt::format("verify settings: the coverage to reach ({}) must lie in "
                                      "[0, 1] and the excess bound ({}) be finite and >= 0",
                                      settings.min_coverage, settings.max_excess),
                          "verify settings");
    }
    ProgramDialect dialect = ProgramDialect::kGm;
    if (settings.dialect) {
        dialect = *settings.dialect;
    } else {
        auto d = dialect_of(profiles.machine);
        if (!d) return std::unexpected(d.error());
        dialect = *d;
    }
    auto kin = machine::MachineKinematics::create(profiles.machine);
    if (!kin) return std::unexpected(kin.error());
    auto replay = replay_program(program_text, profiles, dialect);
    if (!replay) return std::unexpected(replay.error());
    const machine::NozzleProfile nozzle =
        profiles.machine.nozzle.value_or(machine::NozzleProfile{});
    Verifier v(profiles, *kin, settings, nozzle);
    auto report = v.run(*replay, placed_model, placed_finished);
    if (report) {
        report->default_nozzle = !profiles.machine.nozzle.has_value();
        report->substrate = profiles.machine.substrate.has_value();
    }
    return report;
}

}  // namespace maxslice::verify
